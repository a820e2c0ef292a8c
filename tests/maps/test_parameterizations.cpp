// Forward, inverse, anisotropy and seams of every parameterization, tested against each other
// and against closed forms.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/maps/latlong_map.hpp>
#include <brdfbake/maps/paraboloid_map.hpp>
#include <brdfbake/maps/sphere_map.hpp>

#include <random>

namespace brdfbake {
namespace {

std::vector<Vec3> randomDirections(int count, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss;
  std::vector<Vec3> out;
  while (static_cast<int>(out.size()) < count) {
    Vec3 v(gauss(rng), gauss(rng), gauss(rng));
    if (v.norm() > 1e-3) out.push_back(v.normalized());
  }
  return out;
}

// Round trip over a dense grid of image positions: pixel -> direction -> pixel.
void expectPixelRoundTrip(const Parameterization& map, double tolerance,
                          const std::function<bool(const Vec2&)>& singular) {
  int checked = 0;
  for (double y = 0.013; y < map.height(); y += 0.37) {
    for (double x = 0.011; x < map.width(); x += 0.37) {
      const Vec2 pixel(x, y);
      if (singular(pixel)) continue;
      const auto direction = map.getDirectionFor(pixel);
      if (!direction) continue;
      EXPECT_NEAR(direction->norm(), 1.0, 1e-12);
      const MapAddress back = map.getAddressFor(*direction);
      ASSERT_NEAR((back.pixel - pixel).norm(), 0.0, tolerance) << toString(map.kind()) << " at " << x << "," << y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

// Direction -> pixel -> direction over random directions.
void expectDirectionRoundTrip(const Parameterization& map, double tolerance) {
  for (const Vec3& d : randomDirections(20000)) {
    const MapAddress address = map.getAddressFor(d);
    const auto back = map.getDirectionFor(address.pixel);
    ASSERT_TRUE(back.has_value());
    ASSERT_NEAR((*back - d).norm(), 0.0, tolerance) << toString(map.kind()) << " " << d.transpose();
  }
}

TEST(Parameterizations, CoverageRowIsTexelCoverage) {
  // The batch form the baker uses (SphereMap has its own loop) against texelCoverage per texel.
  for (const auto kind : {ParameterizationKind::Sphere, ParameterizationKind::Paraboloid, ParameterizationKind::Cube,
                          ParameterizationKind::LatLong}) {
    const auto map = makeParameterization(kind, 37);
    std::vector<double> row(map->width());
    for (int y = 0; y < map->height(); ++y) {
      map->texelCoverageRow(y, row.data());
      for (int x = 0; x < map->width(); ++x)
        ASSERT_EQ(row[x], map->texelCoverage(x, y)) << toString(kind) << " " << x << ", " << y;
    }
  }
}

TEST(SphereMap, RoundTripsAwayFromTheRim) {
  const SphereMap map(512);
  // Singular set: the rim circle (radius 1 in map units), which is the single direction -z.
  expectPixelRoundTrip(map, 1e-9, [&](const Vec2& p) {
    const double x = 2 * p.x() / 512 - 1, y = 1 - 2 * p.y() / 512;
    return x * x + y * y > 1.0 - 1e-9;
  });
  expectDirectionRoundTrip(map, 1e-9);
}

TEST(SphereMap, ForwardIsTheGlFormula) {
  for (const Vec3& r : randomDirections(1000)) {
    const double m = 2 * std::sqrt(r.x() * r.x() + r.y() * r.y() + (r.z() + 1) * (r.z() + 1));
    const Vec2 st = SphereMap::textureCoordinates(r);
    EXPECT_NEAR(st.x(), r.x() / m + 0.5, 1e-14);
    EXPECT_NEAR(st.y(), r.y() / m + 0.5, 1e-14);
  }
}

TEST(SphereMap, RimIsFiniteAndOnTheCircle) {
  // r = -z exactly, and directions within 1e-12 of it, land on the rim, never NaN.
  for (const Vec3& r : {Vec3(0, 0, -1), Vec3(1e-12, 0, -1), Vec3(0, -1e-12, -1), Vec3(1e-13, 1e-13, -1),
                        Vec3(1e-300, 0, -1), Vec3(-5e-13, 7e-13, -1)}) {
    const Vec2 st = SphereMap::textureCoordinates(r.normalized());
    ASSERT_TRUE(st.allFinite()) << r.transpose();
    EXPECT_NEAR((2 * st - Vec2::Ones()).norm(), 1.0, 1e-9) << r.transpose();
  }
  const SphereMap map(64);
  EXPECT_TRUE(map.getAddressFor(Vec3(0, 0, -1)).pixel.allFinite());
}

TEST(SphereMap, AnisotropyGrowsAsInverseCosSquaredOfHalfAngle) {
  const SphereMap map(256);
  for (double radius : {0.0, 0.2, 0.5, 0.7071, 0.9, 0.97}) {
    const Vec2 pixel(128 + radius * 128 * std::cos(0.3), 128 - radius * 128 * std::sin(0.3));
    const Vec3 r = *map.getDirectionFor(pixel);
    const double theta = std::acos(r.z());  // angle from the view axis
    const double expected = 1.0 / std::pow(std::cos(theta / 2), 2);
    EXPECT_NEAR(map.anisotropy(pixel), expected, 1e-5 * expected) << "radius " << radius;
  }
}

TEST(SphereMap, FrontBackSplitIsAtRadiusOneOverSqrtTwo) {
  // Zimmons 1999: directions with rz > 0 (in front of the sphere) fill the disc of radius 1/sqrt 2.
  const Vec2 st = SphereMap::textureCoordinates(Vec3(1, 0, 0));
  EXPECT_NEAR(2 * st.x() - 1, 1.0 / std::sqrt(2.0), 1e-15);
  const Vec3 inside = SphereMap::direction(Vec2(0.5 + 0.5 * 0.7071, 0.5));
  const Vec3 outside = SphereMap::direction(Vec2(0.5 + 0.5 * 0.7072, 0.5));
  EXPECT_GT(inside.z(), 0.0);
  EXPECT_LT(outside.z(), 0.0);
}

TEST(ParaboloidMap, RoundTripsEverywhere) {
  const ParaboloidMap map(256);
  // No singular set inside either half; exclude the seam column between the halves.
  expectPixelRoundTrip(map, 1e-9, [](const Vec2& p) {
    const double local = std::fmod(p.x(), 256.0) / 256 * 2 - 1, y = 1 - 2 * p.y() / 256;
    return local * local + y * y > 1.0;  // extended area maps into the other half on the way back
  });
  expectDirectionRoundTrip(map, 1e-9);
}

TEST(ParaboloidMap, ForwardIsHeidrichsFormula) {
  const ParaboloidMap map(100);
  for (const Vec3& r : randomDirections(1000)) {
    const MapAddress a = map.getAddressFor(r);
    const bool front = r.z() >= 0;
    EXPECT_EQ(a.region, front ? 0 : 1);
    const double x = r.x() / (front ? 1 + r.z() : 1 - r.z()), y = r.y() / (front ? 1 + r.z() : 1 - r.z());
    EXPECT_NEAR(a.pixel.x(), ((x + 1) / 2 + (front ? 0 : 1)) * 100, 1e-9);
    EXPECT_NEAR(a.pixel.y(), (1 - (y + 1) / 2) * 100, 1e-9);
  }
}

TEST(ParaboloidMap, IsConformal) {
  const ParaboloidMap map(128);
  for (const Vec2& pixel : {Vec2(64, 64), Vec2(10.5, 64), Vec2(100, 20), Vec2(200, 70), Vec2(129, 3)}) {
    EXPECT_NEAR(map.anisotropy(pixel), 1.0, 1e-6) << pixel.transpose();
  }
}

TEST(ParaboloidMap, ExtendedInverseContinuesIntoTheOtherHemisphere) {
  // Outside the unit circle the front image shows back-hemisphere directions, matching the back
  // image's own mapping of those directions (Heidrich 2000 Fig. 6).
  const ParaboloidMap map(64);
  const Vec2 corner(0.5, 0.5);  // front half, top-left corner: x = y = -1 + 1/64
  const Vec3 d = *map.getDirectionFor(corner);
  EXPECT_LT(d.z(), 0.0);
  const MapAddress back = map.getAddressFor(d);
  EXPECT_EQ(back.region, 1);
  // In the back image the same direction lies inside the unit circle, at (x, y) / (x^2 + y^2).
  const double x = 2 * corner.x() / 64 - 1, y = 1 - 2 * corner.y() / 64, rho2 = x * x + y * y;
  EXPECT_NEAR(back.pixel.x(), 64 + (x / rho2 + 1) / 2 * 64, 1e-9);
  EXPECT_NEAR(back.pixel.y(), (1 - (y / rho2 + 1) / 2) * 64, 1e-9);
}

TEST(ParaboloidMap, SeamAcrossTheEquatorIsContinuous) {
  const ParaboloidMap map(256);
  for (double phi = 0; phi < kTwoPi; phi += 0.1) {
    const Vec3 above(std::cos(phi), std::sin(phi), 1e-9), below(std::cos(phi), std::sin(phi), -1e-9);
    const MapAddress a = map.getAddressFor(above), b = map.getAddressFor(below);
    ASSERT_EQ(a.region, 0);
    ASSERT_EQ(b.region, 1);
    // The same (s, t) in both halves: continuity across the equator in texture space.
    EXPECT_NEAR(a.pixel.x() + 256, b.pixel.x(), 1e-6);
    EXPECT_NEAR(a.pixel.y(), b.pixel.y(), 1e-6);
  }
}

TEST(ParaboloidMap, TextureMatricesReproduceForward) {
  Mat3 rotation = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (const Vec3& eye : randomDirections(500)) {
    const Vec3 r = rotation * eye;  // map frame
    const bool front = r.z() >= 0;
    for (bool atlas : {false, true}) {
      const Mat4 m = ParaboloidMap::textureMatrix(front ? ParaboloidMap::Front : ParaboloidMap::Back, rotation, atlas);
      const Eigen::Vector4d h = m * Eigen::Vector4d(eye.x(), eye.y(), eye.z(), 1.0);
      const double s = h.x() / h.w(), t = h.y() / h.w();
      EXPECT_NEAR(h.z() / h.w(), 1.0, 1e-12);
      const double x = r.x() / (front ? 1 + r.z() : 1 - r.z()), y = r.y() / (front ? 1 + r.z() : 1 - r.z());
      const double expectedS = atlas ? ((x + 1) / 2 + (front ? 0 : 1)) / 2 : (x + 1) / 2;
      EXPECT_NEAR(s, expectedS, 1e-12);
      EXPECT_NEAR(t, (y + 1) / 2, 1e-12);
    }
  }
}

TEST(CubeMap, RoundTripsAwayFromEdges) {
  const CubeMap map(128);
  expectPixelRoundTrip(map, 1e-9, [](const Vec2& p) {
    const double fx = std::fmod(p.x(), 128.0), fy = std::fmod(p.y(), 128.0);
    return fx < 1e-6 || fy < 1e-6;  // face boundaries belong to either face
  });
  expectDirectionRoundTrip(map, 1e-9);
}

TEST(CubeMap, FaceSelectionFollowsTheOpenGlTable) {
  // (direction, face, s, t) from the OpenGL spec's table (Zimmons 1999 Fig. 33).
  struct Case {
    Vec3 r;
    CubeMap::Face face;
    double s, t;
  };
  const double a = 0.5;  // off-axis component
  for (const Case& c : {Case{{1, a, a}, CubeMap::PosX, (-a + 1) / 2, (-a + 1) / 2},
                        Case{{-1, a, a}, CubeMap::NegX, (a + 1) / 2, (-a + 1) / 2},
                        Case{{a, 1, a}, CubeMap::PosY, (a + 1) / 2, (a + 1) / 2},
                        Case{{a, -1, a}, CubeMap::NegY, (a + 1) / 2, (-a + 1) / 2},
                        Case{{a, a, 1}, CubeMap::PosZ, (a + 1) / 2, (-a + 1) / 2},
                        Case{{a, a, -1}, CubeMap::NegZ, (-a + 1) / 2, (-a + 1) / 2}}) {
    const auto [face, st] = CubeMap::faceCoordinates(c.r.normalized());
    EXPECT_EQ(face, c.face) << c.r.transpose();
    EXPECT_NEAR(st.x(), c.s, 1e-15);
    EXPECT_NEAR(st.y(), c.t, 1e-15);
  }
}

TEST(CubeMap, EdgesAreSeamlessInTheCross) {
  // Directions just either side of every cube edge land in adjacent faces at texture positions
  // that agree along the shared edge; where faces touch in the cross, at the same pixel.
  const CubeMap map(64);
  int crossAdjacent = 0;
  for (const Vec3& d : randomDirections(20000, 11)) {
    // Push d onto its nearest edge: the two largest components get equal magnitude.
    std::array<int, 3> order{0, 1, 2};
    std::sort(order.begin(), order.end(), [&](int a, int b) { return std::abs(d[a]) > std::abs(d[b]); });
    const int i = order[0], j = order[1];
    Vec3 edge = d;
    edge[j] = std::copysign(std::abs(d[i]), d[j]);
    Vec3 p = edge, q = edge;
    p[i] *= 1 + 1e-9;
    q[j] *= 1 + 1e-9;
    const MapAddress ap = map.getAddressFor(p), aq = map.getAddressFor(q);
    ASSERT_NE(ap.region, aq.region);
    // Both sides map back to (almost) the same direction: the mapping is continuous across the edge.
    EXPECT_NEAR((*map.getDirectionFor(ap.pixel) - *map.getDirectionFor(aq.pixel)).norm(), 0.0, 1e-7);
    if ((ap.pixel - aq.pixel).norm() < 1e-6) ++crossAdjacent;
  }
  EXPECT_GT(crossAdjacent, 6000);  // 5 of the 12 edges touch inside the cross: pixel for pixel
}

TEST(CubeMap, UnusedCellsHaveNoDirection) {
  const CubeMap map(16);
  EXPECT_FALSE(map.getDirectionFor(Vec2(3, 3)).has_value());    // cell (0, 0)
  EXPECT_FALSE(map.getDirectionFor(Vec2(60, 40)).has_value());  // cell (3, 2)
  EXPECT_EQ(map.texelCoverage(3, 3), 0.0);
  EXPECT_EQ(map.texelSolidAngle(3, 3), 0.0);
}

TEST(LatLongMap, RoundTripsAwayFromPolesAndSeam) {
  const LatLongMap map(128);
  expectPixelRoundTrip(map, 1e-9, [](const Vec2& p) { return p.y() < 1e-3 || p.y() > 128 - 1e-3; });
  expectDirectionRoundTrip(map, 1e-9);
}

TEST(LatLongMap, AnisotropyIsInverseSinTheta) {
  const LatLongMap map(128);
  for (double row : {10.5, 32.0, 64.0, 100.25}) {
    const double theta = row / 128 * kPi;
    EXPECT_NEAR(map.anisotropy(Vec2(77.3, row)), 1.0 / std::sin(theta), 1e-5 / std::sin(theta));
  }
}

TEST(Parameterization, RejectsBadInput) {
  EXPECT_THROW(SphereMap(0), Error);
  EXPECT_THROW(makeParameterization(ParameterizationKind::Cube, -3), Error);
  const SphereMap map(8);
  EXPECT_THROW(map.getAddressFor(Vec3::Zero()), Error);
  EXPECT_THROW(map.getAddressFor(Vec3(NAN, 0, 1)), Error);
  EXPECT_THROW(parseParameterizationKind("spherical"), Error);
  EXPECT_EQ(parseParameterizationKind("latlong"), ParameterizationKind::LatLong);
}

}  // namespace
}  // namespace brdfbake
