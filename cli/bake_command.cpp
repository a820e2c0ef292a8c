// brdfbake bake SPEC.json: bake every map of a spec.
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/bake/radial_profile.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>
#include <brdfbake/core/memory_budget.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/env/prefilter_stack.hpp>
#include <brdfbake/maps/map_file.hpp>
#include <brdfbake/spec/spec.hpp>

#include <chrono>
#include <iostream>

#include "commands.hpp"
#include "terminal.hpp"

namespace brdfbake::cli {
namespace fs = std::filesystem;

namespace {

struct BakeArgs {
  std::string spec;
  std::string outputDirectory;
  std::string misplacedOutput;  // -o, refused with a pointer to --out-dir
  int threads = 0;
  bool quiet = false;
  bool json = false;
  bool allowLarge = false;
};

// The report entry every map shares (`bake --json`): what was written, its size, how long it took.
struct EntryFacts {
  std::string parameterization;
  int resolution = 0, width = 0, height = 0;
  std::string bakePath;
  double bakeSeconds = 0.0, writeSeconds = 0.0;
};
nlohmann::json reportEntry(const MapSpec& map, const EntryFacts& facts, const std::vector<fs::path>& files,
                           const std::vector<std::string>& notes) {
  nlohmann::json entry = {{"output", map.output.string()},
                          {"files", nlohmann::json::array()},
                          {"parameterization", facts.parameterization},
                          {"resolution", facts.resolution},
                          {"width", facts.width},
                          {"height", facts.height},
                          {"bake_path", facts.bakePath},
                          {"bake_seconds", facts.bakeSeconds},
                          {"write_seconds", facts.writeSeconds},
                          {"notes", notes}};
  for (const auto& file : files) entry["files"].push_back(file.string());
  return entry;
}

// A map with "environment" (docs/prefilter.md): prefilter instead of bake; returns its report entry.
nlohmann::json bakeEnvironmentMap(const MapSpec& map, const EnvironmentMapSpec& e, const Environment& environment,
                                  const BakeArgs& args) {
  PrefilterOptions options = map.prefilterOptions();
  options.threads = args.threads;
  options.allowLarge = args.allowLarge;
  ProgressBar bar(map.jsonPath + " " + map.output.filename().string(), !args.quiet && !args.json);
  options.progress = bar.callback();
  const WriteOptions writeOptions{{fs::path(args.spec), e.file}};
  // One map, a stack over elevation (varying lobe models) or a Fresnel decomposition (three files).
  PrefilterSummary summary;
  std::shared_ptr<const Parameterization> parameterization;
  MapWriteReport written;
  nlohmann::json extra = nlohmann::json::object();
  std::string irradianceReport;  // the Fresnel decomposition's second map
  auto writeStart = std::chrono::steady_clock::now();
  if (e.lobeModel() && e.lobeModel()->elevation == LobeElevation::Varying) {
    const PrefilteredStack stack = prefilterLobeModelStack(environment, *e.lobeModel(), e.lobeName, options);
    summary = stack.summary;
    parameterization = stack.slices.front().map;
    writeStart = std::chrono::steady_clock::now();
    written = writePrefilteredStack(stack, map.output, map.raw, map.cubeLayout, writeOptions, e.mipLayout);
    extra["elevations"] = {{"slices", stack.slices.size()}, {"cos_theta", stack.cosines}, {"t", stack.coordinates}};
  } else if (e.fresnel) {
    const FresnelDecomposition decomposition =
        prefilterFresnelDecomposition(environment, *e.analyticLobe(), *e.fresnel, e.combine, options, map.resolution);
    summary = decomposition.specular.summary;
    parameterization = decomposition.specular.map;
    writeStart = std::chrono::steady_clock::now();
    written = writeFresnelDecomposition(decomposition, map.output, map.raw, map.cubeLayout, writeOptions, e.mipLayout);
    irradianceReport = decomposition.irradiance.summary.briefReport();
    extra["fresnel"] = {{"combine", std::string(toString(e.combine))},
                        {"irradiance", fresnelIrradiancePath(map.output).string()},
                        {"table", fresnelTablePath(map.output).string()},
                        {"irradiance_prefilter", decomposition.irradiance.summary.toJson()}};
  } else {
    const PrefilteredMap result = e.lobeModel() ? prefilterLobeModel(environment, *e.lobeModel(), e.lobeName, options)
                                                : prefilter(environment, *e.analyticLobe(), options);
    summary = result.summary;
    parameterization = result.map;
    writeStart = std::chrono::steady_clock::now();
    written = writePrefilteredMap(result, map.output, map.raw, map.cubeLayout, writeOptions, e.mipLayout);
  }
  const double writeSeconds = secondsSince(writeStart);
  bar.done();
  nlohmann::json entry = reportEntry(
      map,
      {std::string(toString(map.parameterization)), map.resolution, parameterization->width(),
       parameterization->height(), "prefilter:" + std::string(toString(summary.method)), summary.seconds, writeSeconds},
      written.files, written.notes);
  entry["prefilter"] = summary.toJson();
  entry.update(extra);
  if (!args.json && !args.quiet) {
    const std::string what =
        extra.contains("elevations") ? elevationSlicePath(map.output, 0).string() + " ..." : map.output.string();
    std::cout << "wrote " << what << " (" << toString(map.parameterization) << " " << parameterization->width() << "x"
              << parameterization->height() << "): " << summary.briefReport() << "; write " << writeSeconds << " s\n";
    if (written.files.size() > 1) std::cout << "  " << written.files.size() << " files in all\n";
    if (!irradianceReport.empty()) std::cout << "  irradiance map: " << irradianceReport << "\n";
    for (const auto& note : summary.notes) std::cout << "  note: " << note << "\n";
    for (const auto& note : written.notes) std::cout << "  note: " << note << "\n";
  }
  return entry;
}

void printAutoChoice(const nlohmann::json& autoReport, double maxError) {
  if (autoReport.is_null()) return;
  std::cout << "  auto: chose " << autoReport["chosen"].get<std::string>() << ", measured error "
            << autoReport["measured_error"].get<double>() << " <= " << maxError << " ("
            << autoReport["configurations_estimated"].get<int>() << " configurations estimated, "
            << autoReport["bakes"].get<int>() << " baked)\n";
}

// A 1-D radial profile ("parameterization": "profile", or chosen by "auto"): written as an N x 1
// image whose metadata says how to look it up (bake/radial_profile.hpp).
nlohmann::json writeProfile(const RadialProfile& profile, const MapSpec& map, const BakeSummary& summary,
                            const nlohmann::json& autoReport, const BakeArgs& args) {
  Image image = profile.toImage();
  image.metadata["convention_version"] = kConventionVersion;
  image.metadata["spec"] = map.raw;
  if (!autoReport.is_null()) image.metadata["spec"]["auto"] = autoReport;
  const auto writeStart = std::chrono::steady_clock::now();
  const WriteReport written = writeImage(image, map.output, {{fs::path(args.spec)}});
  const double writeSeconds = secondsSince(writeStart);
  const Vec3& axis = profile.axis();
  nlohmann::json entry = reportEntry(
      map, {"profile", profile.resolution(), profile.resolution(), 1, summary.path, summary.seconds, writeSeconds},
      {map.output}, written.notes);
  entry["axis"] = {axis.x(), axis.y(), axis.z()};
  entry["samples_per_texel"] = map.samplesPerTexel;
  if (!autoReport.is_null()) entry["auto"] = autoReport;
  if (!args.json && !args.quiet) {
    std::cout << "wrote " << map.output.string() << " (1-D radial profile, " << profile.resolution()
              << " texels about (" << axis.x() << ", " << axis.y() << ", " << axis.z() << "), " << summary.path
              << "): bake " << summary.seconds << " s, write " << writeSeconds << " s\n";
    std::cout << "  lookup: u = |r - axis| / 2, texel i at u = (i + 0.5) / " << profile.resolution()
              << " (about the view: u = the sphere-map radius)\n";
    printAutoChoice(autoReport, map.autoSelect.maxError);
    for (const auto& note : written.notes) std::cout << "  note: " << note << "\n";
  }
  return entry;
}

// A map baked from a material (and lights); returns its report entry.
nlohmann::json bakeMaterialMap(const MapSpec& specified, BakeOptions options, const BakeArgs& args) {
  MapSpec map = specified;
  if (const auto& fit =
          map.materialMap()->deferredFit) {  // a measured material's fit runs now, not while the spec was parsed
    ProgressBar fitting(
        map.jsonPath + " fitting lobes to " + std::filesystem::path(fit->table.sourceFile).filename().string(),
        !args.quiet && !args.json);
    map.prepare(fitting.callback());
  }
  const auto function = map.makeFunction();
  ProgressBar bar(map.jsonPath + " " + map.output.filename().string(), !args.quiet && !args.json);
  options.progress = bar.callback();
  BakeSummary summary;
  Image image;
  nlohmann::json autoReport;
  std::optional<RadialProfile> profile;
  if (map.radialProfile && !map.anyAuto()) {
    const auto start = std::chrono::steady_clock::now();
    options.samplesPerTexel = map.samplesPerTexel;
    profile = bakeRadialProfile(*function, *function->symmetryAxis(), map.resolution, map.samplesPerTexel, options);
    summary.path = "profile";
    summary.seconds = secondsSince(start);
  } else if (map.anyAuto()) {
    // The cheapest configuration meeting max_error (candidates estimated, the choice baked and measured).
    AutoOptions autoOptions = map.autoOptions();
    autoOptions.bake = options;
    autoOptions.bake.progress = {};
    autoOptions.progress = options.progress;
    const auto start = std::chrono::steady_clock::now();
    AutoResult chosen = chooseConfiguration(*function, autoOptions);
    summary.path = "auto";
    summary.seconds = secondsSince(start);
    map.parameterization = chosen.chosen.parameterization;
    map.resolution = chosen.chosen.resolution;
    map.samplesPerTexel = chosen.chosen.samplesPerTexel;
    image = std::move(chosen.image);
    profile = std::move(chosen.radialProfile);
    autoReport = {{"chosen", chosen.chosen.describe()},
                  {"measured_error", chosen.error},
                  {"max_error", map.autoSelect.maxError},
                  {"error_measure", map.parameterization == ParameterizationKind::Sphere ||
                                            (profile && (profile->axis() - Vec3::UnitZ()).norm() < 1e-12)
                                        ? "RMS over a visible sphere's lookups, relative to the peak"
                                        : "RMS over directions uniform on the sphere, relative to the peak"},
                  {"bakes", chosen.bakes},
                  {"configurations_estimated", chosen.estimated}};
    if (!chosen.rejected.empty()) {
      autoReport["next_cheaper"] = {{"configuration", chosen.rejected.back().first.describe()},
                                    {"error", chosen.rejected.back().second}};
    }
  } else {
    options.samplesPerTexel = map.samplesPerTexel;
    BakedMap baked = bakeMap(*makeParameterization(map.parameterization, map.resolution), *function, options);
    image = std::move(baked.image);
    summary = baked.summary;
  }
  bar.done();
  if (profile) {
    return writeProfile(*profile, map, summary, autoReport, args);
  }
  const auto parameterization = makeParameterization(map.parameterization, map.resolution);

  MapInfo info;
  info.parameterization = map.parameterization;
  info.resolution = map.resolution;
  info.conventionVersion = kConventionVersion;
  info.spec = map.raw;
  if (!autoReport.is_null()) info.spec["auto"] = autoReport;
  const auto writeStart = std::chrono::steady_clock::now();
  MapWriteReport written = writeMap(image, info, map.output, map.cubeLayout, {{fs::path(args.spec)}});
  // Extra files the spec asks for: silhouette mip levels ("mips"), the 1-D Fresnel table ("fresnel_table_output").
  const MapWriteReport extras = writeMapExtras(map, options, {{fs::path(args.spec)}});
  written.files.insert(written.files.end(), extras.files.begin(), extras.files.end());
  written.notes.insert(written.notes.end(), extras.notes.begin(), extras.notes.end());
  const double writeSeconds = secondsSince(writeStart);

  nlohmann::json entry =
      reportEntry(map,
                  {std::string(toString(map.parameterization)), map.resolution, parameterization->width(),
                   parameterization->height(), summary.path, summary.seconds, writeSeconds},
                  written.files, written.notes);
  entry["samples_per_texel"] = map.samplesPerTexel;
  if (!autoReport.is_null()) entry["auto"] = autoReport;
  if (!args.json && !args.quiet) {
    std::cout << "wrote " << map.output.string() << " (" << toString(map.parameterization) << " "
              << parameterization->width() << "x" << parameterization->height() << ", " << map.samplesPerTexel
              << " samples/texel, " << summary.path << "): bake " << summary.seconds << " s, write " << writeSeconds
              << " s\n";
    printAutoChoice(autoReport, map.autoSelect.maxError);
    for (const auto& note : written.notes) std::cout << "  note: " << note << "\n";
  }
  return entry;
}

// Outputs go under --out-dir DIR, or the spec's folder; with --out-dir an absolute output path keeps
// only its file name.
void placeOutputs(BakeSpec& spec, const BakeArgs& args) {
  if (args.outputDirectory.empty()) return;
  for (auto& map : spec.maps) {
    const fs::path written = map.raw.at("output").get<std::string>();
    map.output = fs::path(args.outputDirectory) / (written.is_absolute() ? written.filename() : written);
  }
}

// Refuses oversize maps before any work, so a spec either bakes whole or writes nothing.
void checkMapSizes(const BakeSpec& spec, const BakeOptions& options, const std::string& label) {
  for (const auto& map : spec.maps) {
    if (map.anyAuto()) continue;  // auto candidates stay far below the limit
    const auto parameterization = makeParameterization(map.parameterization, map.resolution);
    const long long texels = static_cast<long long>(parameterization->width()) * parameterization->height();
    const std::string size =
        std::to_string(parameterization->width()) + " x " + std::to_string(parameterization->height());
    if (texels > options.maxTexels && !options.allowLarge) {
      throw Error(Error::Kind::Resource, label + ": " + map.jsonPath + ": a " + size + " map needs " +
                                             formatBytes(static_cast<double>(texels) * 16.0) +
                                             "; lower its resolution or pass --allow-large");
    }
    requireWithinMemoryBudget(static_cast<double>(texels) * 16.0, label + ": " + map.jsonPath + ": a " + size + " map");
  }
}

int runBake(const BakeArgs& args) {
  if (!args.misplacedOutput.empty()) {
    throw Error(Error::Kind::InvalidArgument,
                "-o " + shortenForMessage(args.misplacedOutput) +
                    ": bake writes one file per map, named by the spec's \"output\" keys; "
                    "give the folder they go in with --out-dir DIR");
  }
  BakeSpec spec = loadBakeSpec(args.spec);
  placeOutputs(spec, args);
  const fs::path specFolder = fs::path(args.spec).parent_path();
  const fs::path outputFolder = !args.outputDirectory.empty() ? fs::path(args.outputDirectory)
                                : specFolder.empty()          ? fs::path(".")
                                                              : specFolder;
  // Every file the spec reads and writes, checked against each other before any work.
  planSpecFiles(spec, args.spec, outputFolder).check();
  BakeOptions options;
  options.threads = args.threads;
  options.allowLarge = args.allowLarge;
  checkMapSizes(spec, options, args.spec);

  // Environments of prefiltered maps are read (and checked) before any work, too.
  std::vector<std::optional<Environment>> environments(spec.maps.size());
  for (std::size_t i = 0; i < spec.maps.size(); ++i) {
    if (const EnvironmentMapSpec* e = spec.maps[i].environmentMap()) {
      environments[i] = loadEnvironment(e->file, EnvironmentLoadOptions{e->from});
    }
  }

  // A map that fails while baking does not stop the others; each map's status is reported and the
  // first failure decides the exit status.
  nlohmann::json report = {{"spec", args.spec}, {"maps", nlohmann::json::array()}};
  std::exception_ptr firstFailure;
  int failed = 0;
  for (std::size_t i = 0; i < spec.maps.size(); ++i) {
    const MapSpec& map = spec.maps[i];
    nlohmann::json entry;
    try {
      entry = std::visit(
          Overloaded{[&](const EnvironmentMapSpec& e) { return bakeEnvironmentMap(map, e, *environments[i], args); },
                     [&](const MaterialMapSpec&) { return bakeMaterialMap(map, options, args); }},
          map.content);
      entry["status"] = "written";
      for (const auto& note : map.notes) {
        entry["notes"].push_back(note);
        if (!args.json && !args.quiet) std::cout << "  note: " << note << "\n";
      }
    } catch (const Error& e) {
      if (!firstFailure) firstFailure = std::current_exception();
      ++failed;
      entry = {{"output", map.output.string()}, {"status", "failed"}, {"error", e.what()}};
      if (!args.json) std::cerr << "brdfbake: " << map.jsonPath << " failed: " << e.what() << "\n";
    }
    report["maps"].push_back(entry);
  }
  if (args.json) std::cout << report.dump(2) << "\n";
  if (firstFailure) {
    if (!args.json) {
      std::cerr << "brdfbake: " << failed << " of " << spec.maps.size() << " maps failed; the others were written\n";
    }
    std::rethrow_exception(firstFailure);
  }
  return 0;
}

}  // namespace

Command addBakeCommand(CLI::App& app) {
  auto args = std::make_shared<BakeArgs>();
  auto* command = app.add_subcommand("bake", "Bake every map described by a JSON spec");
  command->footer(R"(A spec lists maps; each names its output, parameterization (sphere | paraboloid | cube |
latlong | profile | auto), resolution, samples_per_texel, material and lights. Relative paths
resolve against the spec's folder (or --out-dir). The whole spec is validated before anything is baked.
Specs for every model: data_samples/specs/. Format: docs/spec.md. Models: phong, blinn_phong,
cook_torrance, fresnel, colorgram, gooch, silhouette, hatching (docs/materials.md), measured, lobes
(docs/fitting.md). "environment" in place of a material prefilters an HDR environment
(docs/prefilter.md). "auto" values with "max_error" let the tool pick the cheapest map that meets
it, a 1-D radial profile included when the map is radially symmetric.

  {"maps": [{"output": "phong_eye.exr", "parameterization": "sphere", "resolution": 256,
             "samples_per_texel": 16,
             "material": {"model": "phong", "specular": [1, 1, 1], "exponent": 50},
             "lights": [{"direction": "eye", "color": [1, 1, 1]}]}]})");
  command->add_option("spec", args->spec, "Spec file (JSON)")->required();
  command->add_option(
      "-d,--out-dir", args->outputDirectory,
      "Write the spec's outputs under this folder instead of the spec's own (they must stay inside it)");
  // -o names one output file on every command; bake writes a file per map, so it takes a folder.
  command->add_option("-o,--output", args->misplacedOutput, "(bake takes --out-dir: it writes one file per map)")
      ->group("");
  addThreadsOption(command, args->threads);
  addQuietFlag(command, args->quiet);
  addJsonFlag(command, args->json, "per map its status, files, seconds baking and writing, notes");
  command->add_flag("--allow-large", args->allowLarge, "Allow maps over 8192^2 texels (1 GiB of float RGBA)");
  return [args] { return runBake(*args); };
}

}  // namespace brdfbake::cli
