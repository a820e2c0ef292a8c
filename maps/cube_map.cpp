#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/cube_map.hpp>

namespace brdfbake {
namespace {

// Solid angle of the face rectangle [0, a] x [0, b] seen from the cube centre (face at distance 1).
double cornerSolidAngle(double a, double b) { return std::atan2(a * b, std::sqrt(a * a + b * b + 1.0)); }

constexpr std::array<std::array<int, 2>, 6> kCells{{{2, 1}, {0, 1}, {1, 0}, {1, 2}, {1, 1}, {3, 1}}};

}  // namespace

std::array<int, 2> CubeMap::faceCell(Face face) { return kCells[face]; }

std::string_view CubeMap::faceName(Face face) {
  static constexpr std::array<std::string_view, 6> names{"+X", "-X", "+Y", "-Y", "+Z", "-Z"};
  return names[face];
}

std::pair<CubeMap::Face, Vec2> CubeMap::faceCoordinates(const Vec3& r) {
  const double ax = std::abs(r.x()), ay = std::abs(r.y()), az = std::abs(r.z());
  Face face;
  double sc, tc, ma;
  // OpenGL table (Zimmons 1999 Fig. 33): major axis, then (sc, tc).
  if (ax >= ay && ax >= az) {
    ma = ax;
    face = r.x() >= 0 ? PosX : NegX;
    sc = r.x() >= 0 ? -r.z() : r.z();
    tc = -r.y();
  } else if (ay >= az) {
    ma = ay;
    face = r.y() >= 0 ? PosY : NegY;
    sc = r.x();
    tc = r.y() >= 0 ? r.z() : -r.z();
  } else {
    ma = az;
    face = r.z() >= 0 ? PosZ : NegZ;
    sc = r.z() >= 0 ? r.x() : -r.x();
    tc = -r.y();
  }
  return {face, Vec2((sc / ma + 1.0) * 0.5, (tc / ma + 1.0) * 0.5)};
}

Vec3 CubeMap::faceDirection(Face face, const Vec2& st) {
  const double sc = 2.0 * st.x() - 1.0, tc = 2.0 * st.y() - 1.0;
  Vec3 r;
  switch (face) {
    case PosX:
      r = {1.0, -tc, -sc};
      break;
    case NegX:
      r = {-1.0, -tc, sc};
      break;
    case PosY:
      r = {sc, 1.0, tc};
      break;
    case NegY:
      r = {sc, -1.0, -tc};
      break;
    case PosZ:
      r = {sc, -tc, 1.0};
      break;
    case NegZ:
      r = {-sc, -tc, -1.0};
      break;
  }
  return r.normalized();
}

MapAddress CubeMap::getAddressFor(const Vec3& direction) const {
  const auto [face, st] = faceCoordinates(checkedUnit(direction));
  const double n = resolution();
  const auto cell = kCells[face];
  return {Vec2((cell[0] + st.x()) * n, (cell[1] + st.y()) * n), face};
}

std::optional<Vec3> CubeMap::getDirectionFor(const Vec2& pixel) const {
  const double n = resolution();
  const int column = static_cast<int>(std::floor(pixel.x() / n));
  const int row = static_cast<int>(std::floor(pixel.y() / n));
  for (int f = 0; f < 6; ++f) {
    if (kCells[f][0] == column && kCells[f][1] == row) {
      return faceDirection(static_cast<Face>(f), Vec2(pixel.x() / n - column, pixel.y() / n - row));
    }
  }
  return std::nullopt;
}

TexelRect CubeMap::region(int index) const {
  require(index >= 0 && index < 6, "cube face index must be in 0..5");
  const int n = resolution();
  return {kCells[index][0] * n, kCells[index][1] * n, n, n};
}

double CubeMap::texelCoverage(int x, int y) const {
  const int n = resolution();
  const int column = x / n, row = y / n;
  for (const auto& cell : kCells) {
    if (cell[0] == column && cell[1] == row) return 1.0;
  }
  return 0.0;
}

double CubeMap::texelSolidAngle(int x, int y) const {
  if (texelCoverage(x, y) == 0.0) return 0.0;
  const int n = resolution();
  const double scale = 2.0 / n;
  const double a0 = (x % n) * scale - 1.0, a1 = a0 + scale;
  const double b0 = (y % n) * scale - 1.0, b1 = b0 + scale;
  return cornerSolidAngle(a1, b1) - cornerSolidAngle(a0, b1) - cornerSolidAngle(a1, b0) + cornerSolidAngle(a0, b0);
}

}  // namespace brdfbake
