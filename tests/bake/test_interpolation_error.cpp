// Per-vertex interpolation error: limits, scaling, where it is worst, and Zimmons 1999's line.
#include <gtest/gtest.h>
#include <brdfbake/bake/interpolation_error.hpp>
#include <brdfbake/core/error.hpp>

#include <cmath>

namespace brdfbake {
namespace {

double sweepError(double size, double place, bool sphereMap) {
  const auto p = interpolationSweep({size}, {place}).front();
  return sphereMap ? p.sphereMapError : p.reflectedVectorError;
}

TEST(InterpolationError, VanishesForAFlatTriangle) {
  const Vec3 n = Vec3(0.3, 0.2, 1).normalized();
  for (auto scheme : {InterpolationScheme::SphereMapCoordinates, InterpolationScheme::ReflectedVector}) {
    EXPECT_NEAR(triangleInterpolationError(scheme, {n, n, n}), 0.0, 1e-6);
  }
}

TEST(InterpolationError, GrowsWithTheSquareOfTheTriangleSize) {
  for (bool sphereMap : {true, false}) {
    for (double place : {20.0, 50.0}) {
      const double ratio = sweepError(2.0, place, sphereMap) / sweepError(1.0, place, sphereMap);
      EXPECT_NEAR(ratio, 4.0, 0.4) << (sphereMap ? "(s,t)" : "r") << " at " << place;
    }
  }
}

TEST(InterpolationError, SphereMapCoordinatesAreWorstNearTheRim) {
  // Texture coordinates: the error grows towards the rim and explodes where a triangle straddles
  // it (its (s, t) are interpolated across the disc); reflected vectors do not care.
  EXPECT_GT(sweepError(5, 80, true), 5 * sweepError(5, 20, true));
  EXPECT_GT(sweepError(10, 88, true), 90.0);
  EXPECT_LT(sweepError(10, 88, false), 1.0);
}

TEST(SeedLineExperiment, MatchesAHandComputationAtTheMidpoint) {
  // One polygon from -10 to 10, viewer (-8.3, 1, 0), normal +y: in the x-y plane r = (x - ex, ey)/|.|.
  const LineExperiment line = planarLineExperiment(Vec3(-8.3, 1, 0), 20.0, 4001);
  auto r = [](double x) { return Vec2(x + 8.3, 1.0).normalized(); };
  const Vec2 lerp = 0.5 * (r(-10) + r(10));
  const double expected = degrees(std::acos(lerp.normalized().dot(r(0))));
  ASSERT_NEAR(line.x[2000], 0.0, 1e-12);
  EXPECT_NEAR(line.errorDegrees[2000], expected, 1e-9);
  EXPECT_EQ(line.errorDegrees.front(), 0.0);
}

TEST(SeedLineExperiment, AViewerOnOrBelowTheSurfaceOrFarAwayIsRefused) {
  // (0, 0, 0) sits on the surface (it reported max_error_degrees 180); 1e308 overflows the view vectors.
  for (const Vec3& viewer : {Vec3(0, 0, 0), Vec3(1e308, 1e308, 0), Vec3(-8.3, -1, 0), Vec3(2e6, 1, 0)}) {
    try {
      planarLineExperiment(viewer);
      ADD_FAILURE() << "no error for " << viewer.transpose();
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::InvalidArgument);
      EXPECT_EQ(std::string(e.what()).rfind("the viewer must lie above the surface (y in [1e-6, 1e6]", 0), 0u)
          << e.what();
    }
  }
  LineExperimentOptions options;
  options.segment = 0;
  EXPECT_THROW(options.validate(), Error);
  options.segment = 20;
  options.samples = 1;
  EXPECT_THROW(options.validate(), Error);
  options.samples = 3;
  EXPECT_NO_THROW(options.validate());
  // A viewer high above still gives finite errors.
  for (double e : planarLineExperiment(Vec3(0, 1e6, 0), 20.0, 5).errorDegrees) EXPECT_TRUE(std::isfinite(e));
}

TEST(SeedLineExperiment, IsSymmetricAndShrinksQuadraticallyWithTheSegment) {
  const LineExperiment left = planarLineExperiment(Vec3(-8.3, 1, 0), 1.0, 2001);
  const LineExperiment right = planarLineExperiment(Vec3(8.3, 1, 0), 1.0, 2001);
  for (std::size_t i = 0; i < left.x.size(); i += 37)
    EXPECT_NEAR(left.errorDegrees[i], right.errorDegrees[2000 - i], 1e-9);
  const double half = planarLineExperiment(Vec3(-8.3, 1, 0), 0.5, 4001).maxError;
  EXPECT_NEAR(left.maxError / half, 4.0, 0.6);
}

}  // namespace
}  // namespace brdfbake
