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

// ---- probes ----------------------------------------------------------------------------------

Vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  Vec3 v;
  do v = Vec3(g(rng), g(rng), g(rng));
  while (v.norm() < 1e-6);
  return v.normalized();
}

double relativeError(const Rgb& value, const Rgb& reference, double floor) {
  return (value - reference).matrix().norm() / std::max(reference.matrix().norm(), floor);
}

// The probe directions of the error estimate and, batch by batch on first use, their reference
// values and weights. Half the probes are a randomly rotated Fibonacci lattice (uniform), half are
// drawn towards the bright parts of the environment; each is weighted by (1/4pi)/q(d), q the
// mixture's density. Batch b holds the lattice points i = b mod B and the guided strata j = b mod B
// (B = 4 batches from 64 probes up), so batches 0 ... b together are a sample of the same mixture
// as all of them, and an estimate decided on the first batches pays only their reference sums.
class ProbeSet {
 public:
  ProbeSet(Context& context, const PrefilterOptions& options, double floor);
  ProbeSet(const ProbeSet&) = delete;
  ProbeSet& operator=(const ProbeSet&) = delete;
  int batches() const { return static_cast<int>(batchEnd_.size()); }
  // Probes [0, batchEnd(b)) are batches 0 ... b.
  int batchEnd(int batch) const { return batchEnd_[static_cast<std::size_t>(batch)]; }
  // Computes the reference and weight of every probe of batches 0 ... `batch` not yet computed.
  void extend(int batch);
  const Vec3& axis(int p) const { return axes_[static_cast<std::size_t>(p)]; }
  const Rgb& reference(int p) const { return reference_[static_cast<std::size_t>(p)]; }
  double weight(int p) const { return weights_[static_cast<std::size_t>(p)]; }
  double floor() const { return floor_; }

 private:
  // The mixture's density at d relative to the uniform density's, over the guided texels within
  // the lobe's support of d (the tabulated lobe is exactly zero beyond it).
  double guidedDensity(const Vec3& d) const;
  PrefilterLobe lobe_;
  double floor_ = 0.0;
  std::vector<Vec3> axes_;
  std::vector<double> weights_;
  std::vector<Rgb> reference_;
  std::vector<int> batchEnd_;
  int ready_ = 0, count_ = 0, uniformCount_ = 0, guided_ = 0;
  // Guided draws: the bright texels' centres and their probabilities (luminance x solid angle, summing to 1).
  std::vector<Vec3> centres_;
  std::vector<double> probability_;
  std::shared_ptr<const RadialTable> table_;
  std::optional<detail::DirectSummer> pyramidSum_;
  std::optional<detail::ReferenceSummer> ownTexels_;
};

ProbeSet::ProbeSet(Context& context, const PrefilterOptions& options, double floor)
    : lobe_(context.lobe()), floor_(floor) {
  const PrefilterLobe& lobe = lobe_;
  const LatLongPyramid& pyramid = context.pyramid();
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const bool sphereIrradiance = options.parameterization == ParameterizationKind::Sphere && lobe.indexedByNormal();
  // A random rotation of a Fibonacci lattice: uniform directions, evenly spread.
  Mat3 rotate;
  {
    const Vec3 a = randomUnit(rng);
    const Vec3 t = anyPerpendicular(a);
    const double angle = kTwoPi * uniform(rng);
    const Vec3 b = std::cos(angle) * t + std::sin(angle) * a.cross(t);
    rotate.col(0) = b, rotate.col(1) = a.cross(b), rotate.col(2) = a;
  }
  // Guided probes: a texel drawn by its luminance x solid angle at a coarse level, then a lobe sample.
  const int guidedLevel = pyramid.levelFor(kPi / 64.0);
  const auto& G = pyramid.level(guidedLevel);
  std::vector<double> cdf(static_cast<std::size_t>(G.width) * G.height + 1, 0.0);
  for (int y = 0; y < G.height; ++y)
    for (int x = 0; x < G.width; ++x) {
      const Rgb v = G.at(x, y);
      const double luminance = std::max(0.0, 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2]);
      const std::size_t i = static_cast<std::size_t>(y) * G.width + x;
      cdf[i + 1] = cdf[i] + luminance * G.rowSolidAngle[y];
    }
  const double total = cdf.back();
  count_ = options.probes;
  guided_ = sphereIrradiance || !(total > 0.0) ? 0 : count_ / 2;
  uniformCount_ = count_ - guided_;
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  auto lattice = [&](int i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / uniformCount_, r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const Vec3 d = rotate * Vec3(r * std::cos(golden * i), r * std::sin(golden * i), z);
    return sphereIrradiance ? prefilterAxis(d, lobe, options) : d;
  };
  std::vector<Vec3> guidedAxes;
  for (int i = 0; i < guided_; ++i) {
    const double u = (i + uniform(rng)) / guided_ * total;
    const std::size_t k =
        std::min<std::size_t>(cdf.size() - 2, std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin() - 1);
    const Vec3 centre = G.direction(static_cast<int>(k % G.width), static_cast<int>(k / G.width));
    const double theta = lobe.sampleAngle(uniform(rng)), phi = kTwoPi * uniform(rng);
    const Vec3 t = anyPerpendicular(centre), b = centre.cross(t);
    guidedAxes.push_back(
        (std::sin(theta) * (std::cos(phi) * t + std::sin(phi) * b) + std::cos(theta) * centre).normalized());
  }
  const int batchCount = count_ >= 64 ? 4 : 1;
  for (int b = 0; b < batchCount; ++b) {
    for (int i = b; i < uniformCount_; i += batchCount) axes_.push_back(lattice(i));
    for (int i = b; i < guided_; i += batchCount) axes_.push_back(guidedAxes[static_cast<std::size_t>(i)]);
    batchEnd_.push_back(static_cast<int>(axes_.size()));
  }
  if (guided_ > 0) {
    for (std::size_t i = 0; i + 1 < cdf.size(); ++i)
      if (const double p = cdf[i + 1] - cdf[i]; p > 0.0) {
        centres_.push_back(G.direction(static_cast<int>(i % G.width), static_cast<int>(i / G.width)));
        probability_.push_back(p / total);
      }
  }
  weights_.assign(axes_.size(), 1.0);
  reference_.resize(axes_.size());
  // The reference on the probes, over all but 1e-7 of the lobe's mass with the lobe tabulated to
  // 1e-6 of its peak. A resampled input (not a power-of-two lat-long) under a lobe narrower than 16
  // texels of the working lat-long is summed over its own texels (ReferenceSummer), not over the
  // pyramid the candidates read, so the resampling error is part of the estimate. Otherwise the
  // finest pyramid level needed is summed (texels <= width / 8 with the lobe corrected for their box,
  // Context::correctedTable, or level 0 split into sub-samples <= width / 8): a power-of-two lat-long input is its
  // pyramid's level 0 (coarser levels are exact solid-angle means of its texels), and a lobe wider than 16 texels
  // averages the resampling's local error away (its 2 x 2 bilinear means keep each neighbourhood's mean), while summing
  // a hemisphere of input texels per probe would cost seconds.
  table_ = context.table();
  const double cosCap = std::cos(lobe.tailAngle(1e-7));
  if (pyramid.resampled() && lobe.width() < 16.0 * pyramid.texelAngle(0)) {
    ownTexels_.emplace(context.environment(), lobe, cosCap, table_);
  } else {
    const int level = pyramid.levelFor(lobe.width() / 8.0);
    const int sub =
        std::clamp(static_cast<int>(std::ceil(8.0 * pyramid.texelAngle(level) / std::max(lobe.width(), 1e-12))), 1, 8);
    pyramidSum_.emplace(pyramid, lobe, level, cosCap, sub,
                        sub == 1 ? context.correctedTable(pyramid.texelAngle(level)) : table_);
  }
}

double ProbeSet::guidedDensity(const Vec3& d) const {
  const RadialTable::View weight = table_->view();
  // u = sin(theta / 2) = sqrt((1 - c) / 2) beyond maxU is outside the table's support: c < 1 - 2 maxU^2.
  const double cosSupport = 1.0 - 2.0 * table_->maxU() * table_->maxU();
  double density = 0.0;
  for (std::size_t i = 0; i < centres_.size(); ++i) {
    const double c = d.dot(centres_[i]);
    if (c >= cosSupport) density += probability_[i] * weight(std::sqrt(std::max(0.0, 0.5 - 0.5 * c)));
  }
  return density / lobe_.mass();
}

void ProbeSet::extend(int batch) {
  const int end = batchEnd(batch);
  if (end <= ready_) return;
  tbb::parallel_for(ready_, end, [&](int p) {
    const Vec3& d = axes_[static_cast<std::size_t>(p)];
    reference_[static_cast<std::size_t>(p)] = pyramidSum_ ? pyramidSum_->value(d) : ownTexels_->value(d);
    if (guided_ > 0) {
      const double q = (static_cast<double>(uniformCount_) / count_) / kFourPi +
                       (static_cast<double>(guided_) / count_) * guidedDensity(d);
      weights_[static_cast<std::size_t>(p)] = 1.0 / (kFourPi * q);
    }
  });
  ready_ = end;
}

struct ErrorEstimate {
  double rms = 0.0, worst = 0.0;
  int probes = 0;
};

// The evaluator's weighted RMS relative error on the probes, batch by batch: it stops at the first
// batch after which the mean square m lies more than twice its standard error above target^2, or
// below it once at least half the probes are read, and otherwise reads every probe. The standard
// error is the self-normalised estimator's, sqrt(Σ w^2 (e^2 - m)^2) / Σ w. On the 1024 x 512 sky's
// gloss chain the first 128 probes put one level's error at 0.35 % where all 512 put it at 0.50 %
// (2 standard errors: the sun's rare large errors are easily missed), while 256 probes were within
// 6 % of all 512 at every candidate tried, so a candidate is accepted only from half the probes on.
ErrorEstimate estimate(const Evaluator& evaluator, ProbeSet& probes, double target) {
  ErrorEstimate out;
  std::vector<double> errors;
  for (int b = 0; b < probes.batches(); ++b) {
    probes.extend(b);
    const int begin = out.probes, end = probes.batchEnd(b);
    errors.resize(static_cast<std::size_t>(end));
    tbb::parallel_for(begin, end, [&](int p) {
      errors[static_cast<std::size_t>(p)] =
          relativeError(evaluator.value(probes.axis(p)), probes.reference(p), probes.floor());
    });
    double sum = 0.0, weights = 0.0;
    for (int p = 0; p < end; ++p) {
      const double e = errors[static_cast<std::size_t>(p)];
      sum += probes.weight(p) * e * e, weights += probes.weight(p);
      out.worst = std::max(out.worst, e);
    }
    const double meanSquare = weights > 0.0 ? sum / weights : 0.0;
    double variance = 0.0;
    for (int p = 0; p < end; ++p) {
      const double e = errors[static_cast<std::size_t>(p)], w = probes.weight(p);
      variance += w * w * (e * e - meanSquare) * (e * e - meanSquare);
    }
    variance = weights > 0.0 ? variance / (weights * weights) : 0.0;
    out.rms = std::sqrt(meanSquare);
    out.probes = end;
    const double spread = 2.0 * std::sqrt(variance), targetSquare = target * target;
    const bool half = 2 * end >= probes.batchEnd(probes.batches() - 1);
    if ((half && meanSquare + spread <= targetSquare) || meanSquare - spread > targetSquare) break;
  }
  return out;
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
                                            PrefilterSummary& summary) {
  const auto specs = candidatesFor(options, context, work);
  const bool automatic = options.method == PrefilterMethod::Auto;
  const bool estimating = options.estimateError || automatic;
  std::optional<ProbeSet> probes;
  if (estimating) {
    const auto probeStart = Clock::now();
    probes.emplace(context, options, context.errorFloor());
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
      const ErrorEstimate e = estimate(*evaluator, *probes, target);
      candidate.errorEstimate = e.rms, candidate.errorEstimateMax = e.worst, candidate.probes = e.probes;
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

// A filtered lobe: chooses the method (reference, or the fast candidates with auto's fallback)
// and evaluates it at every output texel.
Image filterWithLobe(detail::PrefilterInput& input, const PrefilterLobe& lobe, const Parameterization& map,
                     const PrefilterOptions& options, int threads, PrefilterSummary& summary) {
  Context context(input, lobe);
  Workload work;
  work.outputPoints = static_cast<double>(map.width()) * map.height();
  work.threads = threads;
  std::unique_ptr<Evaluator> chosen;
  if (options.method == PrefilterMethod::Reference) {
    chosen = useReference(context, work, summary, "");
  } else {
    chosen = chooseFastMethod(context, work, options, summary);
    if (!chosen)
      chosen =
          useReference(context, work, summary, "no fast method met the error bound; fell back to the reference sum");
  }
  const auto outputStart = Clock::now();
  Image image = evaluateOutput(map, *chosen, lobe, options);
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
  validateRun();
}

std::string PrefilterSummary::briefReport() const {
  std::ostringstream out;
  out << lobe << " by " << toString(method);
  if (!detail.empty()) out << " (" << detail << ")";
  if (exact) {
    out << ": exact";
  } else if (errorEstimated) {
    out << ": estimated RMS relative error " << formatG(100.0 * errorEstimate) << " % (bound "
        << formatG(100.0 * maxError) << " %" << (metBound ? "" : ", NOT met") << ")";
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
    Image level0 = lobe.isMirror()
                       ? resampleMirror(environment, *result.map, options, summary)
                       : filterWithLobe(input, lobe, *result.map, options, arena.max_concurrency(), summary);
    requireFiniteOutput(level0);
    const auto mipStart = Clock::now();
    result.levels = outputLevels(std::move(level0), *result.map, options.mips, options.cubeEdgeFixup);
    summary.mipSeconds = secondsSince(mipStart);
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
