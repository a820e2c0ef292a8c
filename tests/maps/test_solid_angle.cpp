// Exact texel solid angles against totals, closed-form ratios (Heidrich), the sphere map's equal
// area, and brute-force integration of the numerical Jacobian.
#include <gtest/gtest.h>
#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/maps/latlong_map.hpp>
#include <brdfbake/maps/paraboloid_map.hpp>
#include <brdfbake/maps/sphere_map.hpp>

namespace brdfbake {
namespace {

double totalSolidAngle(const Parameterization& map, int x0, int x1) {
  double sum = 0.0;
  for (int y = 0; y < map.height(); ++y)
    for (int x = x0; x < x1; ++x) sum += map.texelSolidAngle(x, y);
  return sum;
}

class SolidAngleSum : public ::testing::TestWithParam<int> {};

TEST_P(SolidAngleSum, CoversTheSphere) {
  const int n = GetParam();
  const SphereMap sphere(n);
  EXPECT_NEAR(totalSolidAngle(sphere, 0, sphere.width()), kFourPi, 1e-6);
  const CubeMap cube(n);
  EXPECT_NEAR(totalSolidAngle(cube, 0, cube.width()), kFourPi, 1e-6);
  const LatLongMap latlong(n);
  EXPECT_NEAR(totalSolidAngle(latlong, 0, latlong.width()), kFourPi, 1e-6);
  const ParaboloidMap paraboloid(n);
  EXPECT_NEAR(totalSolidAngle(paraboloid, 0, n), kTwoPi, 1e-6) << "front disc";
  EXPECT_NEAR(totalSolidAngle(paraboloid, n, 2 * n), kTwoPi, 1e-6) << "back disc";
}

INSTANTIATE_TEST_SUITE_P(Resolutions, SolidAngleSum, ::testing::Values(1, 2, 3, 7, 64, 255, 512));

TEST(SphereMapArea, IsEqualAreaInsideTheDisc) {
  for (int n : {16, 256, 1024}) {
    const SphereMap map(n);
    int interior = 0;
    for (int y = 0; y < n; y += 3) {
      for (int x = 0; x < n; x += 3) {
        if (map.texelCoverage(x, y) < 1.0) continue;
        ++interior;
        ASSERT_NEAR(map.texelSolidAngle(x, y), 16.0 / (double(n) * n), 1e-15) << n << " " << x << "," << y;
      }
    }
    EXPECT_GT(interior, 0);
  }
}

TEST(SphereMapArea, UnusedTexelFractionIsOneMinusPiOverFour) {
  // Zimmons 1999: 1 - pi/4 = 21.46 % of a sphere map's texels hold no direction.
  const int n = 1024;
  const SphereMap map(n);
  double unused = 0.0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) unused += 1.0 - map.texelCoverage(x, y);
  EXPECT_NEAR(unused / (double(n) * n), 1.0 - kPi / 4, 1e-9);
  EXPECT_NEAR(100 * unused / (double(n) * n), 21.46, 0.005);  // Zimmons & Bastos 1999's published percentage
}

TEST(ParaboloidArea, CentreCoversFourTimesTheRimSolidAngle) {
  // Heidrich, Heidrich 2000 Eq. 3: omega / omega_centre = 1 / (4 |f(x, y)|^2), 1/4 at the rim.
  const int n = 1024;
  const ParaboloidMap map(n);
  const double centre = map.solidAngleDensity(Vec2(n / 2.0, n / 2.0));
  const double rim = map.solidAngleDensity(Vec2(n / 2.0 + n / 2.0 * std::cos(0.4), n / 2.0 - n / 2.0 * std::sin(0.4)));
  EXPECT_NEAR(centre / rim, 4.0, 1e-6);
  // Whole texels: centre texel against the outermost texel wholly inside the disc on the x axis,
  // whose ratio is the density ratio (1 + r^2)^2 at its centre radius r (just under 1).
  int edge = n - 1;
  while (map.texelCoverage(edge, n / 2) < 1.0) --edge;
  const double r = (edge + 0.5) / n * 2 - 1, rc = 0.5 / n * 2;
  const double expected = std::pow((1 + r * r) / (1 + rc * rc), 2);
  EXPECT_GT(expected, 3.97);
  EXPECT_NEAR(map.texelSolidAngle(n / 2, n / 2) / map.texelSolidAngle(edge, n / 2), expected, 1e-4);
}

TEST(CubeArea, FaceCentreCoversThreeRootThreeTimesTheCorner) {
  const int n = 2048;
  const CubeMap map(n);
  const TexelRect face = map.region(CubeMap::PosZ);
  const double centre = map.solidAngleDensity(Vec2(face.x0 + n / 2.0, face.y0 + n / 2.0));
  const double corner = map.solidAngleDensity(Vec2(face.x0 + 1e-3, face.y0 + 1e-3));
  EXPECT_NEAR(centre / corner, 3 * std::sqrt(3.0), 1e-2);
  const double texelRatio =
      map.texelSolidAngle(face.x0 + n / 2, face.y0 + n / 2) / map.texelSolidAngle(face.x0, face.y0);
  EXPECT_NEAR(texelRatio, 3 * std::sqrt(3.0), 0.01);
}

// Brute force: integrate the numerical Jacobian density over a fine grid inside each texel,
// counting only points inside the domain. Independent of the exact (Green's theorem) code path.
double bruteForceSolidAngle(const Parameterization& map, int x, int y, bool disc, int steps) {
  const double n = map.resolution();
  double sum = 0.0;
  for (int j = 0; j < steps; ++j) {
    for (int i = 0; i < steps; ++i) {
      const Vec2 p(x + (i + 0.5) / steps, y + (j + 0.5) / steps);
      if (disc) {
        const double lx = std::fmod(p.x(), n) / n * 2 - 1, ly = 1 - p.y() / n * 2;
        if (lx * lx + ly * ly > 1.0) continue;
      }
      sum += map.solidAngleDensity(p);
    }
  }
  return sum / (double(steps) * steps);
}

TEST(SolidAngle, MatchesBruteForceIntegrationIncludingRimTexels) {
  const SphereMap sphere(32);
  const ParaboloidMap paraboloid(32);
  const CubeMap cube(32);
  const LatLongMap latlong(32);
  struct Case {
    const Parameterization* map;
    int x, y;
    bool disc;
  };
  // Interior texels and texels the rim circle cuts through.
  for (const Case& c : {Case{&sphere, 16, 16, true}, Case{&sphere, 31, 16, true}, Case{&sphere, 27, 4, true},
                        Case{&sphere, 4, 28, true}, Case{&paraboloid, 16, 16, true}, Case{&paraboloid, 0, 15, true},
                        Case{&paraboloid, 60, 5, true}, Case{&paraboloid, 40, 2, true}, Case{&cube, 40, 40, false},
                        Case{&cube, 32, 32, false}, Case{&cube, 95, 63, false}, Case{&latlong, 3, 0, false},
                        Case{&latlong, 40, 17, false}}) {
    const double exact = c.map->texelSolidAngle(c.x, c.y);
    const double brute = bruteForceSolidAngle(*c.map, c.x, c.y, c.disc, 400);
    EXPECT_NEAR(exact, brute, 2e-3 * exact + 1e-9)
        << toString(c.map->kind()) << " texel " << c.x << "," << c.y << " coverage " << c.map->texelCoverage(c.x, c.y);
  }
}

}  // namespace
}  // namespace brdfbake
