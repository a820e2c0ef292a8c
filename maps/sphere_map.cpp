#include <brdfbake/maps/sphere_map.hpp>

#include "disc_region.hpp"

namespace brdfbake {
namespace {

// Points at or outside the rim are pulled in to this radius (1e-15 inside): the direction is then
// within 1e-7 of -z but still says which rim point it came from, so the normal n = (x, y, ~0), and
// every shading term that depends on it, extends continuously outwards at each azimuth.
constexpr double kRimRadius = 1.0 - 1e-15;
constexpr double kRimRadius2 = kRimRadius * kRimRadius;

// Equal-area density 4 sr per unit area of the disc: h(R) = 2 R^2, so h/r^2 = 2.
constexpr detail::RadialDensity kSphereSolidAngle{[](double d, double s0, double s1) { return 2.0 * d * (s1 - s0); },
                                                  2.0};

// Map-plane square of texel (x, y): the disc is the unit disc of x' = 2s - 1, y' = 2t - 1.
struct Square {
  double x0, x1, y0, y1;
};
Square texelSquare(int x, int y, int n) {
  const double scale = 2.0 / n;
  return {x * scale - 1.0, (x + 1) * scale - 1.0, 1.0 - (y + 1) * scale, 1.0 - y * scale};
}

}  // namespace

Vec2 SphereMap::textureCoordinates(const Vec3& r) {
  const double m = 2.0 * std::sqrt(r.x() * r.x() + r.y() * r.y() + (r.z() + 1.0) * (r.z() + 1.0));
  if (!(m > 0.0)) return {1.0, 0.5};  // r = -z exactly: the whole rim; pick (s, t) = (1, 1/2)
  return {r.x() / m + 0.5, r.y() / m + 0.5};
}

Vec3 SphereMap::direction(const Vec2& st) {
  double x = 2.0 * st.x() - 1.0, y = 2.0 * st.y() - 1.0;
  double rho2 = x * x + y * y;
  if (rho2 > kRimRadius2) {
    const double pull = std::sqrt(kRimRadius2 / rho2);
    x *= pull, y *= pull, rho2 = kRimRadius2;
  }
  const double nz = std::sqrt(1.0 - rho2);
  // r = 2 nz n - (0,0,1)
  return {2.0 * nz * x, 2.0 * nz * y, 2.0 * nz * nz - 1.0};
}

MapAddress SphereMap::getAddressFor(const Vec3& direction) const {
  const Vec2 st = textureCoordinates(checkedUnit(direction));
  const double n = resolution();
  return {Vec2(st.x() * n, (1.0 - st.y()) * n), 0};
}

std::optional<Vec3> SphereMap::getDirectionFor(const Vec2& pixel) const {
  const double inverse = inverseResolution();
  return direction(Vec2(pixel.x() * inverse, 1.0 - pixel.y() * inverse));
}

void SphereMap::getDirectionsForRow(double py, const double* px, int count, double* x, double* y, double* z,
                                    unsigned char* valid) const {
  const double twoOverN = 2.0 * inverseResolution();
  const double sy = 1.0 - py * twoOverN;
  for (int i = 0; i < count; ++i) {
    double sx = px[i] * twoOverN - 1.0, sy2 = sy;
    double rho2 = sx * sx + sy * sy;
    if (rho2 > kRimRadius2) {
      const double pull = std::sqrt(kRimRadius2 / rho2);
      sx *= pull, sy2 *= pull, rho2 = kRimRadius2;
    }
    const double nz = std::sqrt(1.0 - rho2);
    x[i] = 2.0 * nz * sx;
    y[i] = 2.0 * nz * sy2;
    z[i] = 2.0 * nz * nz - 1.0;
    valid[i] = 1;
  }
}

double SphereMap::texelCoverage(int x, int y) const {
  const Square q = texelSquare(x, y, resolution());
  return detail::discCoverage(q.x0, q.x1, q.y0, q.y1);
}

void SphereMap::texelCoverageRow(int y, double* coverage) const {
  const int n = resolution();  // a local: stores to coverage[] cannot change it
  for (int x = 0; x < n; ++x) {
    const Square q = texelSquare(x, y, n);
    coverage[x] = detail::discCoverage(q.x0, q.x1, q.y0, q.y1);
  }
}

double SphereMap::texelSolidAngle(int x, int y) const {
  const Square q = texelSquare(x, y, resolution());
  return detail::integrateOverDiscPart(q.x0, q.x1, q.y0, q.y1, kSphereSolidAngle);
}

}  // namespace brdfbake
