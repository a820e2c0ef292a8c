// A material under an environment (material_under_environment.hpp): the candidates, the probes and
// their reference, the choice, the bake and the honest measure of the finished map.
#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/named_values.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/env/material_under_environment.hpp>
#include <brdfbake/io/text_io.hpp>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <map>
#include <optional>
#include <random>
#include <sstream>

#include "environment_cache.hpp"
#include "under_environment_internal.hpp"

namespace brdfbake {
namespace {
using Clock = std::chrono::steady_clock;
using detail::NormalGrid;

// Cost model (seconds on one core, measured on the development machine; only the order of the
// candidates depends on it): one importance sample (draw, mixture density, shade, trilinear lookup),
// one light, one bicubic grid lookup of a footprint sample.
constexpr double kPerSample = 250e-9;
constexpr double kPerLight = 80e-9;
constexpr double kPerGridLookup = 120e-9;

// What every candidate shares.
struct Setup {
  Setup(const Environment& environment, const Material& m, const UnderEnvironmentOptions& o, const Context& c)
      : input(environment), material(m), options(o), context(c) {}
  const Environment& input;
  const Material& material;
  const UnderEnvironmentOptions& options;
  const Context& context;
  double scale = 1.0;  // Material::lightColorPerIrradiance
  Vec3 view;
  Mat3 eyeToEnvironment, environmentToEye;
  std::shared_ptr<const detail::PreparedSplit> prepared;  // kept with the environment (environment_cache.hpp)
  double narrowest = 1.0;  // the narrowest lobe width (l) over the views' normals, radians

  ShadingGeometry geometry(const Vec3& normal) const { return {normal, view, reflect(view, normal)}; }
  const detail::EnvironmentSplit& split() const { return prepared->split; }
  const detail::LatLongPyramid& rest() const { return prepared->rest; }
};

// The narrowest reflection lobe (not the cosine) at normals from the view to the rim.
double narrowestLobe(const Setup& setup) {
  const Vec3 t = anyPerpendicular(setup.view);
  double narrowest = 1.0;
  for (double degrees : {0.0, 20.0, 40.0, 60.0, 75.0, 85.0, 89.0}) {
    const Vec3 n = std::cos(radians(degrees)) * setup.view + std::sin(radians(degrees)) * t;
    const auto lobes = setup.material.reflectionLobes(setup.geometry(n));
    for (const auto& lobe : *lobes) {
      if (lobe.shape != ReflectionLobeShape::Cosine) narrowest = std::min(narrowest, reflectionLobeWidth(lobe));
    }
  }
  return narrowest;
}

// A configuration: importance samples and grid points per lobe width (-1: every footprint sample).
struct Candidate {
  int samples = 0;
  int perWidth = 0;
  int rows = 0, columns = 0;
  double predicted = 0.0;
  std::string detail;
};

int lightSubdivision(const Setup& setup) {
  double largest = 0.0;
  for (const auto& t : setup.split().texels) largest = std::max(largest, t.angle);
  return detail::subdivisionFor(largest, setup.narrowest, 2.0, 8);
}

Candidate makeCandidate(const Setup& setup, int samples, int perWidth, double footprintSamples, int threads) {
  Candidate c;
  c.samples = samples, c.perWidth = perWidth;
  const int sub = lightSubdivision(setup);
  const double lights = static_cast<double>(setup.split().texels.size()) * sub * sub;
  const double perEvaluation = samples * kPerSample + lights * kPerLight;
  std::ostringstream detail;
  detail << samples << " samples, " << setup.split().texels.size() << " bright texels";
  if (sub > 1) detail << " (" << sub << "x" << sub << " each)";
  if (perWidth > 0) {
    // Rows from the view to the rim, perWidth per lobe width in normals (half the width in l).
    const double spacing = 0.5 * setup.narrowest / perWidth;
    c.rows = std::clamp(static_cast<int>(std::ceil(0.5 * kPi / spacing)), 8, 2048) + 1;
    c.columns = 2 * std::max(4, static_cast<int>(std::ceil(kPi / (0.5 * kPi / (c.rows - 1)))));
    const double nodes = static_cast<double>(c.rows) * c.columns;
    c.predicted = (nodes * perEvaluation + footprintSamples * kPerGridLookup) / threads;
    detail << ", grid " << c.rows << " x " << c.columns << " (" << perWidth << " per lobe width)";
  } else {
    c.predicted = footprintSamples * perEvaluation / threads;
    detail << ", at every footprint sample";
  }
  c.detail = detail.str();
  return c;
}

// From this bound on (a live preview), cheaper settings are tried too: 4 and 8 importance samples, a
// grid of 2 points per lobe width.
constexpr double kLooseBound = 0.02;

std::vector<Candidate> candidatesFor(const Setup& setup, double footprintSamples, int threads) {
  const UnderEnvironmentOptions& o = setup.options;
  const bool loose = o.maxError >= kLooseBound;
  std::vector<int> samples = o.importanceSamples > 0 ? std::vector<int>{o.importanceSamples}
                             : loose                 ? std::vector<int>{4, 8, 16, 64, 256, 1024}
                                                     : std::vector<int>{16, 64, 256, 1024};
  std::vector<int> grids = o.gridPerWidth != 0 ? std::vector<int>{o.gridPerWidth}
                           : loose             ? std::vector<int>{2, 4, 8, -1}
                                               : std::vector<int>{4, 8, -1};
  std::vector<Candidate> out;
  for (int k : samples)
    for (int g : grids) {
      Candidate c = makeCandidate(setup, k, g, footprintSamples, threads);
      // A grid finer than the footprint samples does not pay; it stays only when asked for, and
      // never above 2^24 nodes (400 MB).
      const double nodes = static_cast<double>(c.rows) * c.columns;
      if (g > 0 && ((o.gridPerWidth == 0 && nodes > footprintSamples) || nodes > 16777216.0)) continue;
      out.push_back(c);
    }
  if (out.empty()) out.push_back(makeCandidate(setup, samples.front(), -1, footprintSamples, threads));
  std::stable_sort(out.begin(), out.end(),
                   [](const Candidate& a, const Candidate& b) { return a.predicted < b.predicted; });
  return out;
}

// L_o at an eye-space normal, for one way of computing it.
class Evaluation {
 public:
  virtual ~Evaluation() = default;
  virtual Rgb at(const Vec3& normal) const = 0;
};

// Bright lights plus filtered importance sampling of the rest, at the normal itself.
class SampledEvaluation final : public Evaluation {
 public:
  SampledEvaluation(const Setup& setup, int samples)
      : setup_(setup),
        lights_(setup.input, setup.split().texels, setup.environmentToEye, lightSubdivision(setup)),
        sampler_(setup.rest(), setup.eyeToEnvironment, samples) {}
  Rgb at(const Vec3& normal) const override {
    const ShadingGeometry g = setup_.geometry(normal);
    const auto lobes = setup_.material.reflectionLobes(g);
    return setup_.scale * (lights_.sum(setup_.material, g) + sampler_.integrate(setup_.material, g, *lobes));
  }

 private:
  const Setup& setup_;
  detail::LightSet lights_;
  detail::LobeSampler sampler_;
};

// The sampled evaluation on a polar grid of normals, interpolated.
class GridEvaluation final : public Evaluation {
 public:
  GridEvaluation(const Setup& setup, const Candidate& c, const std::function<void(double)>& progress)
      : grid_(setup.view, c.rows, c.columns) {
    const SampledEvaluation sampled(setup, c.samples);
    ProgressCounter counter(progress, static_cast<std::size_t>(c.rows));
    tbb::parallel_for(0, c.rows, [&](int row) {
      setup.context.checkCancelled();
      // The pole is one normal: evaluated once.
      const int columns = row == 0 ? 1 : c.columns;
      for (int column = 0; column < columns; ++column) grid_.set(row, column, sampled.at(grid_.normal(row, column)));
      if (row == 0)
        for (int column = 1; column < c.columns; ++column) grid_.set(0, column, grid_.at(0, 0));
      counter.step();
    });
    grid_.finish();
  }
  Rgb at(const Vec3& normal) const override { return grid_.value(normal); }
  const NormalGrid& grid() const { return grid_; }

 private:
  NormalGrid grid_;
};

class ReferenceEvaluation final : public Evaluation {
 public:
  explicit ReferenceEvaluation(const Setup& setup)
      : setup_(setup), sum_(setup.input, setup.split(), setup.rest(), setup.eyeToEnvironment) {}
  Rgb at(const Vec3& normal) const override {
    return setup_.scale * sum_.value(setup_.material, setup_.geometry(normal));
  }

 private:
  const Setup& setup_;
  detail::ReferenceSum sum_;
};

std::unique_ptr<Evaluation> build(const Setup& setup, const Candidate& c, const std::function<void(double)>& progress) {
  if (c.perWidth > 0) return std::make_unique<GridEvaluation>(setup, c, progress);
  return std::make_unique<SampledEvaluation>(setup, c.samples);
}

// The map's value at a map direction: L_o at the normal the direction stands for.
class EvaluationFunction final : public MapFunction {
 public:
  EvaluationFunction(const Evaluation& evaluation, const Vec3& view) : evaluation_(evaluation), view_(view) {}
  Rgb evaluate(const Vec3& direction) const override {
    return evaluation_.at(geometryForReflection(direction.normalized(), view_).normal);
  }

 private:
  const Evaluation& evaluation_;
  Vec3 view_;
};

// The map: each texel the function at its centre when the normals of its footprint (corners) lie
// within `smoothAngle` / 2 of the centre's, where L_o is smooth enough that the centre is the
// footprint mean to second order (within (w / s)^2 / 24 for footprint w and scale s); else the mean
// over its stratified footprint samples, as the baker takes it (bakeTexel). Alpha is coverage.
Image renderOutput(const Parameterization& map, const Evaluation& evaluation, const Vec3& view, double smoothAngle,
                   int samplesPerTexel, const Context& context) {
  const EvaluationFunction function(evaluation, view);
  Image image(map.width(), map.height(), Rgba::Zero());
  ProgressCounter counter(context.progress(), static_cast<std::size_t>(map.height()));
  auto normalAt = [&](double px, double py) -> std::optional<Vec3> {
    const auto d = map.getDirectionFor(Vec2(px, py));
    if (!d) return std::nullopt;
    return geometryForReflection(d->normalized(), view).normal;
  };
  // A corner within smoothAngle / 2 of the centre in angle is within this chord |n_corner - n_centre|.
  const double chord = 2.0 * std::sin(std::min(0.25 * smoothAngle, 0.5 * kPi));
  tbb::parallel_for(0, map.height(), [&](int y) {
    std::vector<std::optional<Vec3>> top(static_cast<std::size_t>(map.width()) + 1), bottom(top.size());
    for (int x = 0; x <= map.width(); ++x) top[x] = normalAt(x, y), bottom[x] = normalAt(x, y + 1);
    for (int x = 0; x < map.width(); ++x) {
      context.checkCancelled();  // a texel of the reference sum takes milliseconds
      const auto n = normalAt(x + 0.5, y + 0.5);
      if (!n) continue;  // no direction (a cube cross's empty cells): 0, alpha 0
      bool smooth = true;
      for (const auto* corner : {&top[x], &top[x + 1], &bottom[x], &bottom[x + 1]})
        smooth = smooth && (!*corner || (**corner - *n).norm() <= chord);
      const Rgb value = smooth ? evaluation.at(*n) : bakeTexel(map, function, x, y, samplesPerTexel);
      image.set(x, y, Rgba(value[0], value[1], value[2], map.texelCoverage(x, y)));
    }
    counter.step();
  });
  return image;
}

// ---- probes ----------------------------------------------------------------------------------

struct Probe {
  Vec3 direction;  // map direction r (eye space)
  Vec3 normal;
  Rgb reference = Rgb::Zero();
  double weight = 1.0;  // value-weighted set: v / q (self-normalised); lookup set: 1
  bool highlight = false;
};

Vec3 uniformDirection(std::mt19937& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    const Vec3 d(g(rng), g(rng), g(rng));
    if (d.norm() > 1e-9) return d.normalized();
  }
}

// Probes: half uniform map directions, half drawn from a density proportional to the guide's value
// over the grid's cells (times the cells' measure in map directions, dω_r = 4 (n.v) dω_n), mixed
// with 10 % uniform; each value-weighted probe carries v / q once its reference v is known. Sphere
// maps leave out the rim band (mapRimCos).
std::vector<Probe> drawProbes(const Setup& setup, const NormalGrid& guide, int count, double rimCos) {
  std::mt19937 rng(setup.options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Probe> probes;
  // Draws are rejected only in the rim band, which leaves at least a cap of the sphere (mapRimCos), so a
  // draw is kept with a probability of at least 2.5 %: 10^4 draws per probe is a bound never reached.
  long long draws = 0;
  const long long maxDraws = 10000LL * count;
  auto keep = [&](const Vec3& r) {
    if (++draws > maxDraws) {
      throw Error(Error::Kind::Numerical, "error probes: " + std::to_string(draws) + " draws kept only " +
                                              std::to_string(probes.size()) + " of " + std::to_string(count));
    }
    if ((draws & 1023) == 0) setup.context.checkCancelled();
    return !(-r.z() > rimCos && setup.options.parameterization == ParameterizationKind::Sphere);
  };
  while (static_cast<int>(probes.size()) < count / 2) {
    const Vec3 r = uniformDirection(rng);
    if (keep(r)) probes.push_back({r, geometryForReflection(r, setup.view).normal});
  }
  const int rows = guide.rows() - 1, columns = guide.columns();
  const double dt = guide.rowSpacing(), dp = guide.columnSpacing();
  std::vector<double> cdf(static_cast<std::size_t>(rows) * columns + 1, 0.0);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < columns; ++j) {
      double v = 0.0;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) v = std::max(v, guide.at(i + a, (j + b) % columns).abs().maxCoeff());
      const double t0 = i * dt, t1 = t0 + dt;  // ∫ 4 cos sin dθ dφ over the cell
      const double measure = dp * (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0)) * 2.0;
      const std::size_t k = static_cast<std::size_t>(i) * columns + j;
      cdf[k + 1] = cdf[k] + v * measure;
    }
  const double total = cdf.back();
  const double guided = total > 0.0 ? 0.9 : 0.0;
  auto density = [&](const Vec3& n) {  // per steradian of r
    double q = (1.0 - guided) / kFourPi;
    if (guided > 0.0) {
      double theta = 0.0, phi = 0.0;
      guide.angles(n, theta, phi);
      const int i = std::min(rows - 1, static_cast<int>(theta / dt)),
                j = std::min(columns - 1, static_cast<int>(phi / dp));
      const std::size_t k = static_cast<std::size_t>(i) * columns + j;
      // Uniform in (theta, phi) within the cell: per unit dθ dφ, then per dω_r = 4 cos sin dθ dφ.
      const double perAngle = (cdf[k + 1] - cdf[k]) / total / (dt * dp);
      q += guided * perAngle / std::max(4.0 * std::cos(theta) * std::sin(theta), 1e-12);
    }
    return q;
  };
  while (static_cast<int>(probes.size()) < count) {
    Vec3 n, r;
    if (unit(rng) < guided) {
      const double u = unit(rng) * total;
      const std::size_t k =
          std::min<std::size_t>(cdf.size() - 2, std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin() - 1);
      const double theta = (static_cast<double>(k / columns) + unit(rng)) * dt;
      const double phi = (static_cast<double>(k % columns) + unit(rng)) * dp;
      n = guide.normal(0, 0) * std::cos(theta);  // v
      const Vec3 t = guide.normal(guide.rows() - 1, 0), b = guide.normal(guide.rows() - 1, columns / 4);
      n = (n + std::sin(theta) * (std::cos(phi) * t + std::sin(phi) * b)).normalized();
      r = reflect(setup.view, n);
      if (!(r.norm() > 0.5)) continue;
      r.normalize();
    } else {
      r = uniformDirection(rng);
      n = geometryForReflection(r, setup.view).normal;
    }
    if (!keep(r)) continue;
    Probe p{r, n};
    p.highlight = true;
    p.weight = 1.0 / density(n);  // times v once the reference is known
    probes.push_back(p);
  }
  return probes;
}

struct Measure {
  double lookupRms = 0.0, highlightRms = 0.0, max = 0.0, peak = 0.0;
  double lower = 0.0;  // the larger RMS with two standard errors taken off: clearly above a bound when above it
  // The largest relative error |value - reference| / reference (per channel, over the probe's largest
  // reference channel) over the probes whose reference is above kRelativeFloor x the median of the
  // uniform probes' references: the error where the picture is dim, which an RMS relative to a sun's
  // highlight cannot see. A maximum only grows with more probes: above a bound is clearly above it.
  double relative = 0.0, median = 0.0;
  double bound() const { return std::max(lookupRms, highlightRms); }
};
constexpr double kRelativeFloor = 0.01;

// The largest relative error of `values` at the probes above kRelativeFloor x the uniform probes' median.
void measureRelative(const std::vector<Probe>& probes, const std::vector<Rgb>& values, Measure& m) {
  std::vector<double> uniform;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!probes[i].highlight) uniform.push_back(probes[i].reference.abs().maxCoeff());
  if (uniform.empty()) return;
  std::nth_element(uniform.begin(), uniform.begin() + uniform.size() / 2, uniform.end());
  m.median = uniform[uniform.size() / 2];
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double v = probes[i].reference.abs().maxCoeff();
    if (v > kRelativeFloor * m.median && v > 0.0)
      m.relative = std::max(m.relative, (values[i] - probes[i].reference).abs().maxCoeff() / v);
  }
}

// The errors of `values` (one per probe) against the probes' reference, relative to the peak: each
// RMS as the square root of its mean square plus two standard errors (the self-normalised
// estimator's for the value-weighted set), so that another sample of the same directions measures
// less with high probability.
Measure measure(const std::vector<Probe>& probes, const std::vector<Rgb>& values) {
  Measure m;
  std::vector<double> e2(values.size());
  double lookupSum = 0.0, lookupCount = 0.0, highSum = 0.0, highWeight = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const Probe& p = probes[i];
    const double v = p.reference.abs().maxCoeff();
    m.peak = std::max(m.peak, v);
    e2[i] = (values[i] - p.reference).square().sum() / 3.0;
    worst = std::max(worst, std::sqrt(e2[i]));
    if (p.highlight) {
      highSum += p.weight * v * e2[i], highWeight += p.weight * v;
    } else {
      lookupSum += e2[i], lookupCount += 1.0;
    }
  }
  const double lookupMean = lookupCount > 0.0 ? lookupSum / lookupCount : 0.0;
  const double highMean = highWeight > 0.0 ? highSum / highWeight : lookupMean;
  double lookupVariance = 0.0, highVariance = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const Probe& p = probes[i];
    if (p.highlight) {
      const double w = p.weight * p.reference.abs().maxCoeff();
      highVariance += w * w * (e2[i] - highMean) * (e2[i] - highMean);
    } else {
      lookupVariance += (e2[i] - lookupMean) * (e2[i] - lookupMean);
    }
  }
  const double lookupError = lookupCount > 1.0 ? std::sqrt(lookupVariance / (lookupCount - 1.0) / lookupCount) : 0.0;
  const double highError = highWeight > 0.0 ? std::sqrt(highVariance) / highWeight : lookupError;
  const double scale = m.peak > 0.0 ? 1.0 / m.peak : 1.0;
  m.lookupRms = std::sqrt(lookupMean + 2.0 * lookupError) * scale;
  m.highlightRms = std::sqrt(highMean + 2.0 * highError) * scale;
  m.lower = std::sqrt(std::max({lookupMean - 2.0 * lookupError, highMean - 2.0 * highError, 0.0})) * scale;
  m.max = worst * scale;
  measureRelative(probes, values, m);
  return m;
}

std::vector<Rgb> valuesAt(const std::vector<Probe>& probes, const std::function<Rgb(const Probe&)>& value,
                          const Context& context) {
  std::vector<Rgb> out(probes.size());
  tbb::parallel_for(std::size_t(0), probes.size(), [&](std::size_t i) {
    context.checkCancelled();
    out[i] = value(probes[i]);
  });
  return out;
}

void requireFinite(const Image& image) {
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      if (!allFinite(image.at(x, y))) {
        throw Error(Error::Kind::Numerical, "a material under an environment came out non-finite at texel (" +
                                                std::to_string(x) + ", " + std::to_string(y) + ")");
      }
}

void prepare(Setup& setup) {
  const UnderEnvironmentOptions& o = setup.options;
  setup.scale = setup.material.lightColorPerIrradiance();
  setup.view = o.view.normalized();
  setup.eyeToEnvironment = o.camera.eyeToEnvironment();
  setup.environmentToEye = setup.eyeToEnvironment.transpose();
  setup.prepared = setup.input.prepared.cache().split(setup.input, o.brightFactor, o.maxBrightTexels);
  setup.narrowest = narrowestLobe(setup);
}

// The lobe narrower than a quarter of the environment's texels: the environment holds no detail the
// lobe could resolve, so it reflects the environment as a mirror does (the sampler's lookups land at
// the finest level, bilinear), and no sum over texels can measure it (the reference subdivides a
// texel 16 x 16 at most, more coarsely than the lobe). Auto would try every candidate against a
// reference blind to the lobe: a Phong exponent of 1e7 under a 256 x 128 sky took 325 s.
bool narrowerThanTexels(const Setup& setup, double& texelAngle) {
  texelAngle = kPi / setup.rest().level(0).height;
  return setup.narrowest < 0.25 * texelAngle;
}

// The map of such a lobe: 16 importance samples of the whole environment (bright texels included:
// as point lights they would alias under a lobe narrower than them), its error not estimated.
std::unique_ptr<Evaluation> mirrorOfTheEnvironment(Setup& setup, double texelAngle, UnderEnvironmentSummary& summary) {
  const UnderEnvironmentOptions& o = setup.options;
  setup.prepared = setup.input.prepared.cache().split(setup.input, o.brightFactor, 0);
  constexpr int kSamples = 16;
  summary.brightTexels = 0, summary.brightShare = 0.0;
  summary.detail = std::to_string(kSamples) + " samples of the whole environment, as a mirror";
  summary.unestimated = "the lobe is narrower than the environment's texels";
  summary.notes.push_back("the lobe (" + formatG(degrees(setup.narrowest)) +
                          " degrees wide) is narrower than a quarter of the environment's texels (" +
                          formatG(degrees(texelAngle)) +
                          " degrees): it reflects the environment's bilinear lookups as a mirror does; its error "
                          "is not estimated, since no sum over the texels resolves the lobe");
  summary.candidates.push_back({summary.detail, 0.0, 0.0});
  summary.candidates.back().chosen = true;
  return std::make_unique<SampledEvaluation>(setup, kSamples);
}

}  // namespace

// ---- public ----------------------------------------------------------------------------------

std::string_view toString(UnderEnvironmentMethod method) {
  switch (method) {
    case UnderEnvironmentMethod::Auto:
      return "auto";
    case UnderEnvironmentMethod::Sampled:
      return "sampled";
    case UnderEnvironmentMethod::Reference:
      return "reference";
  }
  return "?";
}

UnderEnvironmentMethod parseUnderEnvironmentMethod(std::string_view name) {
  return parseByName(
      name,
      std::array{UnderEnvironmentMethod::Auto, UnderEnvironmentMethod::Sampled, UnderEnvironmentMethod::Reference},
      "method");
}

void UnderEnvironmentOptions::validate() const {
  require(resolution >= 1 && resolution <= 65536,
          "resolution must be in [1, 65536], got " + std::to_string(resolution));
  require(view.allFinite() && view.norm() > 0.0, "view must be a non-zero finite vector");
  require(parameterization != ParameterizationKind::Sphere || (view.normalized() - Vec3::UnitZ()).norm() < 1e-9,
          "a sphere map views along +z (eye space); turn the camera instead of the view");
  camera.validate();
  require(samplesPerTexel >= 1 && samplesPerTexel <= 4096, "samples per texel must be in [1, 4096]");
  require(maxError > 0.0 && maxError < 1.0,
          "max error must be in (0, 1) (0.01 is 1 % of the peak), got " + formatG(maxError));
  require(!maxRelativeError || (*maxRelativeError > 0.0 && *maxRelativeError <= 10.0),
          "max relative error must be in (0, 10] (0.03 is 3 % of each texel's value)");
  require(importanceSamples == 0 || (importanceSamples >= 8 && importanceSamples <= 1 << 20),
          "importance samples must be 0 (searched) or in [8, 2^20]");
  require(gridPerWidth == 0 || gridPerWidth == -1 || (gridPerWidth >= 2 && gridPerWidth <= 64),
          "grid points per lobe width must be 0 (searched), -1 (every footprint sample) or in [2, 64]");
  require((importanceSamples == 0 && gridPerWidth == 0) || method == UnderEnvironmentMethod::Sampled,
          "fixed importance samples or grid need the sampled method");
  require(probes >= 16 && probes <= 1 << 20, "probes must be in [16, 2^20]");
  require(std::isfinite(brightFactor) && brightFactor > 1.0, "the bright factor must be > 1");
  require(maxBrightTexels >= 0 && maxBrightTexels <= 1 << 16, "bright texels must be in [0, 65536]");
}

void requireBrdf(const Material& material) {
  const Vec3 v = Vec3::UnitZ();
  if (material.reflectionLobes({v, v, v})) return;
  throw Error(Error::Kind::InvalidArgument,
              std::string(material.model()) +
                  " has no BRDF to light with an environment: its map is hand-designed or holds one fixed "
                  "configuration (a reflectance or prefiltered mode, a mirror-direction table), not reflected "
                  "light; use a lighting-mode material (phong, blinn_phong, cook_torrance, lobes, measured with "
                  "\"method\": \"fit\")");
}

std::vector<Rgb> underEnvironmentReferenceAt(const Environment& environment, const Material& material,
                                             const std::vector<Vec3>& normals, const Vec3& view,
                                             const UnderEnvironmentOptions& options, const Context& context) {
  requireBrdf(material);
  options.camera.validate();
  Setup setup(environment, material, options, context);
  tbb::task_arena arena(context.arenaThreads());
  std::vector<Rgb> values(normals.size());
  arena.execute([&] {
    prepare(setup);
    setup.view = view.normalized();
    const ReferenceEvaluation reference(setup);
    tbb::parallel_for(std::size_t(0), normals.size(), [&](std::size_t i) {
      context.checkCancelled();
      values[i] = reference.at(normals[i].normalized());
    });
  });
  return values;
}

namespace {

// The probes, drawn once (uniform and value-weighted ones interleaved), their reference computed for the
// first `ready`; a candidate makes more ready, in doubling batches from kFirstProbes, while its error on
// them is neither clearly within the target nor clearly above it. A loose bound (a live preview) needs a
// few dozen reference sums, a tight one up to every probe.
struct ProbeBank {
  std::vector<Probe> probes;
  std::size_t ready = 0;
};
constexpr std::size_t kFirstProbes = 64;

// Draws the bank's probes, the value-weighted half guided by a coarse grid (at most 32 rows, 4 samples
// each: only a guide, whose error decides where probes go, not what they measure).
void drawBank(const Setup& setup, double rimCos, ProbeBank& bank) {
  Candidate coarse = makeCandidate(setup, 4, 2, 1.0, 1);
  coarse.rows = std::min(coarse.rows, 33), coarse.columns = std::min(coarse.columns, 128);
  const GridEvaluation guide(setup, coarse, [&](double) { setup.context.checkCancelled(); });
  std::vector<Probe> drawn = drawProbes(setup, guide.grid(), setup.options.probes, rimCos);
  const std::size_t half = static_cast<std::size_t>(setup.options.probes / 2);
  for (std::size_t i = 0; i < drawn.size(); ++i) {  // uniform and guided alternately
    const std::size_t from = i % 2 == 0 ? i / 2 : half + i / 2;
    bank.probes.push_back(drawn[std::min(from, drawn.size() - 1)]);
  }
  bank.probes.resize(drawn.size());
}

void makeReady(const Setup& setup, ProbeBank& bank, std::size_t count) {
  count = std::min(count, bank.probes.size());
  if (count <= bank.ready) return;
  const ReferenceEvaluation reference(setup);
  const std::vector<Probe> batch(bank.probes.begin() + static_cast<std::ptrdiff_t>(bank.ready),
                                 bank.probes.begin() + static_cast<std::ptrdiff_t>(count));
  const auto values = valuesAt(
      batch, [&](const Probe& p) { return reference.at(p.normal); }, setup.context);
  for (std::size_t i = 0; i < values.size(); ++i) bank.probes[bank.ready + i].reference = values[i];
  bank.ready = count;
}

// What a candidate must meet on the probes: 0.8 of each bound (the margin covers the gap between its
// point values and the finished map's lookups).
struct Targets {
  double peak = 0.0, relative = 0.0;
  bool within(const Measure& m) const { return m.bound() <= peak && m.relative <= relative; }
  bool clearlyAbove(const Measure& m) const { return m.lower > peak || m.relative > relative; }
};

// The candidate's error on the ready probes, more made ready until it is clearly within the targets,
// clearly above them, or every probe is.
Measure estimateOn(const Setup& setup, const Evaluation& evaluation, ProbeBank& bank, const Targets& target) {
  std::vector<Rgb> values;
  for (;;) {
    const std::vector<Probe> fresh(bank.probes.begin() + static_cast<std::ptrdiff_t>(values.size()),
                                   bank.probes.begin() + static_cast<std::ptrdiff_t>(bank.ready));
    const auto more = valuesAt(
        fresh, [&](const Probe& p) { return evaluation.at(p.normal); }, setup.context);
    values.insert(values.end(), more.begin(), more.end());
    const Measure m = measure(bank.probes, values);
    if (target.within(m) || target.clearlyAbove(m) || bank.ready == bank.probes.size()) return m;
    makeReady(setup, bank, 2 * bank.ready);
  }
}

// Tries the candidates cheapest first and returns the first within the targets on the probes (0.8
// maxError and 0.8 of the relative bound); without estimation the first. When none qualifies, the
// most accurate one tried (by its error over its targets), with a note.
std::unique_ptr<Evaluation> chooseCandidate(const Setup& setup, const std::vector<Candidate>& candidates,
                                            ProbeBank& bank, double rimCos, bool estimating,
                                            UnderEnvironmentSummary& summary) {
  const UnderEnvironmentOptions& o = setup.options;
  const Targets target{0.8 * o.maxError, 0.8 * o.relativeBound()};
  std::unique_ptr<Evaluation> best;
  double bestError = HUGE_VAL;
  std::size_t bestIndex = 0;
  std::map<int, bool> pointwise;  // whether the sampled values' own error is clearly too much, per sample count
  for (const Candidate& c : candidates) {
    if (estimating && bank.probes.empty()) {
      const auto drawStart = Clock::now();
      drawBank(setup, rimCos, bank);
      makeReady(setup, bank, kFirstProbes);
      summary.estimateSeconds += secondsSince(drawStart);
    }
    // A grid only interpolates its nodes' values: skip it when their own error is clearly too much (never the
    // last candidate, nor a grid asked for).
    if (estimating && c.perWidth > 0 && o.gridPerWidth == 0 && &c != &candidates.back()) {
      if (!pointwise.count(c.samples)) {
        const auto checkStart = Clock::now();
        pointwise[c.samples] =
            target.clearlyAbove(estimateOn(setup, SampledEvaluation(setup, c.samples), bank, target));
        summary.estimateSeconds += secondsSince(checkStart);
      }
      if (pointwise[c.samples]) continue;
    }
    const auto start = Clock::now();
    auto evaluation = build(setup, c, setup.context.progress());
    UnderEnvironmentCandidate record{c.detail, c.predicted, secondsSince(start)};
    bool within = !estimating;
    double overTargets = 0.0;
    if (estimating) {
      const auto estimateStart = Clock::now();
      const Measure m = estimateOn(setup, *evaluation, bank, target);
      record.errorEstimate = m.bound(), record.errorEstimateMax = m.max, record.relativeError = m.relative;
      within = target.within(m);
      overTargets = std::max(m.bound() / target.peak, m.relative / target.relative);
      summary.estimateSeconds += secondsSince(estimateStart);
    }
    summary.candidates.push_back(record);
    if (within) {
      summary.candidates.back().chosen = true;
      summary.detail = c.detail;
      return evaluation;
    }
    if (overTargets < bestError) {
      bestError = overTargets, best = std::move(evaluation), bestIndex = summary.candidates.size() - 1;
    }
  }
  const UnderEnvironmentCandidate& used = summary.candidates[bestIndex];
  summary.candidates[bestIndex].chosen = true;
  summary.detail = candidates[bestIndex].detail;
  summary.notes.push_back("no sampled setting met 0.8 x the error bounds on the probes (best " +
                          formatG(100.0 * used.errorEstimate) + " % of the peak, " +
                          formatG(100.0 * used.relativeError) + " % relative); used the most accurate one tried");
  return best;
}

// The finished map's error as a renderer reads it (bilinear lookups at the probes, relative to the
// peak), and the chosen evaluation's relative error: a texel's own value against the reference, since
// lookups between texels across a highlight's edge are relative errors of the resolution, which the
// peak measure already bounds.
void reportFinishedMap(const Setup& setup, const MaterialUnderEnvironment& result, ProbeBank& bank,
                       UnderEnvironmentSummary& summary) {
  const UnderEnvironmentOptions& options = setup.options;
  const auto measureStart = Clock::now();
  auto lookups = [&] {
    const std::vector<Probe> ready(bank.probes.begin(), bank.probes.begin() + static_cast<std::ptrdiff_t>(bank.ready));
    auto lookup = [&](const Probe& p) -> Rgb {
      return sampleBilinear(result.image, *result.map, p.direction).head<3>();
    };
    return measure(ready, valuesAt(ready, lookup, setup.context));
  };
  Measure m = lookups();
  if (m.bound() > options.maxError && bank.ready < bank.probes.size()) {  // a tighter bound from every probe
    makeReady(setup, bank, bank.probes.size());
    m = lookups();
  }
  summary.errorEstimated = true;
  summary.errorEstimate = m.bound(), summary.lookupRms = m.lookupRms, summary.highlightRms = m.highlightRms;
  summary.errorMax = m.max, summary.peak = m.peak, summary.probes = static_cast<int>(bank.ready);
  for (const auto& c : summary.candidates)
    if (c.chosen) summary.relativeError = std::max(0.0, c.relativeError);
  summary.relativeFloor = kRelativeFloor * m.median;
  const bool peakMet = summary.errorEstimate <= options.maxError;
  summary.metBound = peakMet && summary.relativeError <= options.relativeBound();
  if (!peakMet) {
    summary.notes.push_back(
        "the finished map's lookups miss the bound: its resolution limits them when the "
        "sampled values met it (raise the resolution)");
  }
  summary.estimateSeconds += secondsSince(measureStart);
}

}  // namespace

MaterialUnderEnvironment shadeUnderEnvironment(const Environment& environment, const Material& material,
                                               const UnderEnvironmentOptions& options, const Context& context) {
  options.validate();
  requireBrdf(material);
  require(environment.map && !environment.image.empty(), "an empty environment");
  const auto start = Clock::now();
  MaterialUnderEnvironment result;
  result.map =
      std::shared_ptr<const Parameterization>(makeParameterization(options.parameterization, options.resolution));
  context.requireImageSize(result.map->width(), result.map->height());
  UnderEnvironmentSummary& summary = result.summary;
  summary.material = std::string(material.model());
  summary.maxError = options.maxError;
  summary.maxRelativeError = options.relativeBound();
  Setup setup(environment, material, options, context);
  tbb::task_arena arena(context.arenaThreads());
  arena.execute([&] {
    prepare(setup);
    summary.brightTexels = static_cast<int>(setup.split().texels.size());
    summary.brightThreshold = setup.split().threshold;
    summary.brightShare = setup.split().brightShare;
    summary.setupSeconds = secondsSince(start);
    if (setup.rest().resampled()) {
      summary.notes.push_back(
          "the environment is not a power-of-two lat-long image: its rest (below the bright "
          "texels) is read resampled into one, by the map and by the reference alike");
    }
    const double rimCos = mapRimCos(options.parameterization, options.resolution);
    const double footprintSamples =
        static_cast<double>(result.map->width()) * result.map->height() * options.samplesPerTexel;
    ProbeBank bank;
    std::unique_ptr<Evaluation> evaluation;
    const bool reference = options.method == UnderEnvironmentMethod::Reference;
    bool estimating = !reference && (options.estimateError || options.method == UnderEnvironmentMethod::Auto);
    double texelAngle = 0.0;
    if (options.method == UnderEnvironmentMethod::Auto && narrowerThanTexels(setup, texelAngle)) {
      summary.method = UnderEnvironmentMethod::Sampled;
      evaluation = mirrorOfTheEnvironment(setup, texelAngle, summary);
      estimating = false;
    } else if (reference) {
      evaluation = std::make_unique<ReferenceEvaluation>(setup);
      summary.method = UnderEnvironmentMethod::Reference;
      summary.detail = "the reference sum at every footprint sample";
      summary.exact = summary.metBound = true;
    } else {
      summary.method = UnderEnvironmentMethod::Sampled;
      const auto candidates = candidatesFor(setup, footprintSamples, arena.max_concurrency());
      const auto candidateStart = Clock::now();
      evaluation = chooseCandidate(setup, candidates, bank, rimCos, estimating, summary);
      summary.outputSeconds += secondsSince(candidateStart) - summary.estimateSeconds;
    }
    const auto bakeStart = Clock::now();
    const auto* grid = dynamic_cast<const GridEvaluation*>(evaluation.get());
    // Where L_o is smooth: the grid's spacing, or an eighth of the narrowest lobe in normals.
    const double smoothAngle = grid ? grid->grid().rowSpacing() : setup.narrowest / 16.0;
    result.image = renderOutput(*result.map, *evaluation, setup.view, smoothAngle, options.samplesPerTexel, context);
    requireFinite(result.image);
    summary.outputSeconds += secondsSince(bakeStart);
    if (estimating) reportFinishedMap(setup, result, bank, summary);
  });
  summary.seconds = secondsSince(start);
  return result;
}

std::string UnderEnvironmentSummary::briefReport() const {
  std::ostringstream out;
  out << material << " under the environment by " << toString(method);
  if (!detail.empty()) out << " (" << detail << ")";
  if (exact) {
    out << ": exact";
  } else if (errorEstimated) {
    out << ": estimated error " << formatG(100.0 * errorEstimate) << " % of the peak (lookups "
        << formatG(100.0 * lookupRms) << " %, highlight " << formatG(100.0 * highlightRms) << " %; bound "
        << formatG(100.0 * maxError) << " %), " << formatG(100.0 * relativeError)
        << " % of each texel's value where above 1 % of the median (bound " << formatG(100.0 * maxRelativeError)
        << " %)" << (metBound ? "" : ", bounds NOT met");
  } else {
    out << ": error not estimated (" << unestimated << ")";
  }
  out << ", " << formatG(seconds) << " s";
  return out.str();
}

nlohmann::json UnderEnvironmentSummary::toJson() const {
  nlohmann::json candidatesJson = nlohmann::json::array();
  for (const auto& c : candidates) {
    nlohmann::json entry = {
        {"detail", c.detail}, {"predicted_seconds", c.predictedSeconds}, {"seconds", c.seconds}, {"chosen", c.chosen}};
    if (c.errorEstimate >= 0.0)
      entry["error_estimate"] = c.errorEstimate, entry["error_estimate_max"] = c.errorEstimateMax,
      entry["relative_error"] = c.relativeError;
    candidatesJson.push_back(entry);
  }
  auto estimated = [&](double value) { return errorEstimated ? nlohmann::json(value) : nlohmann::json(nullptr); };
  return {{"material", material},
          {"method", std::string(toString(method))},
          {"detail", detail},
          {"max_error", maxError},
          {"error_metric", "max(lookup RMS, value-weighted RMS), relative to the peak"},
          {"error_estimated", errorEstimated},
          {"error_estimate", estimated(errorEstimate)},
          {"lookup_rms", estimated(lookupRms)},
          {"highlight_rms", estimated(highlightRms)},
          {"error_max", estimated(errorMax)},
          {"max_relative_error", maxRelativeError},
          {"relative_error", estimated(relativeError)},
          {"relative_floor", estimated(relativeFloor)},
          {"peak", estimated(peak)},
          {"probes", probes},
          {"exact", exact},
          {"met_bound", errorEstimated || exact ? nlohmann::json(metBound) : nlohmann::json(nullptr)},
          {"not_estimated", errorEstimated || exact ? nlohmann::json(nullptr) : nlohmann::json(unestimated)},
          {"bright_texels", brightTexels},
          {"bright_threshold", brightThreshold},
          {"bright_share", brightShare},
          {"seconds", seconds},
          {"setup_seconds", setupSeconds},
          {"estimate_seconds", estimateSeconds},
          {"output_seconds", outputSeconds},
          {"candidates", candidatesJson},
          {"notes", notes}};
}

MapInfo underEnvironmentMapInfo(const MaterialUnderEnvironment& map, nlohmann::json spec) {
  if (!spec.is_object()) spec = nlohmann::json::object();
  const UnderEnvironmentSummary& s = map.summary;
  MapInfo info;
  info.parameterization = map.map->kind();
  info.resolution = map.map->resolution();
  info.conventionVersion = kConventionVersion;
  info.spec = spec;
  info.spec["under_environment"] = {
      {"material", s.material},
      {"method", std::string(toString(s.method))},
      {"detail", s.detail},
      {"max_error", s.maxError},
      {"error_metric", "max(lookup RMS, value-weighted RMS), relative to the peak"},
      {"error_estimate", s.errorEstimated ? nlohmann::json(s.errorEstimate) : nlohmann::json(nullptr)},
      {"max_relative_error", s.maxRelativeError},
      {"relative_error", s.errorEstimated ? nlohmann::json(s.relativeError) : nlohmann::json(nullptr)},
      {"exact", s.exact}};
  return info;
}

MapWriteReport writeUnderEnvironmentMap(const MaterialUnderEnvironment& map, const std::filesystem::path& path,
                                        nlohmann::json spec, CubeLayout layout, const WriteOptions& options) {
  require(map.map && !map.image.empty(), "writeUnderEnvironmentMap: nothing to write");
  return writeMap(map.image, underEnvironmentMapInfo(map, std::move(spec)), path, layout, options);
}

}  // namespace brdfbake
