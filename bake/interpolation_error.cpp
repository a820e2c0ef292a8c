#include <brdfbake/bake/interpolation_error.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/sphere_map.hpp>

namespace brdfbake {
namespace {

double angleDegrees(const Vec3& a, const Vec3& b) {
  if (!(a.norm() > 0.0) || !(b.norm() > 0.0)) return 180.0;  // a degenerate (zero) lookup
  return degrees(std::atan2(a.cross(b).norm(), a.dot(b)));
}

}  // namespace

double triangleInterpolationError(InterpolationScheme scheme, const std::array<Vec3, 3>& normals, int steps) {
  require(steps >= 1, "steps must be >= 1");
  const Vec3 view = Vec3::UnitZ();
  std::array<Vec3, 3> reflected;
  std::array<Vec2, 3> st;
  for (int i = 0; i < 3; ++i) {
    reflected[i] = reflect(view, Vec3(normals[i].normalized()));
    st[i] = SphereMap::textureCoordinates(reflected[i]);
  }
  double worst = 0.0;
  for (int i = 0; i <= steps; ++i) {
    for (int j = 0; i + j <= steps; ++j) {
      const double a = double(i) / steps, b = double(j) / steps, c = 1.0 - a - b;
      const Vec3 normal = (a * normals[0] + b * normals[1] + c * normals[2]).normalized();
      const Vec3 exact = reflect(view, normal);
      const Vec3 looked = scheme == InterpolationScheme::ReflectedVector
                              ? Vec3(a * reflected[0] + b * reflected[1] + c * reflected[2])
                              : SphereMap::direction(a * st[0] + b * st[1] + c * st[2]);
      worst = std::max(worst, angleDegrees(looked, exact));
    }
  }
  return worst;
}

std::vector<InterpolationPoint> interpolationSweep(const std::vector<double>& sizes,
                                                   const std::vector<double>& places) {
  std::vector<InterpolationPoint> out;
  for (double size : sizes) {
    for (double place : places) {
      InterpolationPoint p{size, place, 0.0, 0.0};
      const Vec3 centre(std::sin(radians(place)), 0.0, std::cos(radians(place)));
      const Vec3 u = Vec3::UnitY(), w = centre.cross(u);
      // Equilateral triangle of normals `size` degrees apart: vertices at angular radius size/sqrt 3.
      const double radius = radians(size) / std::sqrt(3.0);
      for (int k = 0; k < 12; ++k) {  // orientations
        std::array<Vec3, 3> normals;
        for (int v = 0; v < 3; ++v) {
          const double phi = kTwoPi * (k / 36.0 + v / 3.0);
          normals[v] =
              (std::cos(radius) * centre + std::sin(radius) * (std::cos(phi) * u + std::sin(phi) * w)).normalized();
        }
        p.sphereMapError =
            std::max(p.sphereMapError, triangleInterpolationError(InterpolationScheme::SphereMapCoordinates, normals));
        p.reflectedVectorError =
            std::max(p.reflectedVectorError, triangleInterpolationError(InterpolationScheme::ReflectedVector, normals));
      }
      out.push_back(p);
    }
  }
  return out;
}

void LineExperimentOptions::validate() const {
  require(viewer.allFinite() && viewer.y() >= 1e-6 && viewer.cwiseAbs().maxCoeff() <= 1e6,
          "the viewer must lie above the surface (y in [1e-6, 1e6], |x| and |z| <= 1e6), got (" +
              std::to_string(viewer.x()) + ", " + std::to_string(viewer.y()) + ", " + std::to_string(viewer.z()) + ")");
  require(std::isfinite(segment) && segment > 0.0 && segment <= 20.0,
          "segment must be in (0, 20], got " + std::to_string(segment));
  require(samples >= 2 && samples <= 10'000'000, "samples must be in [2, 1e7], got " + std::to_string(samples));
}

LineExperiment planarLineExperiment(const Vec3& viewer, double segment, int samples) {
  return planarLineExperiment(LineExperimentOptions{viewer, segment, samples});
}

LineExperiment planarLineExperiment(const LineExperimentOptions& options) {
  options.validate();
  const Vec3& viewer = options.viewer;
  const double segment = options.segment;
  const int samples = options.samples;
  const Vec3 normal = Vec3::UnitY();
  auto reflectedAt = [&](double x) { return reflect(Vec3((viewer - Vec3(x, 0, 0)).normalized()), normal); };
  LineExperiment result;
  for (int i = 0; i < samples; ++i) {
    const double x = -10.0 + 20.0 * i / (samples - 1);
    double x0 = -10.0 + std::floor((x + 10.0) / segment) * segment;
    if (x0 + segment > 10.0 + 1e-12) x0 = std::max(-10.0, 10.0 - segment);
    const double x1 = std::min(10.0, x0 + segment), t = (x - x0) / (x1 - x0);
    const Vec3 interpolated = (1 - t) * reflectedAt(x0) + t * reflectedAt(x1);
    const double error = angleDegrees(interpolated, reflectedAt(x));
    result.x.push_back(x);
    result.errorDegrees.push_back(error);
    if (error > result.maxError) result.maxError = error, result.maxAt = x;
  }
  return result;
}

}  // namespace brdfbake
