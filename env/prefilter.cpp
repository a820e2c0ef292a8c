// prefilter() and its neighbours: the options and the summary, the mirror lobe (resampling), the
// output levels, lobe models as sums of Phong terms, and writing the prefiltered map.
#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/material.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/named_values.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/env/env_accuracy.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/io/text_io.hpp>
#include <brdfbake/maps/map_mips.hpp>

#include <tbb/task_arena.h>

#include <chrono>
#include <optional>
#include <sstream>

#include "prefilter_internal.hpp"

namespace brdfbake {
namespace detail {

Mat3 eyeToEnvironment(const PrefilterOptions& options) {
  const Vec3 z = options.view.normalized();
  Vec3 up = options.up - options.up.dot(z) * z;
  if (up.norm() < 1e-9) up = anyPerpendicular(z);
  const Vec3 y = up.normalized();
  Mat3 r;
  r.col(0) = y.cross(z), r.col(1) = y, r.col(2) = z;
  return r;
}

}  // namespace detail

namespace {
using detail::eyeToEnvironment;
using Clock = std::chrono::steady_clock;

// Mirror: the environment looked up (bilinear) over each texel's footprint.
class RotatedEnvironment final : public MapFunction {
 public:
  RotatedEnvironment(const Environment& environment, const Mat3& rotation)
      : environment_(environment), rotation_(rotation) {}
  Rgb evaluate(const Vec3& direction) const override { return environment_.radiance(rotation_ * direction); }

 private:
  const Environment& environment_;
  Mat3 rotation_;
};

void requireFiniteOutput(const Image& image) {
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      if (!allFinite(image.at(x, y))) {
        throw Error(Error::Kind::Numerical, "prefilter produced a non-finite value at texel (" + std::to_string(x) +
                                                ", " + std::to_string(y) + ")");
      }
}

// ---- the steps of prefilter() ------------------------------------------------------------------

// The output map, refused above the context's size limit.
std::shared_ptr<const Parameterization> outputMap(const PrefilterOptions& options, const Context& context) {
  std::shared_ptr<const Parameterization> map(makeParameterization(options.parameterization, options.resolution));
  context.requireImageSize(map->width(), map->height());
  return map;
}

// The mirror lobe: the environment looked up over each texel's footprint (the baker's supersampling).
Image resampleMirror(const Environment& environment, const Parameterization& map, const PrefilterOptions& options,
                     const Context& context, PrefilterSummary& summary) {
  if (options.method != PrefilterMethod::Auto && options.method != PrefilterMethod::Reference) {
    throw Error(Error::Kind::InvalidArgument, "the mirror lobe is plain resampling (no integral); --method " +
                                                  std::string(toString(options.method)) +
                                                  " applies to filtered lobes only");
  }
  const auto outputStart = Clock::now();
  const Mat3 rotation =
      options.parameterization == ParameterizationKind::Sphere ? eyeToEnvironment(options) : Mat3::Identity();
  const RotatedEnvironment function(environment, rotation);
  BakeOptions bakeOptions;
  bakeOptions.samplesPerTexel = options.mirrorSamples;
  Image image = bake(map, function, bakeOptions, context);
  summary.method = PrefilterMethod::Resample;
  summary.detail = std::to_string(options.mirrorSamples) + " footprint samples per texel";
  summary.exact = true;
  summary.metBound = true;
  summary.outputSeconds = secondsSince(outputStart);
  return image;
}

// Level 0 and, if asked, its solid-angle mip chain; cube edges fixed and paraboloid borders aligned
// at every level.
std::vector<Image> outputLevels(Image level0, const Parameterization& map, bool mips, bool cubeEdgeFixup) {
  if (mips) return environmentMipChain(level0, map);
  if (map.kind() == ParameterizationKind::Cube && cubeEdgeFixup) fixCubeEdges(level0, static_cast<const CubeMap&>(map));
  if (map.kind() == ParameterizationKind::Paraboloid)
    alignParaboloidBorder(level0, static_cast<const ParaboloidMap&>(map));
  std::vector<Image> levels;
  levels.push_back(std::move(level0));
  return levels;
}

}  // namespace

// ---- public ----------------------------------------------------------------------------------

std::string_view toString(PrefilterMethod method) {
  switch (method) {
    case PrefilterMethod::Auto:
      return "auto";
    case PrefilterMethod::Reference:
      return "reference";
    case PrefilterMethod::SphericalHarmonics:
      return "sh";
    case PrefilterMethod::Importance:
      return "importance";
    case PrefilterMethod::Direct:
      return "direct";
    case PrefilterMethod::Resample:
      return "resample";
  }
  return "?";
}

PrefilterMethod parsePrefilterMethod(std::string_view name) {
  return parseByName(name,
                     std::array{PrefilterMethod::Auto, PrefilterMethod::Reference, PrefilterMethod::SphericalHarmonics,
                                PrefilterMethod::Importance, PrefilterMethod::Direct},
                     "prefilter method");
}

void PrefilterOptions::validate() const {
  require(resolution >= 1 && resolution <= 65536,
          "prefilter resolution must be in [1, 65536], got " + std::to_string(resolution));
  require(view.allFinite() && view.norm() > 0.0, "prefilter view must be a non-zero finite vector");
  require(up.allFinite() && up.norm() > 0.0, "prefilter up must be a non-zero finite vector");
  require(maxError > 0.0 && maxError < 1.0,
          "max error must be in (0, 1) (a relative RMS error; 0.01 is 1 %), got " + formatG(maxError));
  require(method != PrefilterMethod::Resample, "the resample method is the mirror lobe's; choose auto or reference");
  require(shOrder >= 0 && shOrder <= 200, "SH order must be in [0, 200], got " + std::to_string(shOrder));
  require(importanceSamples >= 0 && importanceSamples <= 1 << 20, "importance samples must be in [0, 2^20]");
  require(directTexelsPerWidth >= 0.0 && directTexelsPerWidth <= 64.0, "direct texels per width must be in [0, 64]");
  require(shOrder == 0 || method == PrefilterMethod::SphericalHarmonics, "an SH order needs the sh method");
  require(importanceSamples == 0 || method == PrefilterMethod::Importance,
          "importance samples need the importance method");
  require(directTexelsPerWidth == 0.0 || method == PrefilterMethod::Direct,
          "direct texels per width need the direct method");
  require(cubeEdgeFixup || !mips,
          "cube edge fixup can be turned off only without the solid-angle mip chain, which always fixes edges");
  require(probes >= 16 && probes <= 1 << 20, "probes must be in [16, 2^20], got " + std::to_string(probes));
  require(mirrorSamples >= 1 && mirrorSamples <= 4096, "mirror samples must be in [1, 4096]");
  require(elevations >= 2 && elevations <= 64,
          "elevations (maps in a varying lobe model's stack) must be in [2, 64], got " + std::to_string(elevations));
}

std::string PrefilterSummary::briefReport() const {
  std::ostringstream out;
  out << lobe << " by " << toString(method);
  if (!detail.empty()) out << " (" << detail << ")";
  if (exact) {
    out << ": exact";
  } else if (errorEstimated) {
    out << ": estimated relative error " << formatG(100.0 * errorEstimate) << " % (RMS "
        << formatG(100.0 * errorEstimateRms) << " %, near the highlight " << formatG(100.0 * errorEstimateHighlight)
        << " %";
    if (lookupErrorEstimate >= 0.0) out << ", lookups " << formatG(100.0 * lookupErrorEstimate) << " %";
    out << "; bound " << formatG(100.0 * maxError) << " %" << (metBound ? "" : ", NOT met") << ")";
  } else {
    out << ": error not estimated (estimation off)";
  }
  out << ", " << formatG(seconds) << " s";
  if (levels > 1) out << ", " << levels << " mip levels";
  return out.str();
}

nlohmann::json PrefilterSummary::toJson() const {
  nlohmann::json candidatesJson = nlohmann::json::array();
  for (const auto& c : candidates) {
    nlohmann::json entry = {{"method", std::string(toString(c.method))},
                            {"detail", c.detail},
                            {"predicted_seconds", c.predictedSeconds},
                            {"seconds", c.seconds},
                            {"chosen", c.chosen}};
    if (c.errorEstimate >= 0.0) {
      entry["error_estimate_rms"] = c.errorEstimateRms, entry["error_estimate_highlight"] = c.errorEstimateHighlight;
      entry["error_estimate"] = c.errorEstimate, entry["error_estimate_max"] = c.errorEstimateMax,
      entry["probes"] = c.probes;
    }
    candidatesJson.push_back(entry);
  }
  nlohmann::json out = {
      {"lobe", lobe},
      {"method", std::string(toString(method))},
      {"detail", detail},
      {"max_error", maxError},
      {"error_metric", "rms_relative"},
      {"error_estimated", errorEstimated},
      {"exact", exact},
      {"met_bound", errorEstimated || exact ? nlohmann::json(metBound)
                                            : nlohmann::json(nullptr)},  // unknown when nothing was estimated
      {"levels", levels},
      {"filter_seconds", seconds},
      {"estimate_seconds", estimateSeconds},
      {"output_seconds", outputSeconds},
      {"mip_seconds", mipSeconds},
      {"candidates", candidatesJson},
      {"notes", notes}};
  out["error_estimate"] = errorEstimated ? nlohmann::json(errorEstimate) : nlohmann::json(nullptr);
  out["error_estimate_max"] = errorEstimated ? nlohmann::json(errorEstimateMax) : nlohmann::json(nullptr);
  out["error_estimate_rms"] = errorEstimated ? nlohmann::json(errorEstimateRms) : nlohmann::json(nullptr);
  out["error_estimate_highlight"] = errorEstimated ? nlohmann::json(errorEstimateHighlight) : nlohmann::json(nullptr);
  out["lookup_error_estimate"] =
      lookupErrorEstimate >= 0.0 ? nlohmann::json(lookupErrorEstimate) : nlohmann::json(nullptr);
  out["lookup_error_max"] = lookupErrorEstimate >= 0.0 ? nlohmann::json(lookupErrorMax) : nlohmann::json(nullptr);
  return out;
}

Vec3 prefilterAxis(const Vec3& mapDirection, const PrefilterLobe& lobe, const PrefilterOptions& options) {
  if (options.parameterization != ParameterizationKind::Sphere) return mapDirection.normalized();
  const Mat3 rotation = eyeToEnvironment(options);
  const Vec3 eye = lobe.indexedByNormal() ? geometryForReflection(mapDirection.normalized(), Vec3::UnitZ()).normal
                                          : mapDirection.normalized();
  return (rotation * eye).normalized();
}

namespace detail {

const LatLongPyramid& PrefilterInput::pyramid() {
  if (!pyramid_) pyramid_ = std::make_unique<LatLongPyramid>(environment_);
  return *pyramid_;
}

double PrefilterInput::meanNorm() {
  if (meanNorm_ >= 0.0) return meanNorm_;
  const Parameterization& map = *environment_.map;
  double sum = 0.0, weight = 0.0;
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) {
      const double w = map.texelSolidAngle(x, y);
      sum += w * environment_.image.at(x, y).head<3>().matrix().norm();
      weight += w;
    }
  meanNorm_ = weight > 0.0 ? sum / weight : 0.0;
  return meanNorm_;
}

}  // namespace detail

PrefilteredMap prefilter(const Environment& environment, const PrefilterLobe& lobe, const PrefilterOptions& options,
                         const Context& context) {
  detail::PrefilterInput input(environment);
  return prefilter(input, lobe, options, context);
}

PrefilteredMap prefilter(detail::PrefilterInput& input, const PrefilterLobe& lobe, const PrefilterOptions& options,
                         const Context& context) {
  options.validate();
  const Environment& environment = input.environment();
  require(environment.map && !environment.image.empty(), "prefilter: empty environment");
  const auto start = Clock::now();
  PrefilteredMap result;
  result.map = outputMap(options, context);
  PrefilterSummary& summary = result.summary;
  summary.lobe = lobe.name();
  summary.maxError = options.maxError;
  tbb::task_arena arena(context.arenaThreads());
  arena.execute([&] {
    std::optional<detail::ProbeCheck> check;
    Image level0 = lobe.isMirror() ? resampleMirror(environment, *result.map, options, context, summary)
                                   : detail::filterWithLobe(input, lobe, *result.map, options, context,
                                                            arena.max_concurrency(), summary, check);
    requireFiniteOutput(level0);
    const auto mipStart = Clock::now();
    result.levels = outputLevels(std::move(level0), *result.map, options.mips, options.cubeEdgeFixup);
    summary.mipSeconds = secondsSince(mipStart);
    if (check) {
      const auto lookupStart = Clock::now();
      detail::measureLookups(result.levels[0], *result.map, lobe, options, *check, summary);
      summary.estimateSeconds += secondsSince(lookupStart);
    }
  });
  summary.levels = static_cast<int>(result.levels.size());
  summary.seconds = secondsSince(start);
  return result;
}

void mergePrefilterSummary(PrefilterSummary& into, const PrefilterSummary& part, const std::string& label, bool first) {
  if (into.method == PrefilterMethod::Auto ||
      (part.method != PrefilterMethod::Resample && part.method != PrefilterMethod::Reference)) {
    into.method = part.method;
  }
  into.errorEstimated = into.errorEstimated || part.errorEstimated;
  into.exact = first ? part.exact : into.exact && part.exact;
  into.metBound = first ? part.metBound : into.metBound && part.metBound;
  into.errorEstimate = std::max(into.errorEstimate, part.errorEstimate);
  into.errorEstimateMax = std::max(into.errorEstimateMax, part.errorEstimateMax);
  into.errorEstimateRms = std::max(into.errorEstimateRms, part.errorEstimateRms);
  into.errorEstimateHighlight = std::max(into.errorEstimateHighlight, part.errorEstimateHighlight);
  into.lookupErrorEstimate = std::max(into.lookupErrorEstimate, part.lookupErrorEstimate);
  into.lookupErrorMax = std::max(into.lookupErrorMax, part.lookupErrorMax);
  into.estimateSeconds += part.estimateSeconds;
  into.outputSeconds += part.outputSeconds;
  into.mipSeconds += part.mipSeconds;
  into.levels = part.levels;
  for (auto candidate : part.candidates) {
    candidate.detail = label + ": " + candidate.detail;
    into.candidates.push_back(candidate);
  }
  for (const auto& note : part.notes) into.notes.push_back(label + ": " + note);
}

PrefilteredMap prefilterLobeModel(const Environment& environment, const LobeModel& model, const std::string& name,
                                  const PrefilterOptions& options, const Context& context) {
  model.validate();
  if (model.variesWithView()) {
    throw Error(Error::Kind::InvalidArgument,
                name +
                    ": lobes that vary with elevation (or with a colour profile) need a stack of maps over elevation "
                    "(prefilterLobeModelStack); only constant lobe models prefilter into one map");
  }
  options.validate();
  const auto start = Clock::now();
  // RGB weight of each distinct exponent (env_accuracy.hpp).
  const std::vector<std::pair<double, Rgb>> terms = prefilterLobeModelTerms(model);
  PrefilterOptions run = options;
  run.mips = false;
  PrefilteredMap result;
  PrefilterSummary& summary = result.summary;
  summary.lobe = name;
  summary.maxError = options.maxError;
  std::ostringstream detail;
  Image sum;
  detail::PrefilterInput input(environment);
  for (std::size_t t = 0; t < terms.size(); ++t) {
    const auto& [exponent, weight] = terms[t];
    const double share = 1.0 / static_cast<double>(terms.size());
    const PrefilteredMap part =
        prefilter(input, PrefilterLobe::phong(exponent), run, context.part(t * share, (t + 1) * share));
    const bool first = sum.empty();
    if (first) {
      sum = part.levels[0];
      result.map = part.map;
      for (int y = 0; y < sum.height(); ++y)
        for (int x = 0; x < sum.width(); ++x) sum.set(x, y, Rgba(0, 0, 0, part.levels[0].at(x, y)[3]));
    }
    for (int y = 0; y < sum.height(); ++y)
      for (int x = 0; x < sum.width(); ++x) {
        Rgba v = sum.at(x, y);
        v.head<3>() += weight * part.levels[0].at(x, y).head<3>();
        sum.set(x, y, v);
      }
    const PrefilterSummary& s = part.summary;
    detail << (detail.tellp() > 0 ? "; " : "") << s.lobe << " by " << toString(s.method);
    mergePrefilterSummary(summary, s, s.lobe, first);
  }
  if (terms.empty()) {
    throw Error(Error::Kind::InvalidArgument, name + ": the model has no lobe of non-zero weight to prefilter");
  }
  summary.detail = std::to_string(terms.size()) + " Phong terms: " + detail.str();
  const auto mipStart = Clock::now();
  result.levels = options.mips ? environmentMipChain(sum, *result.map) : std::vector<Image>{sum};
  summary.mipSeconds = secondsSince(mipStart);
  summary.levels = static_cast<int>(result.levels.size());
  summary.seconds = secondsSince(start);
  return result;
}

MapInfo prefilteredMapInfo(const PrefilteredMap& map, nlohmann::json spec, int level) {
  if (!spec.is_object()) spec = nlohmann::json::object();
  MapInfo info;
  info.parameterization = map.map->kind();
  info.resolution = std::max(1, map.map->resolution() >> level);
  info.conventionVersion = kConventionVersion;
  info.spec = std::move(spec);
  const PrefilterSummary& s = map.summary;
  nlohmann::json& prefilterInfo = info.spec["prefilter"];
  if (!prefilterInfo.is_object()) prefilterInfo = nlohmann::json::object();
  prefilterInfo.update(
      nlohmann::json{{"lobe", s.lobe},
                     {"method", std::string(toString(s.method))},
                     {"detail", s.detail},
                     {"max_error", s.maxError},
                     {"error_metric", "rms_relative"},
                     {"error_estimate", s.errorEstimated ? nlohmann::json(s.errorEstimate) : nlohmann::json(nullptr)},
                     {"exact", s.exact},
                     {"mip_level", level},
                     {"mip_levels", static_cast<int>(map.levels.size())}});
  if (s.lobe == "irradiance") prefilterInfo["irradiance_quantity"] = kIrradianceQuantity;
  if (!map.levelValues.empty()) info.spec["level_values"] = map.levelValues;
  return info;
}

MapWriteReport writePrefilteredMap(const PrefilteredMap& map, const std::filesystem::path& path, nlohmann::json spec,
                                   CubeLayout layout, const WriteOptions& options, MipLayout mipLayout) {
  require(!map.levels.empty() && map.map, "writePrefilteredMap: nothing to write");
  const int count = static_cast<int>(map.levels.size());
  auto levelInfo = [&](int level) { return prefilteredMapInfo(map, spec, level); };
  if (mipLayout == MipLayout::Tiled) {
    // A 1 x 1 map has one level: its tiled file holds just that level.
    require(count == mipLevelCount(map.map->resolution()),
            "a tiled MIP-mapped output holds every mip level; prefilter with mips on (\"mips\": true, --mips)");
    MapInfo info = levelInfo(0);
    info.spec["prefilter"]["mip_layout"] = "tiled";
    info.spec.erase("level_values");  // writeTiledMap stores them beside "mip_levels"
    return writeTiledMap(map.levels, info, path, layout, options, map.levelValues);
  }
  MapWriteReport report;
  for (int level = 0; level < count; ++level) {
    const MapWriteReport written =
        writeMap(map.levels[level], levelInfo(level), mipLevelPath(path, level), layout, options);
    report.files.insert(report.files.end(), written.files.begin(), written.files.end());
    if (level == 0) report.notes.insert(report.notes.end(), written.notes.begin(), written.notes.end());
  }
  return report;
}

}  // namespace brdfbake
