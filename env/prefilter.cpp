#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/material.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/named_values.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/core/run_options.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/env/env_accuracy.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/maps/map_mips.hpp>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>

#include "prefilter_internal.hpp"

namespace brdfbake {
namespace {
using detail::LatLongPyramid;
using detail::relativeError;
using Clock = std::chrono::steady_clock;

std::string formatG(double value) {
  std::ostringstream out;
  out.precision(3);
  out << value;
  return out.str();
}

// Cost model (seconds per operation on one core, measured on the development machine; only the
// order of candidates depends on it).
constexpr double kDirectPerSample = 5e-9;
constexpr double kShPerCoefficient = 5e-9;  // evaluation: basis and RGB dot, per coefficient
constexpr double kShProjectPerCoefficient = 2e-9;
constexpr double kImportancePerSample = 60e-9;
constexpr double kGridLookup = 80e-9;
constexpr double kConvolvedPerSample = 0.6e-9;  // direct sum on a grid by row convolutions, per grid point and texel
constexpr double kReferencePerSample = 6e-9;

// Eye space of a sphere map -> environment frame.
Mat3 eyeToEnvironment(const PrefilterOptions& options) {
  const Vec3 z = options.view.normalized();
  Vec3 up = options.up - options.up.dot(z) * z;
  if (up.norm() < 1e-9) up = anyPerpendicular(z);
  const Vec3 y = up.normalized();
  Mat3 r;
  r.col(0) = y.cross(z), r.col(1) = y, r.col(2) = z;
  return r;
}

// ---- evaluators ------------------------------------------------------------------------------

struct Evaluator {
  virtual ~Evaluator() = default;
  virtual Rgb value(const Vec3& axis) const = 0;
};

struct DirectEvaluator final : Evaluator {
  explicit DirectEvaluator(std::unique_ptr<detail::DirectSummer> s) : summer(std::move(s)) {}
  Rgb value(const Vec3& axis) const override { return summer->value(axis); }
  std::unique_ptr<detail::DirectSummer> summer;
};

struct ImportanceEvaluator final : Evaluator {
  explicit ImportanceEvaluator(std::unique_ptr<detail::ImportanceSampler> s) : sampler(std::move(s)) {}
  Rgb value(const Vec3& axis) const override { return sampler->value(axis); }
  std::unique_ptr<detail::ImportanceSampler> sampler;
};

struct ShEvaluator final : Evaluator {
  explicit ShEvaluator(std::unique_ptr<detail::ShFilter> f) : filter(std::move(f)) {}
  Rgb value(const Vec3& axis) const override {
    thread_local std::vector<double> scratch;
    scratch.resize(shCount(filter->order()));
    return filter->value(axis, scratch.data());
  }
  std::unique_ptr<detail::ShFilter> filter;
};

struct GridEvaluator final : Evaluator {
  GridEvaluator(const Evaluator& inner, int height) : grid(height) {
    tbb::parallel_for(0, grid.height(), [&](int y) {
      for (int x = 0; x < grid.width(); ++x) grid.set(x, y, inner.value(grid.direction(x, y)));
    });
  }
  Rgb value(const Vec3& axis) const override { return grid.value(axis); }
  detail::LatLongGrid grid;
};

struct ConvolvedGridEvaluator final : Evaluator {
  explicit ConvolvedGridEvaluator(detail::LatLongGrid g) : grid(std::move(g)) {}
  Rgb value(const Vec3& axis) const override { return grid.value(axis); }
  detail::LatLongGrid grid;
};

struct ReferenceEvaluator final : Evaluator {
  ReferenceEvaluator(const Environment& environment, const PrefilterLobe& lobe) : summer(environment, lobe) {}
  Rgb value(const Vec3& axis) const override { return summer.value(axis); }
  detail::ReferenceSummer summer;
};

// A configuration of one method.
struct CandidateSpec {
  PrefilterMethod method = PrefilterMethod::Auto;
  int shOrder = 0;
  int samples = 0;
  double q = 0.0, tail = 0.0;
  double shTail = 0.0;   // SH: max over l > order of |lambda_l| / lambda_0 (the truncation's scale)
  int gridPerWidth = 0;  // > 0: evaluate a lat-long grid with this many points per lobe width, interpolate
  int gridHeight = 0;
  int gridMultiple = 0;  // > 0: the direct sum's grid by row convolutions, this many grid rows per level row
  double predicted = 0.0;
  std::string detail;
};

CandidateSpec makeSpec(PrefilterMethod method, int shOrder = 0, int samples = 0, double q = 0.0, double tail = 0.0) {
  CandidateSpec spec;
  spec.method = method, spec.shOrder = shOrder, spec.samples = samples, spec.q = q, spec.tail = tail;
  return spec;
}

// Everything the candidates share, built on first use.
class Context {
 public:
  Context(detail::PrefilterInput& input, const PrefilterLobe& lobe) : input_(input), lobe_(lobe) {}
  const LatLongPyramid& pyramid() { return input_.pyramid(); }
  // prefilterErrorFloor's delta.
  double errorFloor() { return std::max(1e-3 * lobe_.mass() * input_.meanNorm(), 1e-30); }
  std::shared_ptr<const RadialTable> table() {
    if (!table_) {
      const PrefilterLobe lobe = lobe_;
      table_ = std::make_shared<RadialTable>([lobe](double c) { return lobe.weight(c); }, 1e-6, (1 << 20) + 1);
    }
    return table_;
  }
  // The lobe narrowed for sums over box-filtered texels of angular size `box`: a box adds a
  // variance of box^2/12 per axis, so the lobe's angles are scaled by s = sigma / sqrt(sigma^2 -
  // box^2/12) (at most sqrt 2) to keep the variance of the sum that of the lobe.
  std::shared_ptr<const RadialTable> correctedTable(double box) {
    const double sigma = lobe_.width(), added = box * box / 12.0;
    const double scale = added < 0.5 * sigma * sigma ? sigma / std::sqrt(sigma * sigma - added) : std::sqrt(2.0);
    if (scale < 1.0 + 1e-3) return table();
    const long key = std::lround(scale * 1e6);
    auto& entry = corrected_[key];
    if (!entry) {
      const PrefilterLobe lobe = lobe_;
      entry = std::make_shared<RadialTable>(
          [lobe, scale](double c) {
            return lobe.weight(std::cos(std::min(kPi, scale * std::acos(std::clamp(c, -1.0, 1.0)))));
          },
          1e-6, (1 << 20) + 1);
    }
    return entry;
  }
  const std::vector<double>& zonal(int order) {
    if (static_cast<int>(zonal_.size()) <= order) zonal_ = lobe_.zonalCoefficients(std::max(order, 256));
    return zonal_;
  }
  const Environment& environment() const { return input_.environment(); }
  const PrefilterLobe& lobe() const { return lobe_; }

 private:
  detail::PrefilterInput& input_;
  PrefilterLobe lobe_;
  std::shared_ptr<const RadialTable> table_;
  std::map<long, std::shared_ptr<const RadialTable>> corrected_;
  std::vector<double> zonal_;
};

int directLevel(Context& context, double q) { return context.pyramid().levelFor(context.lobe().width() / q); }
// Where even level 0 is coarser than width/q, its texels are split into sub-samples (at most 4 x 4).
int directSubdivision(Context& context, double q) {
  const int level = directLevel(context, q);
  return std::clamp(
      static_cast<int>(std::ceil(q * context.pyramid().texelAngle(level) / std::max(context.lobe().width(), 1e-12))), 1,
      4);
}

std::unique_ptr<Evaluator> buildInner(const CandidateSpec& spec, Context& context) {
  switch (spec.method) {
    case PrefilterMethod::SphericalHarmonics:
      return std::make_unique<ShEvaluator>(
          std::make_unique<detail::ShFilter>(context.pyramid(), context.lobe(), spec.shOrder));
    case PrefilterMethod::Importance:
      return std::make_unique<ImportanceEvaluator>(
          std::make_unique<detail::ImportanceSampler>(context.pyramid(), context.lobe(), spec.samples));
    case PrefilterMethod::Direct: {
      const int level = directLevel(context, spec.q), sub = directSubdivision(context, spec.q);
      const double cosCap = std::cos(context.lobe().tailAngle(spec.tail));
      return std::make_unique<DirectEvaluator>(
          std::make_unique<detail::DirectSummer>(context.pyramid(), context.lobe(), level, cosCap, sub,
                                                 context.correctedTable(context.pyramid().texelAngle(level) / sub)));
    }
    case PrefilterMethod::Reference:
      return std::make_unique<ReferenceEvaluator>(context.environment(), context.lobe());
    default:
      break;
  }
  throw Error(Error::Kind::InvalidArgument, "prefilter: no evaluator for method " + std::string(toString(spec.method)));
}

std::unique_ptr<Evaluator> build(const CandidateSpec& spec, Context& context) {
  if (spec.gridMultiple > 0) {
    const int level = directLevel(context, spec.q);
    const double cosCap = std::cos(context.lobe().tailAngle(spec.tail));
    return std::make_unique<ConvolvedGridEvaluator>(
        detail::convolvedDirectGrid(context.pyramid(), context.lobe(), level, cosCap,
                                    context.correctedTable(context.pyramid().texelAngle(level)), spec.gridMultiple));
  }
  auto inner = buildInner(spec, context);
  if (spec.gridHeight <= 0) return inner;
  return std::make_unique<GridEvaluator>(*inner, spec.gridHeight);
}

// ---- candidates and the cost model -----------------------------------------------------------

// The smallest SH order past which every |lambda_l| / lambda_0 stays below tau (up to 256).
int shOrderFor(const std::vector<double>& lambda, double tau) {
  int order = static_cast<int>(lambda.size()) - 1;
  for (int l = static_cast<int>(lambda.size()) - 1; l >= 0; --l) {
    if (std::abs(lambda[l]) > tau * std::abs(lambda[0])) break;
    order = l - 1;
  }
  return std::max(order, 0);
}

struct Workload {
  double outputPoints = 0.0;  // texels evaluated
  int threads = 1;
};

// Per-point cost and setup cost of an inner method (seconds, one core).
void innerCost(const CandidateSpec& spec, Context& context, double& perPoint, double& setup) {
  setup = 0.0;
  switch (spec.method) {
    case PrefilterMethod::SphericalHarmonics: {
      const int n = shCount(spec.shOrder);
      const auto& level = context.pyramid().level(context.pyramid().levelFor(kPi / (4.0 * (spec.shOrder + 1))));
      perPoint = n * kShPerCoefficient;
      setup = (static_cast<double>(level.width) * level.height * (spec.shOrder + 1) * 2.0 + level.height * 8.0 * n) *
              kShProjectPerCoefficient;
      break;
    }
    case PrefilterMethod::Importance:
      perPoint = spec.samples * kImportancePerSample;
      break;
    case PrefilterMethod::Direct: {
      const detail::DirectSummer summer(context.pyramid(), context.lobe(), directLevel(context, spec.q),
                                        std::cos(context.lobe().tailAngle(spec.tail)),
                                        directSubdivision(context, spec.q), nullptr);
      perPoint = summer.texelsPerAxis() * kDirectPerSample;
      break;
    }
    default:
      perPoint = 0.0;
  }
}

// Fills in the grid, predicted seconds and the detail text; false if the grid would not pay.
bool finishSpec(CandidateSpec& spec, Context& context, const Workload& work) {
  double perPoint = 0.0, setup = 0.0;
  innerCost(spec, context, perPoint, setup);
  const double direct = setup + work.outputPoints * perPoint;
  double seconds = direct;
  if (spec.gridPerWidth > 0) {
    const double rows = std::ceil(spec.gridPerWidth * kPi / std::max(context.lobe().width(), 1e-9) / 2.0) * 2.0;
    if (rows > 4096) return false;
    spec.gridHeight = std::max(8, static_cast<int>(rows));
    double gridPerPoint = perPoint;
    if (spec.method == PrefilterMethod::Direct && directSubdivision(context, spec.q) == 1) {
      // The direct sum by row convolutions: the grid is a power-of-two multiple of the level's rows
      // (the nearest to the rows asked for, at least 1), and a texel costs a vectorised multiply-add.
      const int levelRows = context.pyramid().level(directLevel(context, spec.q)).height;
      // Its planar copy of the level holds 6 floats per texel: up to 4096 x 2048 texels (200 MB).
      if (levelRows > 2048) return false;
      spec.gridMultiple = 1 << std::max(0, static_cast<int>(std::lround(std::log2(rows / levelRows))));
      spec.gridHeight = levelRows * spec.gridMultiple;
      if (spec.gridHeight > 4096) return false;
      gridPerPoint = perPoint / kDirectPerSample * kConvolvedPerSample;
    }
    const double gridPoints = 2.0 * spec.gridHeight * static_cast<double>(spec.gridHeight);
    seconds = setup + gridPoints * gridPerPoint + work.outputPoints * kGridLookup;
    if (seconds > 0.7 * direct) return false;
  }
  spec.predicted = seconds / work.threads;
  std::ostringstream detail;
  switch (spec.method) {
    case PrefilterMethod::SphericalHarmonics:
      detail << "order " << spec.shOrder << " (" << shCount(spec.shOrder) << " coefficients)";
      break;
    case PrefilterMethod::Importance:
      detail << spec.samples << " samples";
      break;
    case PrefilterMethod::Direct: {
      const int level = directLevel(context, spec.q);
      const auto& L = context.pyramid().level(level);
      detail << "level " << level << " (" << L.width << "x" << L.height << ", q " << spec.q << "), tail " << spec.tail;
      if (const int sub = directSubdivision(context, spec.q); sub > 1)
        detail << ", " << sub << "x" << sub << " per texel";
      break;
    }
    default:
      break;
  }
  if (spec.gridHeight > 0) detail << ", via a " << 2 * spec.gridHeight << "x" << spec.gridHeight << " grid";
  if (spec.gridMultiple > 0) detail << " (row convolutions)";
  spec.detail = detail.str();
  return true;
}

std::vector<CandidateSpec> candidatesFor(const PrefilterOptions& options, Context& context, const Workload& work) {
  std::vector<CandidateSpec> specs;
  const PrefilterMethod m = options.method;
  auto want = [&](PrefilterMethod method) { return m == PrefilterMethod::Auto || m == method; };
  const bool fixed = options.shOrder > 0 || options.importanceSamples > 0 || options.directTexelsPerWidth > 0.0;
  if (want(PrefilterMethod::SphericalHarmonics)) {
    std::vector<int> orders;
    if (options.shOrder > 0) {
      orders.push_back(options.shOrder);
    } else if (!fixed) {
      const auto& lambda = context.zonal(256);
      if (context.lobe().kind() == LobeKind::Irradiance) orders.push_back(2);
      for (double tau : {3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5}) {
        const int order = shOrderFor(lambda, tau);
        if (order <= 128 && (orders.empty() || order > orders.back())) orders.push_back(order);
      }
    }
    for (int order : orders) {
      CandidateSpec spec = makeSpec(PrefilterMethod::SphericalHarmonics, order);
      const auto& lambda = context.zonal(256);
      for (std::size_t l = order + 1; l < lambda.size(); ++l)
        spec.shTail = std::max(spec.shTail, std::abs(lambda[l] / lambda[0]));
      specs.push_back(spec);
    }
  }
  if (want(PrefilterMethod::Direct)) {
    if (options.directTexelsPerWidth > 0.0) {
      specs.push_back(makeSpec(PrefilterMethod::Direct, 0, 0, options.directTexelsPerWidth, 1e-6));
    } else if (!fixed) {
      // q = 1 (texels as wide as the lobe, 1e-3 of its mass left out) trades accuracy for a quarter
      // of q = 2's texels: loose bounds on narrow lobes.
      specs.push_back(makeSpec(PrefilterMethod::Direct, 0, 0, 1.0, 1e-3));
      specs.push_back(makeSpec(PrefilterMethod::Direct, 0, 0, 2.0, 1e-4));
      specs.push_back(makeSpec(PrefilterMethod::Direct, 0, 0, 4.0, 1e-5));
      specs.push_back(makeSpec(PrefilterMethod::Direct, 0, 0, 8.0, 1e-6));
    }
  }
  if (want(PrefilterMethod::Importance)) {
    if (options.importanceSamples > 0) {
      specs.push_back(makeSpec(PrefilterMethod::Importance, 0, options.importanceSamples));
    } else if (!fixed) {
      for (int samples : {64, 256, 1024}) specs.push_back(makeSpec(PrefilterMethod::Importance, 0, samples));
    }
  }
  // Each configuration evaluated at the output texels, or on a grid of 4 or 8 points per lobe
  // width and interpolated, where that is cheaper.
  std::vector<CandidateSpec> all;
  for (const auto& spec : specs) {
    for (int grid : {0, 4, 8}) {
      if (grid > 0 && !options.interpolate) continue;
      CandidateSpec variant = spec;
      variant.gridPerWidth = grid;
      if (finishSpec(variant, context, work)) all.push_back(variant);
    }
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const CandidateSpec& a, const CandidateSpec& b) { return a.predicted < b.predicted; });
  return all;
}

// Evaluates `evaluator` at every output texel centre.
Image evaluateOutput(const Parameterization& map, const Evaluator& evaluator, const PrefilterLobe& lobe,
                     const PrefilterOptions& options) {
  Image image(map.width(), map.height(), Rgba::Zero());
  ProgressCounter progress(options.progress, static_cast<std::size_t>(map.height()));
  tbb::parallel_for(0, map.height(), [&](int y) {
    for (int x = 0; x < map.width(); ++x) {
      const auto d = map.getDirectionFor(Vec2(x + 0.5, y + 0.5));
      if (!d) continue;
      const Rgb v = evaluator.value(prefilterAxis(*d, lobe, options));
      image.set(x, y, Rgba(v[0], v[1], v[2], map.texelCoverage(x, y)));
    }
    progress.step();
  });
  return image;
}

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

// The output map, refused above options.maxTexels unless large maps are allowed.
std::shared_ptr<const Parameterization> outputMap(const PrefilterOptions& options) {
  std::shared_ptr<const Parameterization> map(makeParameterization(options.parameterization, options.resolution));
  options.requireImageSize(map->width(), map->height());
  return map;
}

// The mirror lobe: the environment looked up over each texel's footprint (the baker's supersampling).
Image resampleMirror(const Environment& environment, const Parameterization& map, const PrefilterOptions& options,
                     PrefilterSummary& summary) {
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
  static_cast<RunOptions&>(bakeOptions) = options;
  bakeOptions.samplesPerTexel = options.mirrorSamples;
  Image image = bake(map, function, bakeOptions);
  summary.method = PrefilterMethod::Resample;
  summary.detail = std::to_string(options.mirrorSamples) + " footprint samples per texel";
  summary.exact = true;
  summary.metBound = true;
  summary.outputSeconds = secondsSince(outputStart);
  return image;
}

// The reference sum, asked for or as auto's fallback (with a note); exact by definition.
std::unique_ptr<Evaluator> useReference(Context& context, const Workload& work, PrefilterSummary& summary,
                                        const std::string& note) {
  const auto setupStart = Clock::now();
  auto evaluator = build(makeSpec(PrefilterMethod::Reference), context);
  const auto& summer = static_cast<const ReferenceEvaluator&>(*evaluator).summer;
  summary.method = PrefilterMethod::Reference;
  summary.detail = std::to_string(summer.samples()) + " input samples (" + std::to_string(summer.subdivision()) + "x" +
                   std::to_string(summer.subdivision()) + " per texel)";
  summary.exact = true;
  summary.metBound = true;
  summary.errorEstimated = false;
  summary.errorEstimate = summary.errorEstimateMax = 0.0;
  if (!note.empty()) summary.notes.push_back(note);
  PrefilterCandidate candidate{PrefilterMethod::Reference, summary.detail,
                               work.outputPoints * summer.samples() * kReferencePerSample / work.threads,
                               secondsSince(setupStart)};
  candidate.chosen = true;
  summary.candidates.push_back(candidate);
  return evaluator;
}

// Records `candidate` as the method that makes the map. Whether it met the bound is known only
// when its error was estimated.
void recordChoice(PrefilterSummary& summary, PrefilterCandidate& candidate, bool estimated) {
  candidate.chosen = true;
  summary.method = candidate.method;
  summary.detail = candidate.detail;
  summary.exact = false;
  summary.errorEstimated = estimated;
  summary.errorEstimate = estimated ? std::max(0.0, candidate.errorEstimate) : 0.0;
  summary.errorEstimateMax = estimated ? std::max(0.0, candidate.errorEstimateMax) : 0.0;
  summary.errorEstimateRms = estimated ? std::max(0.0, candidate.errorEstimateRms) : 0.0;
  summary.errorEstimateHighlight = estimated ? std::max(0.0, candidate.errorEstimateHighlight) : 0.0;
  summary.metBound = estimated && candidate.errorEstimate <= summary.maxError;
}

// Auto's memory of the candidates that failed: it skips a candidate when one already tried predicts
// it will fail: the same setting on another grid failed by more than 2x, or a coarser setting of the
// same method failed by more than the method's convergence can make up (importance sampling's error
// falls as 1/sqrt(samples), the direct sum's as 1/q^2, SH's as the lobe's coefficients beyond the
// order), with a factor 1.5 to spare.
class FailureMemory {
 public:
  explicit FailureMemory(double target) : target_(target) {}
  void add(const CandidateSpec& spec, double error) { failures_.emplace_back(spec, error); }
  double predictedError(const CandidateSpec& spec) const {
    double worst = 0.0;
    for (const auto& [tried, error] : failures_) {
      if (tried.method != spec.method) continue;
      if (tried.shOrder == spec.shOrder && tried.samples == spec.samples && tried.q == spec.q &&
          error > 2.0 * target_) {
        worst = std::max(worst, error);
      }
      if (spec.method == PrefilterMethod::Importance && spec.samples > tried.samples) {
        worst = std::max(worst, error * std::sqrt(static_cast<double>(tried.samples) / spec.samples) / 1.5);
      }
      if (spec.method == PrefilterMethod::SphericalHarmonics && spec.shOrder > tried.shOrder && tried.shTail > 0.0) {
        worst = std::max(worst, error * spec.shTail / tried.shTail / 1.5);
      }
      if (spec.method == PrefilterMethod::Direct && spec.q > tried.q) {
        worst = std::max(worst, error * (tried.q / spec.q) * (tried.q / spec.q) / 1.5);
      }
    }
    return worst;
  }

 private:
  double target_;
  std::vector<std::pair<CandidateSpec, double>> failures_;
};

// Tries the fast candidates cheapest first and returns the first whose estimated RMS error is within
// 0.8 x the bound (the margin covers the estimate's own spread), or, without estimation, the
// first. A named method that met no bound keeps its most accurate setting, with a note. Null when
// auto found nothing (the caller falls back to the reference).
std::unique_ptr<Evaluator> chooseFastMethod(Context& context, const Workload& work, const PrefilterOptions& options,
                                            PrefilterSummary& summary, std::optional<detail::ProbeSet>& probes) {
  const auto specs = candidatesFor(options, context, work);
  const bool automatic = options.method == PrefilterMethod::Auto;
  const bool estimating = options.estimateError || automatic;
  if (estimating) {
    const auto probeStart = Clock::now();
    const detail::ProbeSources sources{context.environment(), context.pyramid(), context.lobe(), context.table(),
                                       [&context](double box) { return context.correctedTable(box); }};
    probes.emplace(sources, options, context.errorFloor());
    summary.estimateSeconds += secondsSince(probeStart);
  }
  const double target = 0.8 * options.maxError;
  FailureMemory failures(target);
  std::unique_ptr<Evaluator> best;
  std::size_t bestIndex = 0;
  for (const CandidateSpec& spec : specs) {
    if (estimating && automatic) {
      if (const double predicted = failures.predictedError(spec); predicted > target) {
        summary.candidates.push_back({spec.method,
                                      spec.detail + " (skipped: predicted error " + formatG(100.0 * predicted) + " %)",
                                      spec.predicted, 0.0});
        continue;
      }
    }
    const auto setupStart = Clock::now();
    auto evaluator = build(spec, context);
    PrefilterCandidate candidate{spec.method, spec.detail, spec.predicted, secondsSince(setupStart)};
    if (estimating) {
      const auto estimateStart = Clock::now();
      const detail::ErrorEstimate e =
          detail::estimate([&](const Vec3& axis) { return evaluator->value(axis); }, *probes, target);
      candidate.errorEstimate = e.bound(), candidate.errorEstimateMax = e.worst, candidate.probes = e.probes;
      candidate.errorEstimateRms = e.rms, candidate.errorEstimateHighlight = e.highlight;
      summary.estimateSeconds += secondsSince(estimateStart);
    }
    summary.candidates.push_back(candidate);
    if (!estimating || candidate.errorEstimate <= target) {
      recordChoice(summary, summary.candidates.back(), estimating);
      return evaluator;
    }
    failures.add(spec, candidate.errorEstimate);
    if (!best || candidate.errorEstimate < summary.candidates[bestIndex].errorEstimate) {
      best = std::move(evaluator);
      bestIndex = summary.candidates.size() - 1;
    }
  }
  if (!best || automatic) return nullptr;
  recordChoice(summary, summary.candidates[bestIndex], true);
  summary.notes.push_back("no " + std::string(toString(options.method)) +
                          " setting met the error bound; used the most accurate one tried");
  return best;
}

// The probes whose reference was computed, kept to measure the finished map's lookups.
struct ProbeCheck {
  std::vector<Vec3> axes;
  std::vector<Rgb> references;
  std::vector<double> weights;
  std::vector<bool> nearBright;
  double floor = 0.0;
};

// A filtered lobe: chooses the method (reference, or the fast candidates with auto's fallback)
// and evaluates it at every output texel. `check` gets the estimate's probes.
Image filterWithLobe(detail::PrefilterInput& input, const PrefilterLobe& lobe, const Parameterization& map,
                     const PrefilterOptions& options, int threads, PrefilterSummary& summary,
                     std::optional<ProbeCheck>& check) {
  Context context(input, lobe);
  Workload work;
  work.outputPoints = static_cast<double>(map.width()) * map.height();
  work.threads = threads;
  std::unique_ptr<Evaluator> chosen;
  std::optional<detail::ProbeSet> probes;
  if (options.method == PrefilterMethod::Reference) {
    chosen = useReference(context, work, summary, "");
  } else {
    chosen = chooseFastMethod(context, work, options, summary, probes);
    if (!chosen)
      chosen =
          useReference(context, work, summary, "no fast method met the error bound; fell back to the reference sum");
  }
  if (probes && !summary.exact && probes->ready() > 0) {
    ProbeCheck c;
    c.floor = probes->floor();
    for (int p = 0; p < probes->ready(); ++p) {
      c.axes.push_back(probes->axis(p)), c.references.push_back(probes->reference(p));
      c.weights.push_back(probes->weight(p)), c.nearBright.push_back(probes->nearBright(p));
    }
    check = std::move(c);
  }
  const auto outputStart = Clock::now();
  Image image = evaluateOutput(map, *chosen, lobe, options);
  summary.outputSeconds = secondsSince(outputStart);
  return image;
}

// The map direction whose texel holds the value at `axis` (prefilterAxis inverted), or nullopt where
// a sphere map cannot look it up: a normal facing away from the view (irradiance), or the rim band.
std::optional<Vec3> mapDirectionFor(const Vec3& axis, const PrefilterLobe& lobe, const PrefilterOptions& options) {
  if (options.parameterization != ParameterizationKind::Sphere) return axis;
  const Vec3 eye = eyeToEnvironment(options).transpose() * axis;
  Vec3 r = eye;
  if (lobe.indexedByNormal()) {
    if (!(eye.z() > 1e-6)) return std::nullopt;
    r = reflect(Vec3(Vec3::UnitZ()), eye);
  }
  if (-r.z() > mapRimCos(ParameterizationKind::Sphere, options.resolution)) return std::nullopt;
  return r.normalized();
}

// The finished map as a renderer reads it: bilinear lookups at the probes against their reference, as
// the solid-angle RMS, the value-weighted RMS and the RMS over the bright sources' caps of the relative
// error, each with two standard errors to spare: lookupErrorEstimate. The probes saw the method at the
// texel centres' axes; the lookups add the texels' interpolation, which only the resolution changes
// (a sun's highlight a few texels wide, issue 22), so it is reported beside the estimate, not in it.
void measureLookups(const Image& level0, const Parameterization& map, const PrefilterLobe& lobe,
                    const PrefilterOptions& options, const ProbeCheck& check, PrefilterSummary& summary) {
  std::vector<double> squares(check.axes.size(), -1.0);
  double worst = 0.0;
  for (std::size_t p = 0; p < check.axes.size(); ++p) {
    const auto direction = mapDirectionFor(check.axes[p], lobe, options);
    if (!direction) continue;
    const double e = relativeError(sampleBilinear(level0, map, *direction).head<3>(), check.references[p], check.floor);
    squares[p] = e * e, worst = std::max(worst, e);
  }
  // Each RMS with two standard errors of its mean square to spare (self-normalised estimators), so
  // that another sample of the same directions measures less with high probability.
  auto rmsOf = [&](const std::function<double(std::size_t)>& weight) {
    double sum = 0.0, total = 0.0, spread = 0.0;
    for (std::size_t p = 0; p < squares.size(); ++p)
      if (squares[p] >= 0.0) sum += weight(p) * squares[p], total += weight(p);
    if (!(total > 0.0)) return 0.0;
    const double mean = sum / total;
    for (std::size_t p = 0; p < squares.size(); ++p)
      if (squares[p] >= 0.0) spread += weight(p) * weight(p) * (squares[p] - mean) * (squares[p] - mean);
    return std::sqrt(mean + 2.0 * std::sqrt(spread) / total);
  };
  const double rms = rmsOf([&](std::size_t p) { return check.weights[p]; });
  const double valued = rmsOf([&](std::size_t p) { return check.weights[p] * check.references[p].matrix().norm(); });
  const double near = rmsOf([&](std::size_t p) { return check.nearBright[p] ? check.weights[p] : 0.0; });
  if (!(rms > 0.0) && !(valued > 0.0)) return;
  summary.lookupErrorEstimate = std::max({rms, valued, near});
  summary.lookupErrorMax = worst;
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
  validateRun();
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

double prefilterErrorFloor(const Environment& environment, const PrefilterLobe& lobe) {
  detail::PrefilterInput input(environment);
  return std::max(1e-3 * lobe.mass() * input.meanNorm(), 1e-30);
}

PrefilterError prefilterError(const Image& result, const Image& reference, const Parameterization& map, double floor) {
  require(result.width() == map.width() && result.height() == map.height() && reference.width() == map.width() &&
              reference.height() == map.height(),
          "prefilterError: images do not match the map");
  double sum = 0.0, weight = 0.0;
  PrefilterError error;
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) {
      const double w = map.texelSolidAngle(x, y);
      if (!(w > 0.0)) continue;
      const double e = relativeError(result.at(x, y).head<3>(), reference.at(x, y).head<3>(), floor);
      sum += w * e * e;
      weight += w;
      error.max = std::max(error.max, e);
    }
  error.rms = weight > 0.0 ? std::sqrt(sum / weight) : 0.0;
  return error;
}

std::vector<Rgb> prefilterReferenceAt(const Environment& environment, const PrefilterLobe& lobe,
                                      const std::vector<Vec3>& axes, int threads) {
  require(!lobe.isMirror(), "the mirror lobe has no integral; look the environment up instead");
  requireThreadCount(threads);
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  std::vector<Rgb> values(axes.size());
  arena.execute([&] {
    const detail::ReferenceSummer summer(environment, lobe);
    tbb::parallel_for(std::size_t(0), axes.size(),
                      [&](std::size_t i) { values[i] = summer.value(axes[i].normalized()); });
  });
  return values;
}

PrefilteredMap prefilter(const Environment& environment, const PrefilterLobe& lobe, const PrefilterOptions& options) {
  detail::PrefilterInput input(environment);
  return prefilter(input, lobe, options);
}

PrefilteredMap prefilter(detail::PrefilterInput& input, const PrefilterLobe& lobe, const PrefilterOptions& options) {
  options.validate();
  const Environment& environment = input.environment();
  require(environment.map && !environment.image.empty(), "prefilter: empty environment");
  const auto start = Clock::now();
  PrefilteredMap result;
  result.map = outputMap(options);
  PrefilterSummary& summary = result.summary;
  summary.lobe = lobe.name();
  summary.maxError = options.maxError;
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    std::optional<ProbeCheck> check;
    Image level0 = lobe.isMirror()
                       ? resampleMirror(environment, *result.map, options, summary)
                       : filterWithLobe(input, lobe, *result.map, options, arena.max_concurrency(), summary, check);
    requireFiniteOutput(level0);
    const auto mipStart = Clock::now();
    result.levels = outputLevels(std::move(level0), *result.map, options.mips, options.cubeEdgeFixup);
    summary.mipSeconds = secondsSince(mipStart);
    if (check) {
      const auto lookupStart = Clock::now();
      measureLookups(result.levels[0], *result.map, lobe, options, *check, summary);
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
                                  const PrefilterOptions& options) {
  model.validate();
  if (model.elevation != LobeElevation::Constant) {
    throw Error(Error::Kind::InvalidArgument,
                name +
                    ": lobes that vary with elevation need a stack of maps over elevation "
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
  for (const auto& [exponent, weight] : terms) {
    const PrefilteredMap part = prefilter(input, PrefilterLobe::phong(exponent), run);
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

MapWriteReport writePrefilteredMap(const PrefilteredMap& map, const std::filesystem::path& path, nlohmann::json spec,
                                   CubeLayout layout, const WriteOptions& options, MipLayout mipLayout) {
  require(!map.levels.empty() && map.map, "writePrefilteredMap: nothing to write");
  if (!spec.is_object()) spec = nlohmann::json::object();
  const int count = static_cast<int>(map.levels.size());
  auto levelInfo = [&](int level) {
    MapInfo info;
    info.parameterization = map.map->kind();
    info.resolution = std::max(1, map.map->resolution() >> level);
    info.conventionVersion = kConventionVersion;
    info.spec = spec;
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
                       {"mip_levels", count}});
    if (s.lobe == "irradiance") prefilterInfo["irradiance_quantity"] = kIrradianceQuantity;
    if (!map.levelValues.empty()) info.spec["level_values"] = map.levelValues;
    return info;
  };
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
