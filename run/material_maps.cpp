// A map baked from a material: one bake, a radial profile, or `auto`'s choice (bake/auto_config.hpp).
#include <brdfbake/bake/auto_config.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/bake/radial_profile.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/io/map_file.hpp>

#include <chrono>

#include "map_runners.hpp"

namespace brdfbake::run_detail {
namespace fs = std::filesystem;

namespace {

// What baking made: a map image or a radial profile, how, and auto's report when it chose.
struct Baked {
  MapSpec map;  // with auto's choice filled in
  Image image;
  std::optional<RadialProfile> profile;
  BakeSummary summary;
  nlohmann::json autoReport;  // null unless auto chose
};

std::string errorMeasureName(const MapSpec& map, const std::optional<RadialProfile>& profile) {
  const bool visible = map.parameterization == ParameterizationKind::Sphere ||
                       (profile && (profile->axis() - Vec3::UnitZ()).norm() < 1e-12);
  return visible ? "RMS over a visible sphere's lookups, relative to the peak"
                 : "RMS over directions uniform on the sphere, relative to the peak";
}

// The cheapest configuration meeting max_error (candidates estimated, the choice baked and measured).
void bakeAuto(const MapFunction& function, const BakeOptions& options, const Context& context, Baked& baked) {
  AutoOptions autoOptions = baked.map.autoOptions();
  autoOptions.bake = options;
  const auto start = std::chrono::steady_clock::now();
  AutoResult chosen = chooseConfiguration(function, autoOptions, context);
  baked.summary.path = "auto";
  baked.summary.seconds = secondsSince(start);
  MapSpec& map = baked.map;
  map.parameterization = chosen.chosen.parameterization;
  map.resolution = chosen.chosen.resolution;
  map.samplesPerTexel = chosen.chosen.samplesPerTexel;
  baked.image = std::move(chosen.image);
  baked.profile = std::move(chosen.radialProfile);
  baked.autoReport = {{"chosen", chosen.chosen.describe()},
                      {"measured_error", chosen.error},
                      {"max_error", map.autoSelect.maxError},
                      {"error_measure", errorMeasureName(map, baked.profile)},
                      {"bakes", chosen.bakes},
                      {"configurations_estimated", chosen.estimated}};
  if (!chosen.rejected.empty()) {
    baked.autoReport["next_cheaper"] = {{"configuration", chosen.rejected.back().first.describe()},
                                        {"error", chosen.rejected.back().second}};
  }
}

Baked bakeMaterial(const MapSpec& specified, const MapRunContext& context) {
  Baked baked{specified, {}, {}, {}, nullptr};
  MapSpec& map = baked.map;
  if (const auto& fit = map.materialMap()->deferredFit) {  // a measured material's fit runs now
    map.prepare(context.context.task(map.jsonPath + " fitting lobes to " +
                                     fs::path(fit->table.sourceFile).filename().string()));
  }
  const auto function = map.makeFunction();
  BakeOptions options;
  options.samplesPerTexel = map.samplesPerTexel;
  const Context task = context.context.task(map.jsonPath + " " + map.outputName());
  if (map.anyAuto()) {
    bakeAuto(*function, options, task, baked);
  } else if (map.radialProfile) {
    const auto start = std::chrono::steady_clock::now();
    baked.profile = bakeRadialProfile(*function, *function->symmetryAxis(), map.resolution, map.samplesPerTexel, task);
    baked.summary.path = "profile";
    baked.summary.seconds = secondsSince(start);
  } else {
    BakedMap result = bakeMap(*makeParameterization(map.parameterization, map.resolution), *function, options, task);
    baked.image = std::move(result.image);
    baked.summary = result.summary;
  }
  return baked;
}

void addAutoLines(const nlohmann::json& autoReport, MapResult& result) {
  if (autoReport.is_null()) return;
  result.entry["auto"] = autoReport;
  result.lines.push_back("  auto: chose " + autoReport["chosen"].get<std::string>() + ", measured error " +
                         formatNumber(autoReport["measured_error"].get<double>()) +
                         " <= " + formatNumber(autoReport["max_error"].get<double>()) + " (" +
                         std::to_string(autoReport["configurations_estimated"].get<int>()) +
                         " configurations estimated, " + std::to_string(autoReport["bakes"].get<int>()) + " baked)");
}

void addNoteLines(const std::vector<std::string>& notes, MapResult& result) {
  for (const auto& note : notes) result.lines.push_back("  note: " + note);
}

// A 1-D radial profile: an N x 1 image whose metadata says how to look it up (bake/radial_profile.hpp).
MapResult writeProfile(const Baked& baked, const MapRunContext& context) {
  const RadialProfile& profile = *baked.profile;
  const MapSpec& map = baked.map;
  Image image = profile.toImage();
  image.metadata["convention_version"] = kConventionVersion;
  image.metadata["spec"] = withoutFolders(map.raw);
  if (!baked.autoReport.is_null()) image.metadata["spec"]["auto"] = baked.autoReport;
  const auto writeStart = std::chrono::steady_clock::now();
  MapWriteReport written;
  const std::vector<fs::path> files = map.outputs();
  for (std::size_t i = 0; i < files.size(); ++i) {
    const fs::path& file = files[i];
    appendWritten(written, {{file}, writeImage(image, file, map.writeOptionsFor(i, context.write.inputs)).notes});
  }
  const double writeSeconds = secondsSince(writeStart);
  const int n = profile.resolution();
  MapResult result =
      makeMapResult(placeOf(map), {"profile", n, n, 1, baked.summary.path, baked.summary.seconds, writeSeconds},
                    written.files, written.notes);
  const Vec3& axis = profile.axis();
  result.entry["axis"] = {axis.x(), axis.y(), axis.z()};
  result.entry["samples_per_texel"] = map.samplesPerTexel;
  result.lines.push_back(placeOf(map).made() + " (1-D radial profile, " + std::to_string(n) + " texels about (" +
                         formatNumber(axis.x()) + ", " + formatNumber(axis.y()) + ", " + formatNumber(axis.z()) +
                         "), " + baked.summary.path + "): bake " + formatNumber(baked.summary.seconds) + " s, write " +
                         formatNumber(writeSeconds) + " s");
  result.lines.push_back("  lookup: u = |r - axis| / 2, texel i at u = (i + 0.5) / " + std::to_string(n) +
                         " (about the view: u = the sphere-map radius)");
  addAutoLines(baked.autoReport, result);
  addNoteLines(written.notes, result);
  return result;
}

MapResult writeMaterialMap(const Baked& baked, const MapRunContext& context) {
  const MapSpec& map = baked.map;
  const auto parameterization = makeParameterization(map.parameterization, map.resolution);
  MapInfo info;
  info.parameterization = map.parameterization;
  info.resolution = map.resolution;
  info.conventionVersion = kConventionVersion;
  info.spec = withoutFolders(map.raw);
  if (!baked.autoReport.is_null()) info.spec["auto"] = baked.autoReport;
  const auto writeStart = std::chrono::steady_clock::now();
  MapWriteReport written;
  const BakeOptions extrasOptions;
  const std::vector<fs::path> files = map.outputs();
  for (std::size_t i = 0; i < files.size(); ++i) {
    const WriteOptions options = map.writeOptionsFor(i, context.write.inputs);
    appendWritten(written, writeMap(baked.image, info, files[i], map.cubeLayout, options));
    // Extra files the spec asks for beside each output: silhouette mip levels ("mips"); the 1-D Fresnel
    // table (one file, written with the first).
    MapSpec one = map;
    one.output = files[i];
    if (i > 0) one.materialMap()->fresnelTableOutput.reset();
    appendWritten(written, writeMapExtras(one, extrasOptions, options, context.context));
  }
  const double writeSeconds = secondsSince(writeStart);
  const std::string kind(toString(map.parameterization));
  const int width = parameterization->width(), height = parameterization->height();
  MapResult result = makeMapResult(
      placeOf(map), {kind, map.resolution, width, height, baked.summary.path, baked.summary.seconds, writeSeconds},
      written.files, written.notes);
  result.entry["samples_per_texel"] = map.samplesPerTexel;
  result.lines.push_back(placeOf(map).made() + " (" + kind + " " + std::to_string(width) + "x" +
                         std::to_string(height) + ", " + std::to_string(map.samplesPerTexel) + " samples/texel, " +
                         baked.summary.path + "): bake " + formatNumber(baked.summary.seconds) + " s, write " +
                         formatNumber(writeSeconds) + " s");
  addAutoLines(baked.autoReport, result);
  addNoteLines(written.notes, result);
  if (map.inMemory()) {
    auto image = std::make_shared<const Image>(baked.image);
    auto write = [image, info](const MapOutputs& o) {
      o.validate();
      MapWriteReport report;
      for (std::size_t i = 0; i < o.files.size(); ++i)
        appendWritten(report, writeMap(*image, info, o.files[i], o.layout, o.writeOptionsFor(i)));
      return report;
    };
    result.made = std::make_shared<const MadeMap>(MadeMap{{baked.image}, info, std::move(write)});
  }
  return result;
}

}  // namespace

MapResult runMaterialMap(const MapSpec& map, const MapRunContext& context) {
  const Baked baked = bakeMaterial(map, context);
  return baked.profile ? writeProfile(baked, context) : writeMaterialMap(baked, context);
}

}  // namespace brdfbake::run_detail
