// Catmull-Rom weights (core/math.hpp) against facts that do not come from the formula: a partition
// of unity, interpolation of the samples, exact reproduction of quadratics and the curve's tangent
// at a sample (half the difference of its neighbours). cubeRoot against the C library's std::cbrt
// and exact cubes.
#include <gtest/gtest.h>
#include <brdfbake/core/math.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <random>

namespace brdfbake {
namespace {

// sum_k w[k] f(k - 1): the interpolated value at t of the samples f(-1), f(0), f(1), f(2).
template <class F>
double interpolate(double t, F f) {
  const std::array<double, 4> w = catmullRomWeights(t);
  double sum = 0.0;
  for (int k = 0; k < 4; ++k) sum += w[k] * f(k - 1);
  return sum;
}

TEST(CatmullRomWeights, SumToOneForEveryFraction) {
  for (int i = 0; i <= 100; ++i) {
    const double t = i / 100.0;
    const std::array<double, 4> w = catmullRomWeights(t);
    EXPECT_NEAR(w[0] + w[1] + w[2] + w[3], 1.0, 1e-15) << "t = " << t;
  }
}

TEST(CatmullRomWeights, PassThroughTheSamplesAtTheEnds) {
  const std::array<double, 4> at0 = catmullRomWeights(0.0), at1 = catmullRomWeights(1.0);
  const std::array<double, 4> expected0{0.0, 1.0, 0.0, 0.0}, expected1{0.0, 0.0, 1.0, 0.0};
  for (int k = 0; k < 4; ++k) {
    EXPECT_DOUBLE_EQ(at0[k], expected0[k]) << "k = " << k;
    EXPECT_DOUBLE_EQ(at1[k], expected1[k]) << "k = " << k;
  }
}

TEST(CatmullRomWeights, ReproduceAQuadraticExactly) {
  const auto quadratic = [](double x) { return 3.0 * x * x - 2.0 * x + 0.5; };
  for (double t : {0.0, 0.1, 0.3, 0.5, 0.77, 1.0})
    EXPECT_NEAR(interpolate(t, quadratic), quadratic(t), 1e-14) << "t = " << t;
}

TEST(CatmullRomWeights, TheTangentAtASampleIsHalfTheDifferenceOfItsNeighbours) {
  // Samples 2, -1, 4, 7 at -1, 0, 1, 2: the tangent at 0 is (4 - 2) / 2 = 1, at 1 it is (7 + 1) / 2 = 4.
  const std::array<double, 4> samples{2.0, -1.0, 4.0, 7.0};
  const auto sample = [&](int x) { return samples[x + 1]; };
  const double h = 1e-6;  // one-sided differences: error of order h times the second derivative (~10)
  EXPECT_NEAR((interpolate(h, sample) - interpolate(0.0, sample)) / h, 1.0, 1e-4);
  EXPECT_NEAR((interpolate(1.0, sample) - interpolate(1.0 - h, sample)) / h, 4.0, 1e-4);
}

TEST(CatmullRomWeights, InFloatTheyReproduceAQuadraticWithinRounding) {
  // The quadratic 3x^2 - 2x + 0.5 from its samples 5.5, 0.5, 1.5, 8.5 in float: within a few float
  // ulps of the largest sample (8.5 * 2^-23 ~ 1e-6 each, four terms).
  const std::array<float, 4> samples{5.5f, 0.5f, 1.5f, 8.5f};
  for (float t : {0.0f, 0.3f, 0.6f, 1.0f}) {
    const std::array<float, 4> w = catmullRomWeights(t);
    float value = 0.0f;
    for (int k = 0; k < 4; ++k) value += w[k] * samples[k];
    EXPECT_NEAR(value, 3.0 * t * t - 2.0 * t + 0.5, 1e-5) << "t = " << t;
  }
}

TEST(CubeRoot, AgreesWithTheCLibraryOverItsWholeRange) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> decade(-300.0, 300.0);
  double worst = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const double x = std::pow(10.0, decade(random)), expected = std::cbrt(x);
    worst = std::max(worst, std::abs(cubeRoot(x) - expected) / expected);
  }
  EXPECT_LT(worst, 1e-14);
}

TEST(CubeRoot, GivesExactCubesTheirRoots) {
  for (double k : {1.0, 2.0, 3.0, 10.0, 1e-3, 1e5}) EXPECT_NEAR(cubeRoot(k * k * k), k, 1e-14 * k) << k;
}

TEST(CubeRoot, LeavesTheEdgesToTheCLibrary) {
  EXPECT_EQ(cubeRoot(0.0), 0.0);
  EXPECT_EQ(cubeRoot(-27.0), std::cbrt(-27.0));
  EXPECT_EQ(cubeRoot(1e-310), std::cbrt(1e-310));  // subnormal
  EXPECT_TRUE(std::isinf(cubeRoot(std::numeric_limits<double>::infinity())));
  EXPECT_TRUE(std::isnan(cubeRoot(std::numeric_limits<double>::quiet_NaN())));
}

}  // namespace
}  // namespace brdfbake
