// How accurate a prefiltered map is: the finished map's lookups measured at the error probes, the
// relative error of a whole map against a reference, its floor, and the reference at given axes.
#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/brdf/material.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/env/prefilter.hpp>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <functional>
#include <optional>

#include "prefilter_internal.hpp"

namespace brdfbake {
namespace detail {
namespace {

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

}  // namespace

// The lookups' error at the probes (prefilter_internal.hpp).
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
      const double e = detail::relativeError(result.at(x, y).head<3>(), reference.at(x, y).head<3>(), floor);
      sum += w * e * e;
      weight += w;
      error.max = std::max(error.max, e);
    }
  error.rms = weight > 0.0 ? std::sqrt(sum / weight) : 0.0;
  return error;
}

std::vector<Rgb> prefilterReferenceAt(const Environment& environment, const PrefilterLobe& lobe,
                                      const std::vector<Vec3>& axes, const Context& context) {
  require(!lobe.isMirror(), "the mirror lobe has no integral; look the environment up instead");
  tbb::task_arena arena(context.arenaThreads());
  std::vector<Rgb> values(axes.size());
  arena.execute([&] {
    const detail::ReferenceSummer summer(environment, lobe);
    tbb::parallel_for(std::size_t(0), axes.size(), [&](std::size_t i) {
      context.checkCancelled();
      values[i] = summer.value(axes[i].normalized());
    });
  });
  return values;
}
}  // namespace brdfbake
