#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/core/error.hpp>

#include <random>

namespace brdfbake {

ErrorStats measureLookupError(const std::function<Rgb(const Vec3&)>& lookup, const MapFunction& exact,
                              const ErrorOptions& options, double rimCos, bool visibleSphere) {
  require(options.samples >= 1, "error measurement needs at least one sample");
  std::mt19937 rng(options.seed);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  struct Accumulator {
    double sumSquares = 0.0, worst = 0.0;
    int count = 0;
  } uniformSet, visibleSet;
  double peak = 0.0;
  auto add = [&](Accumulator& acc, const Vec3& r) {
    const Rgb truth = exact.evaluate(r);
    const Rgb error = lookup(r) - truth;
    peak = std::max(peak, truth.abs().maxCoeff());
    acc.sumSquares += error.square().sum() / 3.0;
    acc.worst = std::max(acc.worst, error.abs().maxCoeff());
    ++acc.count;
  };
  while (uniformSet.count < options.samples) {
    const Vec3 g(gauss(rng), gauss(rng), gauss(rng));
    if (g.norm() == 0.0) continue;
    const Vec3 r = g.normalized();
    if (-r.z() > rimCos) continue;
    add(uniformSet, r);
  }
  if (visibleSphere) {
    while (visibleSet.count < options.samples) {
      const double x = uniform(rng), y = uniform(rng);
      const double rho2 = x * x + y * y;
      if (rho2 >= 1.0) continue;
      const double nz = std::sqrt(1.0 - rho2);
      const Vec3 r(2 * nz * x, 2 * nz * y, 2 * nz * nz - 1);
      if (-r.z() > rimCos) continue;
      add(visibleSet, r);
    }
  }
  ErrorStats stats;
  stats.peak = peak;
  const double scale = peak > 0.0 ? 1.0 / peak : 1.0;
  stats.rms = std::sqrt(uniformSet.sumSquares / uniformSet.count) * scale;
  stats.max = uniformSet.worst * scale;
  stats.visibleRms = visibleSet.count > 0 ? std::sqrt(visibleSet.sumSquares / visibleSet.count) * scale : stats.rms;
  return stats;
}

ErrorStats measureMapError(const Image& image, const Parameterization& map, const MapFunction& exact,
                           const ErrorOptions& options) {
  const bool sphere = map.kind() == ParameterizationKind::Sphere;
  // Rim exclusion for sphere maps: the angle two rim texels span, 4 sqrt(2/N) (docs/conventions.md).
  const double rimCos = sphere ? std::cos(std::min(kPi, 4.0 * std::sqrt(2.0 / map.resolution()))) : 2.0;
  return measureLookupError([&](const Vec3& r) -> Rgb { return sampleBilinear(image, map, r).head<3>(); }, exact, options,
                            rimCos, sphere && options.visibleSphere);
}

}  // namespace brdfbake
