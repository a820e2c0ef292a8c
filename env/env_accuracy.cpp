#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>
#include <brdfbake/env/env_accuracy.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

namespace brdfbake {

PrefilterCheckPoints prefilterTexelSubset(const Parameterization& map, const PrefilterLobe& lobe,
                                          const PrefilterOptions& options, int count, unsigned seed) {
  require(count >= 1, "a texel subset needs at least one texel, got " + std::to_string(count));
  PrefilterCheckPoints points;
  auto add = [&](int x, int y) {
    const double omega = map.texelSolidAngle(x, y);
    if (!(omega > 0.0)) return false;
    const auto d = map.getDirectionFor(Vec2(x + 0.5, y + 0.5));
    if (!d) return false;
    points.texels.push_back({x, y});
    points.directions.push_back(d->normalized());
    points.axes.push_back(prefilterAxis(*d, lobe, options));
    points.weights.push_back(omega);
    return true;
  };
  // Small maps: every texel once (exact). Counting them costs a pass over the map only when the
  // map has no more texels than asked for.
  if (static_cast<long long>(map.width()) * map.height() <= count) {
    for (int y = 0; y < map.height(); ++y)
      for (int x = 0; x < map.width(); ++x) add(x, y);
    require(!points.texels.empty(), "the map has no texel of non-zero solid angle");
    return points;
  }
  std::mt19937 rng(seed);
  long long attempts = 0;
  while (static_cast<int>(points.texels.size()) < count) {
    const int x = static_cast<int>(rng() % map.width()), y = static_cast<int>(rng() % map.height());
    add(x, y);
    require(++attempts < 1000LL * count + 1000000, "the map has too few texels of non-zero solid angle to draw from");
  }
  return points;
}

PrefilterCheckPoints prefilterLookupSet(const Parameterization& map, const PrefilterLobe& lobe,
                                        const PrefilterOptions& options, int count, unsigned seed) {
  require(count >= 1, "a lookup set needs at least one direction, got " + std::to_string(count));
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss;
  const bool sphere = map.kind() == ParameterizationKind::Sphere;
  // The angle two rim texels span, 4 sqrt(2/N), as measureMapError skips it (docs/conventions.md).
  const double rimCos = std::cos(std::min(kPi, 4.0 * std::sqrt(2.0 / map.resolution())));
  PrefilterCheckPoints points;
  while (static_cast<int>(points.directions.size()) < count) {
    const Vec3 d = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
    if (!d.allFinite() || (sphere && -d.z() > rimCos)) continue;
    points.directions.push_back(d);
    points.axes.push_back(prefilterAxis(d, lobe, options));
    points.weights.push_back(1.0);
  }
  return points;
}

std::vector<Rgb> prefilterValuesAt(const Image& level0, const Parameterization& map,
                                   const PrefilterCheckPoints& points) {
  require(level0.width() == map.width() && level0.height() == map.height(),
          "prefilterValuesAt: the image does not match the map");
  std::vector<Rgb> values;
  values.reserve(points.size());
  if (!points.texels.empty()) {
    for (const auto& t : points.texels) values.push_back(level0.at(t[0], t[1]).head<3>());
  } else {
    for (const Vec3& d : points.directions) values.push_back(sampleBilinear(level0, map, d).head<3>());
  }
  return values;
}

PrefilterError prefilterPointsError(const std::vector<Rgb>& values, const std::vector<Rgb>& reference,
                                    const std::vector<double>& weights, double floor) {
  require(values.size() == reference.size() && values.size() == weights.size(),
          "prefilterPointsError: values, reference and weights differ in length");
  double sum = 0.0, weight = 0.0;
  PrefilterError error;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double e = (values[i] - reference[i]).matrix().norm() / std::max(reference[i].matrix().norm(), floor);
    sum += weights[i] * e * e;
    weight += weights[i];
    error.max = std::max(error.max, e);
  }
  error.rms = weight > 0.0 ? std::sqrt(sum / weight) : 0.0;
  return error;
}

std::vector<std::pair<double, Rgb>> prefilterLobeModelTerms(const LobeModel& model) {
  model.validate();
  // A Lafortune lobe (c_xy != -1) is the same radial filter looked up about its own axis a(v) with
  // the amplitude |a|^n (brdf/lobes.hpp), not about the reflected direction: not prefiltered here yet.
  require(model.allAboutMirror(),
          "the lobe model has Lafortune lobes (cxy != -1), which prefilter about their own axis, or half-vector lobes "
          "or a half-difference table, which are not radially symmetric; prefiltering supports mirror lobes only (fit "
          "with --kind mirror)");
  const Eigen::Matrix<double, 3, Eigen::Dynamic> toRgb = model.rgbWeights();
  std::map<double, Rgb> terms;
  for (std::size_t c = 0; c < model.channelCount(); ++c) {
    for (const Lobe& lobe : model.channels[c].lobes) {
      const double n = lobe.exponent[0], weight = lobe.weight[0];
      if (weight == 0.0) continue;
      auto [it, inserted] = terms.try_emplace(n, Rgb::Zero());
      it->second += weight * (n + 2.0) / (n + 1.0) * toRgb.col(static_cast<Eigen::Index>(c)).array();
    }
  }
  return {terms.begin(), terms.end()};
}

std::vector<Rgb> prefilterLobeModelReferenceAt(const Environment& environment, const LobeModel& model,
                                               const std::vector<Vec3>& axes, const Context& context) {
  require(!model.variesWithView(),
          "lobes that vary with elevation (or with a colour profile) need a stack of maps over elevation; only "
          "constant lobe models prefilter "
          "into one map");
  const auto terms = prefilterLobeModelTerms(model);
  require(!terms.empty(), "the lobe model has no lobe of non-zero weight to prefilter");
  std::vector<Rgb> sum(axes.size(), Rgb::Zero());
  for (const auto& [exponent, weight] : terms) {
    const auto part = prefilterReferenceAt(environment, PrefilterLobe::phong(exponent), axes, context);
    for (std::size_t i = 0; i < axes.size(); ++i) sum[i] += weight * part[i];
  }
  return sum;
}

double prefilterLobeModelErrorFloor(const Environment& environment, const LobeModel& model) {
  double mass = 0.0;
  for (const auto& term : prefilterLobeModelTerms(model)) mass += term.second.matrix().norm();
  // prefilterErrorFloor of a lobe of mass 1 (any normalised Phong lobe) is 1e-3 x the mean |L|.
  return std::max(prefilterErrorFloor(environment, PrefilterLobe::phong(1.0)) * mass, 1e-30);
}

}  // namespace brdfbake
