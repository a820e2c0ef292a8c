// Internals of the prefilter's direct sums (bake/prefilter_internal.hpp) checked against brute force.
#include <gtest/gtest.h>
#include <brdfbake/core/math.hpp>
#include <brdfbake/maps/image.hpp>

#include <cmath>

#include "../../env/prefilter_internal.hpp"

namespace brdfbake::detail {
namespace {

// Points of a cap's boundary circle as (polar angle, |azimuth offset|), 200 000 of them: polar
// angle theta from the pole z, the axis at azimuth 0.
std::vector<std::pair<double, double>> capBoundary(double thetaAxis, double cosCap) {
  const double cosD = std::cos(thetaAxis), sinD = std::sin(thetaAxis), alpha = std::acos(cosCap);
  const Vec3 axis(sinD, 0.0, cosD), t1(cosD, 0.0, -sinD), t2(0.0, 1.0, 0.0);
  std::vector<std::pair<double, double>> points;
  const int count = 200000;
  for (int i = 0; i < count; ++i) {
    const double psi = kTwoPi * i / count;
    const Vec3 p = std::cos(alpha) * axis + std::sin(alpha) * (std::cos(psi) * t1 + std::sin(psi) * t2);
    points.emplace_back(std::acos(std::clamp(p.z(), -1.0, 1.0)), std::abs(std::atan2(p.y(), p.x())));
  }
  return points;
}

// The widest azimuth offset of the cap over the polar band [theta0, theta1], found by sampling: the
// boundary points that fall in the band, and points of the band's two edge parallels (20 001
// offsets in [0, pi] each) that lie in the cap. Negative when none qualifies.
double bruteHalfWidth(const std::vector<std::pair<double, double>>& boundary, double theta0, double theta1,
                      double thetaAxis, double cosCap) {
  double widest = -1.0;
  for (const auto& [theta, dphi] : boundary)
    if (theta >= theta0 && theta <= theta1) widest = std::max(widest, dphi);
  const int offsets = 20000;
  for (double theta : {theta0, theta1})
    for (int i = 0; i <= offsets; ++i) {
      const double dphi = kPi * i / offsets;
      if (std::cos(theta) * std::cos(thetaAxis) + std::sin(theta) * std::sin(thetaAxis) * std::cos(dphi) >= cosCap) {
        widest = std::max(widest, dphi);
      }
    }
  return widest;
}

TEST(PrefilterInternals, CapRowHalfWidthMatchesTheSampledCapBoundary) {
  // A 64 x 32 lat-long level; caps from 2.6 degrees to 120 degrees in radius about axes from near
  // the pole to past the equator, every row of the level.
  const LatLongLevel level(Image(64, 32, Rgba(1, 1, 1, 1)));
  int rowsInCap = 0, rowsMissed = 0, wholeParallels = 0;
  for (double thetaAxis : {0.03, 0.4, 1.2, 1.5707963, 2.0, 3.0})
    for (double cosCap : {-0.5, 0.0, 0.3, 0.9, 0.99, 0.999}) {
      const auto boundary = capBoundary(thetaAxis, cosCap);
      for (int y = 0; y < level.height; ++y) {
        const double theta0 = std::acos(level.edgeCos[y]), theta1 = std::acos(level.edgeCos[y + 1]);
        ASSERT_NEAR(theta0, y * kPi / level.height, 1e-9);
        const double expected = bruteHalfWidth(boundary, theta0, theta1, thetaAxis, cosCap);
        const double got = capRowHalfWidth(level, y, std::cos(thetaAxis), std::sin(thetaAxis), cosCap);
        SCOPED_TRACE("axis theta " + std::to_string(thetaAxis) + ", cos cap " + std::to_string(cosCap) + ", row " +
                     std::to_string(y));
        if (expected < 0.0) {
          EXPECT_LT(got, 0.0);
          ++rowsMissed;
          continue;
        }
        ++rowsInCap;
        wholeParallels += got == kPi;
        // The sampled boundary is within 3e-5 rad of the true one; near the poles an azimuth
        // offset is a short arc, so allow 2e-3 rad of azimuth.
        EXPECT_NEAR(got, expected, 2e-3);
      }
    }
  EXPECT_GT(rowsInCap, 300);
  EXPECT_GT(rowsMissed, 300);
  EXPECT_GT(wholeParallels, 20);
}

TEST(PrefilterInternals, CapRowHalfWidthIsWholeRowsForTheWholeSphereOrAnAxisAtAPole) {
  const LatLongLevel level(Image(16, 8, Rgba(1, 1, 1, 1)));
  for (int y = 0; y < level.height; ++y) {
    EXPECT_EQ(capRowHalfWidth(level, y, std::cos(1.0), std::sin(1.0), -1.0), kPi);
    EXPECT_EQ(capRowHalfWidth(level, y, 1.0, 0.0, 0.5), kPi);
  }
}

}  // namespace
}  // namespace brdfbake::detail
