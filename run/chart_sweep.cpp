// Sweeping one map of a spec over its configurations, each made, timed and measured (run/chart.hpp).
#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/auto_config.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/env/env_accuracy.hpp>

#include <chrono>

#include "chart_internal.hpp"
#include "map_runners.hpp"

namespace brdfbake::run_detail {

namespace {

using Clock = std::chrono::steady_clock;

// What one (parameterization, resolution) of an environment sweep compares against: the reference
// prefilter at a random texel subset and at random lookup directions, computed once for every method.
struct SweepReference {
  PrefilterCheckPoints texels, lookups;
  std::vector<Rgb> texelValues, lookupValues;
  long long mapTexels = 0;
  double seconds = 0.0;  // the reference over the whole map, scaled from the subset
};

SweepReference sweepReference(const Environment& environment, const EnvironmentMapSpec& e, const Parameterization& map,
                              const PrefilterOptions& options, int subset, const Context& context) {
  const PrefilterLobe* lobe = e.analyticLobe();
  // Axes of a lobe model are the reflected directions, as phong's.
  const PrefilterLobe axisLobe = lobe ? *lobe : PrefilterLobe::phong(1.0);
  SweepReference r;
  r.texels = prefilterTexelSubset(map, axisLobe, options, subset, 7);
  r.lookups = prefilterLookupSet(map, axisLobe, options, subset, 8);
  std::vector<Vec3> axes = r.texels.axes;
  axes.insert(axes.end(), r.lookups.axes.begin(), r.lookups.axes.end());
  const auto start = Clock::now();
  const std::vector<Rgb> reference = lobe ? prefilterReferenceAt(environment, *lobe, axes, context)
                                          : prefilterLobeModelReferenceAt(environment, *e.lobeModel(), axes, context);
  const double seconds = secondsSince(start);
  const auto split = reference.begin() + static_cast<std::ptrdiff_t>(r.texels.size());
  r.texelValues.assign(reference.begin(), split);
  r.lookupValues.assign(split, reference.end());
  r.mapTexels = static_cast<long long>(map.width()) * map.height();
  r.seconds = seconds * double(r.mapTexels) / double(axes.size());
  return r;
}

// One prefilter of an environment map, timed and measured against the reference. Throws Error when
// the method cannot make the map.
ChartPoint environmentPoint(const MapSpec& map, const EnvironmentMapSpec& e, const Environment& environment,
                            const PrefilterOptions& options, const SweepReference& reference, double floor,
                            const Context& context) {
  const PrefilterLobe* lobe = e.analyticLobe();
  const auto start = Clock::now();
  const PrefilteredMap result = lobe ? prefilter(environment, *lobe, options, context)
                                     : prefilterLobeModel(environment, *e.lobeModel(), e.lobeName, options, context);
  ChartPoint p;
  p.seconds = secondsSince(start);
  p.environment = true;
  p.map = map.jsonPath;
  p.parameterization = std::string(toString(options.parameterization));
  p.resolution = options.resolution;
  p.method = std::string(toString(options.method));
  p.detail = result.summary.detail;
  if (options.method == PrefilterMethod::Auto && lobe)
    p.detail = std::string(toString(result.summary.method)) + ": " + p.detail;
  p.texels = reference.mapTexels;
  const auto measure = [&](const PrefilterCheckPoints& points, const std::vector<Rgb>& values) {
    return prefilterPointsError(prefilterValuesAt(result.levels[0], *result.map, points), values, points.weights,
                                floor);
  };
  const PrefilterError texelError = measure(reference.texels, reference.texelValues);
  const PrefilterError lookupError = measure(reference.lookups, reference.lookupValues);
  p.rms = texelError.rms;
  p.max = texelError.max;
  p.visibleRms = texelError.rms;
  p.lookupRms = lookupError.rms;
  p.lookupMax = lookupError.max;
  if (result.summary.errorEstimated) p.estimate = result.summary.errorEstimate;
  p.metBound = result.summary.metBound;
  p.referenceSeconds = reference.seconds;
  return p;
}

// Why an environment map cannot be charted, or empty.
std::string environmentSkipReason(const EnvironmentMapSpec& e) {
  if (e.analyticLobe() && e.analyticLobe()->isMirror()) {
    return "the mirror lobe is a resampling with no reference to chart against; map skipped";
  }
  if (e.lobeModel() && e.lobeModel()->variesWithView()) {
    return "lobes that vary with elevation (or have a colour profile) prefilter into a stack of maps (one per "
           "elevation); chart a slice's "
           "constant model instead; map skipped";
  }
  if (e.glossChain) return "a gloss chain is one map per level; chart one level's lobe instead; map skipped";
  return "";
}

// One bake of a material map, timed and measured against the exact model.
ChartPoint materialPoint(const MapSpec& map, const MapFunction& function, const ErrorProbes& probes,
                         ParameterizationKind kind, int resolution, int samplesPerTexel, const Context& context) {
  const auto parameterization = makeParameterization(kind, resolution);
  BakeOptions options;
  options.samplesPerTexel = samplesPerTexel;
  const auto [image, summary] = bakeMap(*parameterization, function, options, context);
  ChartPoint p;
  p.map = map.jsonPath;
  p.parameterization = std::string(toString(kind));
  p.resolution = resolution;
  p.samples = samplesPerTexel;
  p.texels = static_cast<long long>(parameterization->width()) * parameterization->height();
  p.seconds = summary.seconds;
  const ErrorStats error = measureMapError(image, *parameterization, probes);
  p.rms = error.rms;
  p.max = error.max;
  p.visibleRms = error.visibleRms;
  p.highlightRms = error.highlightRms;
  p.highlightMax = error.highlightMax;
  p.bound = autoErrorMeasure(error, kind);
  return p;
}

}  // namespace

MapChart chartEnvironmentMap(const MapSpec& map, const EnvironmentMapSpec& e, const Environment& environment,
                             const ChartOptions& options, const Context& context, std::vector<ChartSkip>& skipped) {
  if (const std::string reason = environmentSkipReason(e); !reason.empty()) {
    skipped.push_back({map.jsonPath, "", "", reason, 0});
    return {};
  }
  const PrefilterLobe* lobe = e.analyticLobe();
  const double floor =
      lobe ? prefilterErrorFloor(environment, *lobe) : prefilterLobeModelErrorFloor(environment, *e.lobeModel());
  const Context task = context.task(map.jsonPath);
  const Context quiet = task.withoutProgress();
  const double total =
      double(options.parameterizations.size() * options.environmentResolutions.size() * options.methods.size());
  int done = 0;
  MapChart chart;
  chart.environment = true;
  for (const auto kind : options.parameterizations) {
    for (const int resolution : options.environmentResolutions) {
      PrefilterOptions prefilterOptions = map.prefilterOptions();
      prefilterOptions.parameterization = kind;
      prefilterOptions.resolution = resolution;
      prefilterOptions.mips = false;
      if (options.maxError > 0.0) prefilterOptions.maxError = options.maxError;
      const SweepReference reference = sweepReference(environment, e, *makeParameterization(kind, resolution),
                                                      prefilterOptions, options.subset, quiet);
      for (const auto method : options.methods) {
        prefilterOptions.method = method;
        try {
          chart.points.push_back(environmentPoint(map, e, environment, prefilterOptions, reference, floor, quiet));
        } catch (const Error& error) {
          skipped.push_back(
              {map.jsonPath, std::string(toString(kind)), std::string(toString(method)), error.what(), resolution});
        }
        task.report(++done / total);
      }
    }
  }
  chart.title = map.jsonPath + ": " + e.lobeName + " of " + e.file.filename().string() + ", bound " +
                formatNumber(100.0 * (options.maxError > 0.0 ? options.maxError : e.maxError)) + " % (" +
                map.output.filename().string() + ")";
  return chart;
}

MapChart chartMaterialMap(MapSpec& map, const ChartOptions& options, const Context& context) {
  if (map.materialMap()->deferredFit) map.prepare(context.task(map.jsonPath + " fitting lobes"));
  const auto function = map.makeFunction();
  const Context task = context.task(map.jsonPath);
  const double total =
      double(options.parameterizations.size() * options.resolutions.size() * options.samplesPerTexel.size());
  int done = 0;
  ErrorOptions errorOptions;
  errorOptions.samples = options.lookups;
  const ErrorProbes probes(*function, errorOptions);
  MapChart chart;
  for (const auto kind : options.parameterizations)
    for (const int resolution : options.resolutions)
      for (const int samples : options.samplesPerTexel) {
        chart.points.push_back(
            materialPoint(map, *function, probes, kind, resolution, samples, task.withoutProgress()));
        task.report(++done / total);
      }
  chart.title = map.jsonPath + ": " + map.modelName() + " (" + map.output.filename().string() + ")";
  return chart;
}

}  // namespace brdfbake::run_detail
