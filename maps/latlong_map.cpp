#include <brdfbake/maps/latlong_map.hpp>

namespace brdfbake {

MapAddress LatLongMap::getAddressFor(const Vec3& direction) const { return {pixelForUnit(checkedUnit(direction)), 0}; }

Vec2 LatLongMap::pixelForUnit(const Vec3& r) const {
  const double phi = std::atan2(r.x(), -r.z());  // 0 at -z, +pi/2 at +x
  const double theta = std::acos(clampFinite(r.y(), -1.0, 1.0));
  const double n = resolution();
  return Vec2((phi / kTwoPi + 0.5) * 2.0 * n, theta / kPi * n);
}

std::optional<Vec3> LatLongMap::getDirectionFor(const Vec2& pixel) const {
  const double n = resolution();
  const double phi = (pixel.x() / (2.0 * n) - 0.5) * kTwoPi;
  const double theta = clampFinite(pixel.y() / n, 0.0, 1.0) * kPi;
  const double st = std::sin(theta);
  return Vec3(st * std::sin(phi), std::cos(theta), -st * std::cos(phi));
}

double LatLongMap::texelSolidAngle(int x, int y) const {
  const double n = resolution();
  const double dphi = kTwoPi / (2.0 * n);
  return dphi * (std::cos(y / n * kPi) - std::cos((y + 1) / n * kPi));
}

}  // namespace brdfbake
