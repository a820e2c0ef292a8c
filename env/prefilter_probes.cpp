// The probes of prefilter()'s error estimate (prefilter_internal.hpp): where they are, their reference,
// their weights, and the estimate of a candidate from them.
#include <brdfbake/core/error.hpp>
#include <brdfbake/env/prefilter.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <random>

#include "prefilter_internal.hpp"

namespace brdfbake::detail {
namespace {

Vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  Vec3 v;
  do v = Vec3(g(rng), g(rng), g(rng));
  while (v.norm() < 1e-6);
  return v.normalized();
}

// A unit direction at angle acos(c) and azimuth phi about the unit `centre`.
Vec3 aboutCentre(const Vec3& centre, double c, double phi) {
  const Vec3 t = anyPerpendicular(centre), b = centre.cross(t);
  const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
  return (s * (std::cos(phi) * t + std::sin(phi) * b) + c * centre).normalized();
}

// A uniformly random rotation (its columns an orthonormal frame about a random axis).
Mat3 randomRotation(std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Vec3 a = randomUnit(rng);
  const Vec3 t = anyPerpendicular(a);
  const double angle = kTwoPi * uniform(rng);
  const Vec3 b = std::cos(angle) * t + std::sin(angle) * a.cross(t);
  Mat3 rotate;
  rotate.col(0) = b, rotate.col(1) = a.cross(b), rotate.col(2) = a;
  return rotate;
}

// The bright sources of `level` (a sun and its surroundings, where a user looks): the texels brighter
// than 16 x the mean luminance, the brightest first, each joining the first source within 2 degrees
// (its centre the luminance-weighted mean).
std::vector<Vec3> brightSources(const LatLongLevel& level, double meanLuminance) {
  std::vector<std::pair<double, Vec3>> texels;
  for (int y = 0; y < level.height; ++y)
    for (int x = 0; x < level.width; ++x) {
      const Rgb v = level.at(x, y);
      const double luminance = 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2];
      if (luminance > 16.0 * meanLuminance)
        texels.emplace_back(luminance * level.rowSolidAngle[y], level.direction(x, y));
    }
  std::sort(texels.begin(), texels.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<Vec3> bright, sums;
  for (const auto& texel : texels) {
    const double power = texel.first;
    const Vec3& direction = texel.second;  // named, not a structured binding: clang 14 cannot capture those
    auto source = std::find_if(bright.begin(), bright.end(),
                               [&](const Vec3& c) { return c.dot(direction) >= std::cos(radians(2.0)); });
    if (source == bright.end()) {
      bright.push_back(direction), sums.push_back(power * direction);
    } else {
      Vec3& sum = sums[static_cast<std::size_t>(source - bright.begin())];
      sum += power * direction;
      *source = sum.normalized();
    }
  }
  return bright;
}

// `count` probes stratified within the caps of cosine `capCos` about the `sources` (a Fibonacci spiral,
// equal areas in the cosine, turned by `turn`): a thin ring of large errors, a sun's edge, gets its
// share of probes every time. Probe i goes to source i mod B, as the (i / B)-th of that source's points.
std::vector<Vec3> capProbes(const std::vector<Vec3>& sources, double capCos, int count, double turn) {
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  const int sourceCount = static_cast<int>(sources.size()), perSource = (count + sourceCount - 1) / sourceCount;
  std::vector<Vec3> axes;
  for (int i = 0; i < count; ++i) {
    const int k = i % sourceCount, j = i / sourceCount;
    const double c = 1.0 - (j + 0.5) / perSource * (1.0 - capCos);
    axes.push_back(aboutCentre(sources[static_cast<std::size_t>(k)], c, turn + golden * j));
  }
  return axes;
}

// Luminance x solid angle of the texels of `level` as a running sum: texel i (row-major) weighs
// cdf[i + 1] - cdf[i].
std::vector<double> luminanceCdf(const LatLongLevel& level) {
  std::vector<double> cdf(static_cast<std::size_t>(level.width) * level.height + 1, 0.0);
  for (int y = 0; y < level.height; ++y)
    for (int x = 0; x < level.width; ++x) {
      const Rgb v = level.at(x, y);
      const double luminance = std::max(0.0, 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2]);
      const std::size_t i = static_cast<std::size_t>(y) * level.width + x;
      cdf[i + 1] = cdf[i] + luminance * level.rowSolidAngle[y];
    }
  return cdf;
}

// `count` guided probes: a texel of `level` drawn (stratified) by its share of `cdf`, then a
// direction about its centre drawn from the lobe.
std::vector<Vec3> guidedProbes(const LatLongLevel& level, const std::vector<double>& cdf, const PrefilterLobe& lobe,
                               int count, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double total = cdf.back();
  std::vector<Vec3> axes;
  for (int i = 0; i < count; ++i) {
    const double u = (i + uniform(rng)) / count * total;
    const std::size_t k =
        std::min<std::size_t>(cdf.size() - 2, std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin() - 1);
    const Vec3 centre = level.direction(static_cast<int>(k % level.width), static_cast<int>(k / level.width));
    axes.push_back(aboutCentre(centre, std::cos(lobe.sampleAngle(uniform(rng))), kTwoPi * uniform(rng)));
  }
  return axes;
}

}  // namespace

double relativeError(const Rgb& value, const Rgb& reference, double floor) {
  return (value - reference).matrix().norm() / std::max(reference.matrix().norm(), floor);
}

ProbeSet::ProbeSet(const ProbeSources& sources, const PrefilterOptions& options, double floor)
    : lobe_(sources.lobe), floor_(floor) {
  const PrefilterLobe& lobe = lobe_;
  const LatLongPyramid& pyramid = sources.pyramid;
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const bool sphereIrradiance = options.parameterization == ParameterizationKind::Sphere && lobe.indexedByNormal();
  // A random rotation of a Fibonacci lattice: uniform directions, evenly spread.
  const Mat3 rotate = randomRotation(rng);
  // Guided probes: a texel drawn by its luminance x solid angle at a coarse level, then a lobe sample.
  const auto& G = pyramid.level(pyramid.levelFor(kPi / 64.0));
  const std::vector<double> cdf = luminanceCdf(G);
  const double total = cdf.back();
  // Near-bright probes: uniform in the caps of 5 degrees about the bright sources (issue 22).
  capCos_ = std::cos(radians(5.0));
  if (!sphereIrradiance && total > 0.0) bright_ = brightSources(G, total / kFourPi);
  count_ = options.probes;
  guided_ = sphereIrradiance || !(total > 0.0) ? 0 : count_ / 2;
  near_ = bright_.empty() ? 0 : guided_ / 2;
  guided_ -= near_;
  uniformCount_ = count_ - guided_ - near_;
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  std::vector<Vec3> latticeAxes;
  for (int i = 0; i < uniformCount_; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / uniformCount_, r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const Vec3 d = rotate * Vec3(r * std::cos(golden * i), r * std::sin(golden * i), z);
    latticeAxes.push_back(sphereIrradiance ? prefilterAxis(d, lobe, options) : d);
  }
  const std::vector<Vec3> guidedAxes = guidedProbes(G, cdf, lobe, guided_, rng);
  std::vector<Vec3> nearAxes;
  if (near_ > 0) nearAxes = capProbes(bright_, capCos_, near_, kTwoPi * uniform(rng));
  arrangeBatches(latticeAxes, guidedAxes, nearAxes);
  if (guided_ > 0) keepGuidedTexels(G, cdf);
  weights_.assign(axes_.size(), 1.0);
  nearBright_.assign(axes_.size(), 0);
  reference_.resize(axes_.size());
  prepareReference(sources);
}

void ProbeSet::arrangeBatches(const std::vector<Vec3>& lattice, const std::vector<Vec3>& guided,
                              const std::vector<Vec3>& near) {
  const int batchCount = count_ >= 64 ? 4 : 1;
  for (int b = 0; b < batchCount; ++b) {
    for (int i = b; i < uniformCount_; i += batchCount) axes_.push_back(lattice[static_cast<std::size_t>(i)]);
    for (int i = b; i < guided_; i += batchCount) axes_.push_back(guided[static_cast<std::size_t>(i)]);
    for (int i = b; i < near_; i += batchCount) axes_.push_back(near[static_cast<std::size_t>(i)]);
    batchEnd_.push_back(static_cast<int>(axes_.size()));
  }
}

void ProbeSet::keepGuidedTexels(const LatLongLevel& level, const std::vector<double>& cdf) {
  const double total = cdf.back();
  for (std::size_t i = 0; i + 1 < cdf.size(); ++i)
    if (const double p = cdf[i + 1] - cdf[i]; p > 0.0) {
      centres_.push_back(level.direction(static_cast<int>(i % level.width), static_cast<int>(i / level.width)));
      probability_.push_back(p / total);
    }
}

// The reference on the probes, over all but 1e-7 of the lobe's mass with the lobe tabulated to
// 1e-6 of its peak. A resampled input (not a power-of-two lat-long) under a lobe narrower than 16
// texels of the working lat-long is summed over its own texels (ReferenceSummer), not over the
// pyramid the candidates read, so the resampling error is part of the estimate. Otherwise the
// finest pyramid level needed is summed (texels <= width / 8 with the lobe corrected for their box,
// ProbeSources::correctedTable, or level 0 split into sub-samples <= width / 8): a power-of-two lat-long input is
// its pyramid's level 0 (coarser levels are exact solid-angle means of its texels), and a lobe wider than 16
// texels averages the resampling's local error away (its 2 x 2 bilinear means keep each neighbourhood's mean),
// while summing a hemisphere of input texels per probe would cost seconds.
void ProbeSet::prepareReference(const ProbeSources& sources) {
  const PrefilterLobe& lobe = lobe_;
  const LatLongPyramid& pyramid = sources.pyramid;
  table_ = sources.table;
  const double cosCap = std::cos(lobe.tailAngle(1e-7));
  if (pyramid.resampled() && lobe.width() < 16.0 * pyramid.texelAngle(0)) {
    ownTexels_.emplace(sources.environment, lobe, cosCap, table_);
  } else {
    const int level = pyramid.levelFor(lobe.width() / 8.0);
    const int sub =
        std::clamp(static_cast<int>(std::ceil(8.0 * pyramid.texelAngle(level) / std::max(lobe.width(), 1e-12))), 1, 8);
    pyramidSum_.emplace(pyramid, lobe, level, cosCap, sub,
                        sub == 1 ? sources.correctedTable(pyramid.texelAngle(level)) : table_);
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

int ProbeSet::capsHolding(const Vec3& d) const {
  int count = 0;
  for (const Vec3& centre : bright_) count += d.dot(centre) >= capCos_ ? 1 : 0;
  return count;
}

void ProbeSet::extend(int batch) {
  const int end = batchEnd(batch);
  if (end <= ready_) return;
  const double capArea = kTwoPi * (1.0 - capCos_);
  tbb::parallel_for(ready_, end, [&](int p) {
    const Vec3& d = axes_[static_cast<std::size_t>(p)];
    reference_[static_cast<std::size_t>(p)] = pyramidSum_ ? pyramidSum_->value(d) : ownTexels_->value(d);
    const int caps = bright_.empty() ? 0 : capsHolding(d);
    nearBright_[static_cast<std::size_t>(p)] = caps > 0 ? 1 : 0;
    if (guided_ > 0 || near_ > 0) {
      // The mixture's density at d: uniform, guided and near-bright draws in their proportions.
      double q = (static_cast<double>(uniformCount_) / count_) / kFourPi;
      if (guided_ > 0) q += (static_cast<double>(guided_) / count_) * guidedDensity(d);
      if (near_ > 0)
        q += (static_cast<double>(near_) / count_) * caps / (static_cast<double>(bright_.size()) * capArea);
      weights_[static_cast<std::size_t>(p)] = 1.0 / (kFourPi * q);
    }
  });
  ready_ = end;
}

namespace {

// A weighted mean square and the self-normalised estimator's standard error sqrt(Σ w^2 (e^2 - m)^2) / Σ w.
struct MeanSquare {
  double mean = 0.0, error = 0.0, weight = 0.0;
  void add(double w, double e2) { sum_ += w * e2, weight += w; }
  void finish() { mean = weight > 0.0 ? sum_ / weight : 0.0; }
  void addSpread(double w, double e2) { spread_ += w * w * (e2 - mean) * (e2 - mean); }
  void finishSpread() { error = weight > 0.0 ? std::sqrt(spread_) / weight : 0.0; }

 private:
  double sum_ = 0.0, spread_ = 0.0;
};

}  // namespace

ErrorEstimate estimate(const std::function<Rgb(const Vec3&)>& value, ProbeSet& probes, double target) {
  ErrorEstimate out;
  std::vector<double> errors;
  for (int b = 0; b < probes.batches(); ++b) {
    probes.extend(b);
    const int begin = out.probes, end = probes.batchEnd(b);
    errors.resize(static_cast<std::size_t>(end));
    tbb::parallel_for(begin, end, [&](int p) {
      errors[static_cast<std::size_t>(p)] = relativeError(value(probes.axis(p)), probes.reference(p), probes.floor());
    });
    for (int p = begin; p < end; ++p) out.worst = std::max(out.worst, errors[static_cast<std::size_t>(p)]);
    // Solid angle; value-weighted (weights times |reference|); uniform over the bright sources' caps.
    MeanSquare solid, valued, nearBright;
    auto each = [&](auto&& f) {
      for (int p = 0; p < end; ++p) {
        const double e = errors[static_cast<std::size_t>(p)], w = probes.weight(p);
        f(w, w * probes.reference(p).matrix().norm(), probes.nearBright(p) ? w : 0.0, e * e);
      }
    };
    each([&](double w, double v, double n, double e2) { solid.add(w, e2), valued.add(v, e2), nearBright.add(n, e2); });
    solid.finish(), valued.finish(), nearBright.finish();
    each([&](double w, double v, double n, double e2) {
      solid.addSpread(w, e2), valued.addSpread(v, e2), nearBright.addSpread(n, e2);
    });
    solid.finishSpread(), valued.finishSpread(), nearBright.finishSpread();
    out.rms = std::sqrt(solid.mean);
    out.highlight = std::sqrt(std::max(valued.mean, nearBright.mean));
    out.probes = end;
    const double targetSquare = target * target;
    const bool half = 2 * end >= probes.batchEnd(probes.batches() - 1);
    bool below = true, above = false;
    for (const MeanSquare* m : {&solid, &valued, &nearBright}) {
      if (!(m->weight > 0.0)) continue;
      below = below && m->mean + 2.0 * m->error <= targetSquare;
      above = above || m->mean - 2.0 * m->error > targetSquare;
    }
    if ((half && below) || above) break;
  }
  return out;
}

}  // namespace brdfbake::detail
