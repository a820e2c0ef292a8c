// Prefiltering with a filtered lobe: the evaluators of each method (direct sum, importance sampling,
// spherical harmonics, interpolation grids, the reference), the candidates and their cost model, auto's
// trial of the candidates against the error probes, and the chosen method evaluated at every texel.
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/io/text_io.hpp>

#include <tbb/parallel_for.h>

#include <chrono>
#include <map>
#include <optional>
#include <sstream>

#include "prefilter_internal.hpp"

namespace brdfbake::detail {
namespace {
using Clock = std::chrono::steady_clock;

// Cost model (seconds per operation on one core, measured on the development machine; only the
// order of candidates depends on it).
constexpr double kDirectPerSample = 5e-9;
constexpr double kShPerCoefficient = 5e-9;  // evaluation: basis and RGB dot, per coefficient
constexpr double kShProjectPerCoefficient = 2e-9;
constexpr double kImportancePerSample = 60e-9;
constexpr double kGridLookup = 80e-9;
constexpr double kConvolvedPerSample = 0.6e-9;  // direct sum on a grid by row convolutions, per grid point and texel
constexpr double kReferencePerSample = 6e-9;

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
  GridEvaluator(const Evaluator& inner, int height, const Context& run) : grid(height) {
    tbb::parallel_for(0, grid.height(), [&](int y) {
      run.checkCancelled();
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
class LobeState {
 public:
  LobeState(detail::PrefilterInput& input, const PrefilterLobe& lobe, const Context& run)
      : input_(input), lobe_(lobe), run_(run) {}
  const Context& run() const { return run_; }
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
  const Context& run_;
  std::shared_ptr<const RadialTable> table_;
  std::map<long, std::shared_ptr<const RadialTable>> corrected_;
  std::vector<double> zonal_;
};

int directLevel(LobeState& context, double q) { return context.pyramid().levelFor(context.lobe().width() / q); }
// Where even level 0 is coarser than width/q, its texels are split into sub-samples (at most 4 x 4).
int directSubdivision(LobeState& context, double q) {
  const int level = directLevel(context, q);
  return std::clamp(
      static_cast<int>(std::ceil(q * context.pyramid().texelAngle(level) / std::max(context.lobe().width(), 1e-12))), 1,
      4);
}

std::unique_ptr<Evaluator> buildInner(const CandidateSpec& spec, LobeState& context) {
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

std::unique_ptr<Evaluator> build(const CandidateSpec& spec, LobeState& context) {
  if (spec.gridMultiple > 0) {
    const int level = directLevel(context, spec.q);
    const double cosCap = std::cos(context.lobe().tailAngle(spec.tail));
    return std::make_unique<ConvolvedGridEvaluator>(
        detail::convolvedDirectGrid(context.pyramid(), context.lobe(), level, cosCap,
                                    context.correctedTable(context.pyramid().texelAngle(level)), spec.gridMultiple));
  }
  auto inner = buildInner(spec, context);
  if (spec.gridHeight <= 0) return inner;
  return std::make_unique<GridEvaluator>(*inner, spec.gridHeight, context.run());
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
void innerCost(const CandidateSpec& spec, LobeState& context, double& perPoint, double& setup) {
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
bool finishSpec(CandidateSpec& spec, LobeState& context, const Workload& work) {
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

std::vector<CandidateSpec> candidatesFor(const PrefilterOptions& options, LobeState& context, const Workload& work) {
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
                     const PrefilterOptions& options, const Context& run) {
  Image image(map.width(), map.height(), Rgba::Zero());
  ProgressCounter progress(run.progress(), static_cast<std::size_t>(map.height()));
  tbb::parallel_for(0, map.height(), [&](int y) {
    for (int x = 0; x < map.width(); ++x) {
      run.checkCancelled();  // a texel of the reference sum may take milliseconds
      const auto d = map.getDirectionFor(Vec2(x + 0.5, y + 0.5));
      if (!d) continue;
      const Rgb v = evaluator.value(prefilterAxis(*d, lobe, options));
      image.set(x, y, Rgba(v[0], v[1], v[2], map.texelCoverage(x, y)));
    }
    progress.step();
  });
  return image;
}

// The reference sum, asked for or as auto's fallback (with a note); exact by definition.
std::unique_ptr<Evaluator> useReference(LobeState& context, const Workload& work, PrefilterSummary& summary,
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
std::unique_ptr<Evaluator> chooseFastMethod(LobeState& context, const Workload& work, const PrefilterOptions& options,
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

}  // namespace

// The method for a filtered lobe, evaluated at every output texel (prefilter_internal.hpp).
Image filterWithLobe(PrefilterInput& input, const PrefilterLobe& lobe, const Parameterization& map,
                     const PrefilterOptions& options, const Context& run, int threads, PrefilterSummary& summary,
                     std::optional<ProbeCheck>& check) {
  LobeState context(input, lobe, run);
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
  Image image = evaluateOutput(map, *chosen, lobe, options, run);
  summary.outputSeconds = secondsSince(outputStart);
  return image;
}

}  // namespace brdfbake::detail
