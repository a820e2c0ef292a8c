#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/paraboloid_map.hpp>

#include "disc_region.hpp"

namespace brdfbake {
namespace {

// Stereographic density 4 / (1 + r^2)^2: h(R) = 2 R^2 / (1 + R^2), h/r^2 = 2 / (1 + r^2), and
// ∫ 2 d / (1 + d^2 + s^2) ds = 2 d / sqrt(1 + d^2) atan(s / sqrt(1 + d^2)).
constexpr detail::RadialDensity kParaboloidSolidAngle{[](double d, double s0, double s1) {
                                                        const double w = std::sqrt(1.0 + d * d);
                                                        return 2.0 * d / w * (std::atan(s1 / w) - std::atan(s0 / w));
                                                      },
                                                      1.0};

struct HalfSquare {
  double x0, x1, y0, y1;
};
HalfSquare texelSquare(int x, int y, int n) {
  const int local = x % n;
  const double scale = 2.0 / n;
  return {local * scale - 1.0, (local + 1) * scale - 1.0, 1.0 - (y + 1) * scale, 1.0 - y * scale};
}

}  // namespace

MapAddress ParaboloidMap::getAddressFor(const Vec3& direction) const {
  const Vec3 r = checkedUnit(direction);
  const bool front = r.z() >= 0.0;
  const double denominator = front ? 1.0 + r.z() : 1.0 - r.z();
  const double s = (r.x() / denominator + 1.0) * 0.5, t = (r.y() / denominator + 1.0) * 0.5;
  const double n = resolution();
  return {Vec2((s + (front ? 0.0 : 1.0)) * n, (1.0 - t) * n), front ? Front : Back};
}

std::optional<Vec3> ParaboloidMap::getDirectionFor(const Vec2& pixel) const {
  const double n = resolution(), inverse = inverseResolution();
  const bool front = pixel.x() < n;
  const double s = (front ? pixel.x() : pixel.x() - n) * inverse, t = 1.0 - pixel.y() * inverse;
  const double x = 2.0 * s - 1.0, y = 2.0 * t - 1.0;
  const double rho2 = x * x + y * y;
  const double scale = 1.0 / (1.0 + rho2);
  const double z = (1.0 - rho2) * scale;
  return Vec3(2.0 * x * scale, 2.0 * y * scale, front ? z : -z);
}

void ParaboloidMap::getDirectionsForRow(double py, const double* px, int count, double* x, double* y, double* z,
                                        unsigned char* valid) const {
  const double n = resolution(), twoOverN = 2.0 * inverseResolution();
  const double sy = 1.0 - py * twoOverN;
  for (int i = 0; i < count; ++i) {
    const bool front = px[i] < n;
    const double sx = (front ? px[i] : px[i] - n) * twoOverN - 1.0;
    const double rho2 = sx * sx + sy * sy;
    const double scale = 1.0 / (1.0 + rho2);
    x[i] = 2.0 * sx * scale;
    y[i] = 2.0 * sy * scale;
    z[i] = (front ? 1.0 - rho2 : rho2 - 1.0) * scale;
    valid[i] = 1;
  }
}

TexelRect ParaboloidMap::region(int index) const {
  require(index == 0 || index == 1, "paraboloid region must be 0 or 1");
  return {index * resolution(), 0, resolution(), resolution()};
}

double ParaboloidMap::texelCoverage(int x, int y) const {
  const HalfSquare q = texelSquare(x, y, resolution());
  return detail::discCoverage(q.x0, q.x1, q.y0, q.y1);
}

double ParaboloidMap::texelSolidAngle(int x, int y) const {
  const HalfSquare q = texelSquare(x, y, resolution());
  return detail::integrateOverDiscPart(q.x0, q.x1, q.y0, q.y1, kParaboloidSolidAngle);
}

Mat4 ParaboloidMap::textureMatrix(Hemisphere hemisphere, const Mat3& eyeToMap, bool atlas) {
  // Rotation into the map frame, then (front) (rx, ry, 1 + rz, 1 + rz) or (back)
  // (rx, ry, 1 - rz, 1 - rz): after the divide (x, y, 1, 1). Finally [-1,1] -> [0,1].
  Mat4 rotate = Mat4::Identity();
  rotate.topLeftCorner<3, 3>() = eyeToMap;
  const double sign = hemisphere == Front ? 1.0 : -1.0;
  Mat4 project;
  project << 1, 0, 0, 0,  //
      0, 1, 0, 0,         //
      0, 0, sign, 1,      //
      0, 0, sign, 1;
  Mat4 toTexture;
  const double sScale = atlas ? 0.25 : 0.5;
  const double sOffset = atlas ? (hemisphere == Front ? 0.25 : 0.75) : 0.5;
  toTexture << sScale, 0, 0, sOffset,  //
      0, 0.5, 0, 0.5,                  //
      0, 0, 1, 0,                      //
      0, 0, 0, 1;
  return toTexture * project * rotate;
}

}  // namespace brdfbake
