// brdfbake sample | info | convert: inspect and resample maps.
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/bake/map_file.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/version.hpp>

#include <iostream>

#include "commands.hpp"
#include "terminal.hpp"

namespace brdfbake::cli {
namespace fs = std::filesystem;

namespace {

const std::map<std::string, ParameterizationKind> kKinds{{"sphere", ParameterizationKind::Sphere},
                                                         {"paraboloid", ParameterizationKind::Paraboloid},
                                                         {"cube", ParameterizationKind::Cube},
                                                         {"latlong", ParameterizationKind::LatLong}};

}  // namespace

Command addSampleCommand(CLI::App& app) {
  struct Args {
    std::string map, dir, from;
    bool json = false, quiet = false;
  };
  auto args = std::make_shared<Args>();
  auto* command = app.add_subcommand("sample", "Look up a map at a direction (bilinear, as a GPU filters)");
  command->footer("The direction is in the map's frame: eye space for sphere maps (+z towards the viewer,\n"
                  "y up). Prints R G B A, or {\"value\": [r, g, b, a]} with --json.");
  command->add_option("map", args->map, "Map written by brdfbake")->required();
  command->add_option("--dir", args->dir, "Direction X,Y,Z (need not be unit length)")->required();
  command->add_option("--from", args->from, "Treat a plain image as this parameterization")->check(CLI::IsMember(kKinds));
  addJsonFlag(command, args->json, "the direction and the value");
  addQuietFlag(command, args->quiet);
  return [args] {
    const Vec3 direction = parseVector(args->dir, "--dir");
    if (!(direction.norm() > 0.0)) throw Error(Error::Kind::InvalidArgument, "--dir: direction must be non-zero");
    const MapFile file = openMapOrImage(args->map, args->from);
    const Rgba value = sampleBilinear(file.image, *file.parameterization, direction);
    if (args->json) {
      std::cout << nlohmann::json{{"value", {value[0], value[1], value[2], value[3]}}}.dump() << "\n";
    } else {
      std::cout << value[0] << " " << value[1] << " " << value[2] << " " << value[3] << "\n";
    }
    return 0;
  };
}

Command addInfoCommand(CLI::App& app) {
  struct Args {
    std::string map;
    bool json = false, quiet = false;
  };
  auto args = std::make_shared<Args>();
  auto* command = app.add_subcommand("info", "Say what a map is: parameterization, size, channels, the spec it was baked from");
  command->add_option("map", args->map, "Map or image file")->required();
  addJsonFlag(command, args->json, "the map's metadata and size");
  addQuietFlag(command, args->quiet);
  return [args] {
    const Image image = readImage(args->map);
    nlohmann::json info = {{"file", args->map}, {"width", image.width()}, {"height", image.height()},
                           {"channels", "RGBA"}, {"brdfbake", !image.metadata.empty()}};
    const bool profile = image.metadata.value("parameterization", "") == "profile";
    if (profile) {
      info["parameterization"] = "profile";
      info["resolution"] = image.metadata.value("resolution", 0);
      info["convention_version"] = image.metadata.value("convention_version", 0);
      info["metadata"] = image.metadata;
    } else if (!image.metadata.empty()) {
      const MapInfo map = MapInfo::fromJson(image.metadata);
      info["parameterization"] = std::string(toString(map.parameterization));
      info["resolution"] = map.resolution;
      info["convention_version"] = map.conventionVersion;
      info["metadata"] = image.metadata;
    }
    if (args->json) {
      std::cout << info.dump(2) << "\n";
      return 0;
    }
    std::cout << args->map << ": " << image.width() << " x " << image.height() << " RGBA\n";
    if (image.metadata.empty()) {
      std::cout << "  no brdfbake metadata (a plain image)\n";
      return 0;
    }
    std::cout << "  parameterization: " << info["parameterization"].get<std::string>() << ", resolution "
              << info["resolution"] << " (convention v" << info["convention_version"] << ")\n";
    if (profile) {
      std::cout << "  1-D radial profile about " << image.metadata.value("axis", nlohmann::json::array()).dump() << ": "
                << image.metadata.value("coordinate", "") << "\n";
    }
    if (image.metadata.contains("face")) std::cout << "  cube face " << image.metadata["face"].get<std::string>() << "\n";
    std::cout << "  spec: " << image.metadata.value("spec", nlohmann::json::object()).dump() << "\n";
    return 0;
  };
}

Command addConvertCommand(CLI::App& app) {
  struct Args {
    std::string map, to, from, output;
    int resolution = 0, samples = 16, threads = 0;
    bool json = false, quiet = false, faces = false;
  };
  auto args = std::make_shared<Args>();
  auto* command = app.add_subcommand("convert", "Resample a map into another parameterization");
  command->footer("Each output texel averages bilinear lookups of the input over its footprint. Plain\n"
                  "environment images (no brdfbake metadata) need --from.");
  command->add_option("map", args->map, "Input map or image")->required();
  command->add_option("--to", args->to, "Output parameterization")->required()->check(CLI::IsMember(kKinds));
  command->add_option("--from", args->from, "Parameterization of a plain input image")->check(CLI::IsMember(kKinds));
  command->add_option("--resolution", args->resolution, "Output resolution (default: the input's)")->check(CLI::Range(1, 65536));
  command->add_option("--samples", args->samples, "Samples per output texel")->default_val(16)->check(CLI::Range(1, 4096));
  addThreadsOption(command, args->threads);
  command->add_flag("--faces", args->faces, "Write a cube map as six files instead of a cross");
  command->add_option("-o,--output", args->output, "Output file (.exr, .hdr, .tif, .png)")->required();
  addJsonFlag(command, args->json, "files, seconds, notes");
  addQuietFlag(command, args->quiet);
  return [args] {
    const MapFile source = openMapOrImage(args->map, args->from);
    const ParameterizationKind kind = parseParameterizationKind(args->to);
    const int resolution = args->resolution > 0 ? args->resolution : source.info.resolution;
    const auto target = makeParameterization(kind, resolution);
    imageFormatFor(args->output);  // fail on a bad extension before the work
    FilePlan plan;
    plan.addInput(args->map, "map");
    for (const auto& f : mapOutputFiles(args->output, "-o", kind == ParameterizationKind::Cube,
                                        args->faces ? CubeLayout::Faces : CubeLayout::Cross)) {
      plan.addOutput(f.file, f.role);
    }
    plan.check();
    ProgressBar bar("convert", !args->json && !args->quiet);
    BakeOptions options;
    options.samplesPerTexel = args->samples;
    options.threads = args->threads;
    options.progress = bar.callback();
    BakeSummary summary;
    const Image image = bake(*target, ImageMapFunction(source.image, *source.parameterization), options, &summary);
    MapInfo info;
    info.parameterization = kind;
    info.resolution = resolution;
    info.conventionVersion = kConventionVersion;
    info.spec = source.info.spec;
    info.spec["converted_from"] = {{"file", args->map}, {"parameterization", std::string(toString(source.info.parameterization))},
                                   {"resolution", source.info.resolution}};
    const auto written = writeMap(image, info, args->output, args->faces ? CubeLayout::Faces : CubeLayout::Cross, {{fs::path(args->map)}});
    bar.done();
    if (args->json) {
      nlohmann::json files = nlohmann::json::array();
      for (const auto& f : written.files) files.push_back(f.string());
      std::cout << nlohmann::json{{"files", files}, {"seconds", summary.seconds}, {"notes", written.notes}}.dump(2) << "\n";
    } else if (!args->quiet) {
      for (const auto& f : written.files) std::cout << "wrote " << f.string() << "\n";
      for (const auto& note : written.notes) std::cout << "  note: " << note << "\n";
    }
    return 0;
  };
}

}  // namespace brdfbake::cli
