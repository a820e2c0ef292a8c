// brdfbake sample | info | convert: look up, inspect and resample every output of bake and prefilter.
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/maps/image_io.hpp>
#include <brdfbake/maps/map_file.hpp>
#include <brdfbake/output/baked_output.hpp>

#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>

#include "commands.hpp"
#include "terminal.hpp"

namespace brdfbake::cli {
namespace fs = std::filesystem;

namespace {

const std::map<std::string, ParameterizationKind> kKinds{{"sphere", ParameterizationKind::Sphere},
                                                         {"paraboloid", ParameterizationKind::Paraboloid},
                                                         {"cube", ParameterizationKind::Cube},
                                                         {"latlong", ParameterizationKind::LatLong}};

// One direction of a --dirs file, with the line it came from.
struct DirectionLine {
  Vec3 direction;
  int line = 0;
};

// "x y z" per line; '#' starts a comment; blank lines are skipped. Errors name FILE:LINE.
std::vector<DirectionLine> readDirectionsFile(const std::string& file) {
  std::istringstream in(readTextFile(file, "--dirs file"));
  std::vector<DirectionLine> directions;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    const std::string where = file + ":" + std::to_string(line);
    const std::string content = text.substr(0, text.find('#'));
    std::istringstream fields(content);
    std::vector<std::string> words;
    for (std::string word; fields >> word;) words.push_back(word);
    if (words.empty()) continue;
    if (words.size() != 3) {
      throw Error(Error::Kind::InvalidInput,
                  where + ": expected three numbers \"x y z\", got '" + shortenForMessage(content, 80) + "'");
    }
    Vec3 d;
    for (int i = 0; i < 3; ++i) {
      std::size_t used = 0;
      try {
        d[i] = std::stod(words[static_cast<std::size_t>(i)], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != words[static_cast<std::size_t>(i)].size() || !std::isfinite(d[i])) {
        throw Error(
            Error::Kind::InvalidInput,
            where + ": '" + shortenForMessage(words[static_cast<std::size_t>(i)], 40) + "' is not a finite number");
      }
    }
    if (!(d.norm() > 0.0)) throw Error(Error::Kind::InvalidInput, where + ": the direction must be non-zero");
    directions.push_back({d, line});
  }
  if (directions.empty()) throw Error(Error::Kind::InvalidInput, file + ": no directions (one \"x y z\" per line)");
  return directions;
}

nlohmann::json valueJson(const Rgba& v) { return {v[0], v[1], v[2], v[3]}; }

}  // namespace

Command addSampleCommand(CLI::App& app) {
  struct Args {
    std::string map, dir, dirs, from;
    std::optional<double> cosView;
    int mipLevel = 0;
    bool json = false, quiet = false;
  };
  auto args = std::make_shared<Args>();
  auto* command = app.add_subcommand(
      "sample", "Look up any output of bake or prefilter as a renderer does (bilinear, as a GPU filters)");
  command->footer(R"(MAP is any output of bake or prefilter: a map (sphere, paraboloid, cube, lat-long; a mip level
STEM_mipK.EXT, or --mip-level K of a tiled MIP-mapped file or of STEM.EXT), a cube written as six faces
(pass STEM.EXT or any face), a 1-D radial profile, an elevation stack STEM_elev0.EXT ... (pass STEM.EXT,
and --cos-view), a 1-D Fresnel table (--cos-view only, no direction), or an SH irradiance JSON.

The direction is the one the map is indexed by, in the map's frame: the reflected direction r (eye
space for sphere maps and profiles: +z towards the viewer, y up), or the normal n for irradiance
(irradiance maps other than sphere maps, SH). --cos-view is n.v: an elevation stack is interpolated
between its slices at t = clamp(ln(n.v / min_cos) / ln(max_cos / min_cos), 0, 1), a Fresnel table
is read at cos theta = n.v. Kinds that do not use n.v refuse it.

Prints R G B A (alpha: the map's coverage, 1 for profiles and SH), one line per direction. With
--dirs FILE, FILE holds one direction "x y z" per line ('#' starts a comment, blank lines are
skipped), and errors name FILE:LINE. --json prints {"direction": [x, y, z], "value": [r, g, b, a]}
(and "cos_view" when given) for one direction, an array of them (each with its "line") for --dirs.

Examples:
  brdfbake sample out/phong_eye.exr --dir 0.2,0.3,1
  brdfbake sample out/phong_eye_profile.exr --dirs directions.txt --json
  brdfbake sample out/sky_varying.exr --dir 0,0.5,1 --cos-view 0.7
  brdfbake sample out/sky_coat_fresnel.exr --cos-view 0.3)");
  command->add_option("map", args->map, "Output of bake or prefilter (or a plain image with --from)")->required();
  auto* dirOption = command->add_option("--dir", args->dir, "Direction X,Y,Z (need not be unit length)");
  command
      ->add_option("--dirs", args->dirs, "File of directions, one \"x y z\" per line (# comments, blank lines allowed)")
      ->excludes(dirOption);
  addCosViewOption(command, args->cosView);
  addMipLevelOption(command, args->mipLevel);
  command->add_option("--from", args->from, "Treat a plain image as this parameterization")
      ->check(CLI::IsMember(kKinds));
  addJsonFlag(command, args->json, "the direction and the value (an array of them with --dirs)");
  addQuietFlag(command, args->quiet);
  return [args] {
    // Directions first (flags before files), then the output.
    std::vector<DirectionLine> directions;
    if (!args->dir.empty()) {
      const Vec3 direction = parseVector(args->dir, "--dir");
      if (!(direction.norm() > 0.0)) throw Error(Error::Kind::InvalidArgument, "--dir: direction must be non-zero");
      directions.push_back({direction, 0});
    }
    const BakedOutput output = openOutput(args->map, args->from, args->mipLevel);
    checkCosView(output, args->cosView);
    if (!args->dirs.empty()) directions = readDirectionsFile(args->dirs);
    if (!output.usesDirection() && !directions.empty()) {
      throw Error(Error::Kind::InvalidArgument,
                  std::string(args->dirs.empty() ? "--dir" : "--dirs") +
                      ": a Fresnel table is a function of n.v alone: give --cos-view only");
    }
    if (output.usesDirection() && directions.empty()) {
      throw Error(Error::Kind::InvalidArgument,
                  "--dir or --dirs: a " + std::string(toString(output.kind())) + " is looked up at a direction");
    }
    if (directions.empty()) directions.push_back({Vec3::UnitZ(), 0});  // a Fresnel table: n.v alone
    nlohmann::json array = nlohmann::json::array();
    std::ostringstream text;
    for (const auto& [direction, line] : directions) {
      const Rgba value = output.lookup(direction, args->cosView);
      if (!args->json) {
        text << value[0] << " " << value[1] << " " << value[2] << " " << value[3] << "\n";
        continue;
      }
      nlohmann::json entry = {{"value", valueJson(value)}};
      if (output.usesDirection()) entry["direction"] = {direction.x(), direction.y(), direction.z()};
      if (args->cosView) entry["cos_view"] = *args->cosView;
      if (line > 0) entry["line"] = line;
      array.push_back(entry);
    }
    if (!args->json) {
      std::cout << text.str();
    } else {
      std::cout << (args->dirs.empty() ? array[0] : array).dump() << "\n";
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
  auto* command = app.add_subcommand(
      "info", "Say what an output is: its kind, files, size, how to look it up, the spec it was made from");
  command->footer(
      "Reads every output of bake and prefilter (see brdfbake sample --help): a cube's six faces and an\n"
      "elevation stack are named by STEM.EXT. A plain image is reported as one.");
  command->add_option("map", args->map, "Output, map or image file")->required();
  addJsonFlag(command, args->json, "the kind, files, size, lookup rule and metadata");
  addQuietFlag(command, args->quiet);
  return [args] {
    std::error_code ec;
    const bool plainFile = fs::is_regular_file(args->map, ec) && fs::path(args->map).extension() != ".json";
    std::optional<Image> plain;
    if (plainFile) {
      Image image = readImage(args->map);
      if (image.metadata.empty()) plain = std::move(image);
    }
    nlohmann::json info = {{"file", args->map}, {"channels", "RGBA"}, {"brdfbake", !plain}};
    std::optional<BakedOutput> output;
    if (plain) {
      info["kind"] = "plain image";
      info["width"] = plain->width();
      info["height"] = plain->height();
    } else {
      output = openOutput(args->map, "", 0);
      info.update(output->describe());
      const nlohmann::json& metadata = output->metadata();
      switch (output->kind()) {
        case OutputKind::RadialProfile:
        case OutputKind::FresnelTable:
          info["parameterization"] = metadata.value("parameterization", "");
          info["width"] = info["resolution"];
          info["height"] = 1;
          break;
        case OutputKind::ShIrradiance:
          info["parameterization"] = "sh";
          info.erase("channels");
          break;
        default:
          break;
      }
      info["convention_version"] = metadata.value("convention_version", 0);
    }
    if (args->json) {
      std::cout << info.dump(2) << "\n";
      return 0;
    }
    if (plain) {
      std::cout << args->map << ": " << plain->width() << " x " << plain->height() << " RGBA\n";
      std::cout << "  no brdfbake metadata (a plain image)\n";
      return 0;
    }
    std::cout << args->map << ": " << info["kind"].get<std::string>();
    if (info.contains("width")) std::cout << ", " << info["width"] << " x " << info["height"] << " RGBA";
    std::cout << "\n";
    if (info.contains("parameterization")) {
      std::cout << "  parameterization: " << info["parameterization"].get<std::string>();
      if (info.contains("resolution")) std::cout << ", resolution " << info["resolution"];
      if (output->kind() != OutputKind::ShIrradiance)
        std::cout << " (convention v" << info["convention_version"] << ")";
      std::cout << "\n";
    }
    if (info.contains("axis")) std::cout << "  axis: " << info["axis"].dump() << "\n";
    if (info.contains("slices")) {
      std::cout << "  " << info["slices"] << " slices over n.v from " << info["min_cos"] << " to " << info["max_cos"]
                << "\n";
    }
    if (output->files().size() > 1) {
      std::cout << "  files: " << output->files().front().string() << " ... " << output->files().back().string() << " ("
                << output->files().size() << ")\n";
    }
    std::cout << "  lookup: " << info["lookup"].get<std::string>() << "\n";
    if (output->kind() == OutputKind::ShIrradiance) {
      std::cout << "  coefficients: " << output->metadata()["coefficients"].dump() << "\n";
    } else {
      std::cout << "  spec: " << output->metadata().value("spec", nlohmann::json::object()).dump() << "\n";
    }
    return 0;
  };
}

Command addConvertCommand(CLI::App& app) {
  struct Args {
    std::string map, to, from, output;
    std::optional<double> cosView;
    int resolution = 0, samples = 16, threads = 0, mipLevel = 0;
    bool json = false, quiet = false, faces = false;
  };
  auto args = std::make_shared<Args>();
  auto* command = app.add_subcommand("convert", "Resample a map into another parameterization");
  command->footer(
      "Each output texel averages lookups of the input over its footprint, the lookups a renderer\n"
      "makes (brdfbake sample --help): any output of bake or prefilter converts. An elevation stack\n"
      "needs --cos-view (the map at that n.v); a Fresnel table converts --to sphere only, as\n"
      "seen from +z (the texel at r holds F(n.v), n = normalize(r + z)). Plain environment images\n"
      "(no brdfbake metadata) need --from.");
  command->add_option("map", args->map, "Input map or image")->required();
  command->add_option("--to", args->to, "Output parameterization")->required()->check(CLI::IsMember(kKinds));
  command->add_option("--from", args->from, "Parameterization of a plain input image")->check(CLI::IsMember(kKinds));
  command->add_option("--resolution", args->resolution, "Output resolution (default: the input's)")
      ->check(CLI::Range(1, 65536));
  command->add_option("--samples", args->samples, "Samples per output texel")
      ->default_val(16)
      ->check(CLI::Range(1, 4096));
  addCosViewOption(command, args->cosView);
  addMipLevelOption(command, args->mipLevel);
  addThreadsOption(command, args->threads);
  command->add_flag("--faces", args->faces, "Write a cube map as six files instead of a cross");
  command->add_option("-o,--output", args->output, "Output file (.exr, .hdr, .tif, .png)")->required();
  addJsonFlag(command, args->json, "files, seconds, notes");
  addQuietFlag(command, args->quiet);
  return [args] {
    const BakedOutput source = openOutput(args->map, args->from, args->mipLevel);
    checkCosView(source, args->cosView, false);
    const ParameterizationKind kind = parseParameterizationKind(args->to);
    if (source.kind() == OutputKind::FresnelTable && kind != ParameterizationKind::Sphere) {
      throw Error(Error::Kind::InvalidArgument,
                  "--to: a Fresnel table is a function of n.v; only a sphere map (eye space, view "
                  "+z) holds it as a function of direction");
    }
    const nlohmann::json described = source.describe();
    const int resolution = args->resolution > 0 ? args->resolution : described.value("resolution", 0);
    if (resolution < 1) throw Error(Error::Kind::InvalidArgument, "--resolution: the input has none to keep; give one");
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
    const BakedMap baked = bakeMap(*target, BakedOutputFunction(source, args->cosView), options);
    const Image& image = baked.image;
    const BakeSummary& summary = baked.summary;
    MapInfo info;
    info.parameterization = kind;
    info.resolution = resolution;
    info.conventionVersion = kConventionVersion;
    info.spec = source.metadata().value("spec", nlohmann::json::object());
    info.spec["converted_from"] = {
        {"file", args->map},
        {"kind", described["kind"]},
        {"parameterization", described.value("parameterization", described["kind"].get<std::string>())},
        {"resolution", described.value("resolution", 0)}};
    if (args->cosView) info.spec["converted_from"]["cos_view"] = *args->cosView;
    if (args->mipLevel > 0) info.spec["converted_from"]["mip_level"] = args->mipLevel;
    const auto written = writeMap(image, info, args->output, args->faces ? CubeLayout::Faces : CubeLayout::Cross,
                                  {{fs::path(args->map)}});
    bar.done();
    if (args->json) {
      nlohmann::json files = nlohmann::json::array();
      for (const auto& f : written.files) files.push_back(f.string());
      std::cout << nlohmann::json{{"files", files}, {"seconds", summary.seconds}, {"notes", written.notes}}.dump(2)
                << "\n";
    } else if (!args->quiet) {
      for (const auto& f : written.files) std::cout << "wrote " << f.string() << "\n";
      for (const auto& note : written.notes) std::cout << "  note: " << note << "\n";
    }
    return 0;
  };
}

}  // namespace brdfbake::cli
