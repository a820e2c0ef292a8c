// The R.V -> N.H exponent conversion (Zimmons & Bastos 1999 section 5.1.1): its limits, its stability, and
// the three policies' distance from Phong.
#include <gtest/gtest.h>
#include <brdfbake/brdf/blinn_conversion.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/core/error.hpp>

namespace brdfbake {
namespace {

TEST(BlinnExponentRatio, LimitIsFourAtNormalIncidence) {
  EXPECT_EQ(*blinnExponentRatio(1.0), 4.0);
  // Near x = 1 the ratio is 4 + 4e + 10e^2 + O(e^3) with e = 1 - x; the naive formula loses ~5 digits at
  // e = 1e-12, the stable one keeps them.
  for (double e : {1e-3, 1e-5, 1e-8, 1e-12, 1e-15}) {
    const double x = 1.0 - e;
    const double exactE = 1.0 - x;  // representable e
    EXPECT_NEAR(*blinnExponentRatio(x), 4.0 + 4.0 * exactE + 10.0 * exactE * exactE,
                100 * exactE * exactE * exactE + 1e-14)
        << "e = " << e;
  }
}

TEST(BlinnExponentRatio, MatchesTheClosedFormAwayFromOne) {
  for (double x = 0.71; x < 0.999; x += 0.01) {
    EXPECT_NEAR(*blinnExponentRatio(x), std::log(2 * x * x - 1) / std::log(x),
                1e-12 * std::abs(std::log(2 * x * x - 1) / std::log(x)));
  }
}

TEST(BlinnExponentRatio, HasNoValueAtOrBelowOneOverRootTwo) {
  EXPECT_FALSE(blinnExponentRatio(1.0 / std::sqrt(2.0)).has_value());
  EXPECT_FALSE(blinnExponentRatio(0.5).has_value());
  EXPECT_FALSE(blinnExponentRatio(-1.0).has_value());
  EXPECT_FALSE(blinnExponentRatio(1.0 + 1e-12).has_value());
  EXPECT_FALSE(blinnExponentRatio(std::nan("")).has_value());
  // Just above 1/sqrt 2 the ratio is large but finite.
  const auto big = blinnExponentRatio(1.0 / std::sqrt(2.0) + 1e-9);
  ASSERT_TRUE(big.has_value());
  EXPECT_TRUE(std::isfinite(*big));
  EXPECT_GT(*big, 40.0);
}

TEST(BlinnExponentRatio, ConvertedLobeEqualsPhongInThePlaneOfIncidence) {
  // (N.H)^(n ratio) = (2 (N.H)^2 - 1)^n = (R.V)^n.
  for (double n : {1.0, 10.0, 100.0, 1000.0}) {
    for (double x = 0.72; x <= 1.0; x += 0.007) {
      const double converted = std::pow(x, n * *blinnExponentRatio(x));
      const double phong = std::pow(2 * x * x - 1, n);
      EXPECT_NEAR(converted, phong, 1e-12 + 1e-10 * phong);
    }
  }
}

// The fit's objective, computed independently by midpoint quadrature.
double distance(double n, double m) {
  const int steps = 100000;
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) {
    const double t = (i + 0.5) * (kPi / 2) / steps;
    const double d = std::pow(std::cos(t), n) - std::pow(std::cos(t / 2), m);
    sum += d * d * std::sin(t);
  }
  return sum;
}

TEST(BlinnFitExponent, IsTheMinimumOfTheL2Distance) {
  for (double n : {1.0, 10.0, 100.0, 1000.0}) {
    const double m = blinnFitExponent(n);
    const double at = distance(n, m);
    EXPECT_LE(at, distance(n, m * 1.01)) << n;
    EXPECT_LE(at, distance(n, m * 0.99)) << n;
    EXPECT_LT(at, distance(n, 4 * n) + 1e-15) << n;
  }
  // For sharp lobes the fit approaches the classic 4n (the ratio's limit at the peak).
  EXPECT_NEAR(blinnFitExponent(1000) / 4000, 1.0, 0.02);
  EXPECT_THROW(blinnFitExponent(0.0), Error);
  EXPECT_THROW(blinnFitExponent(-5.0), Error);
}

TEST(BlinnConversion, ParsesPolicyNames) {
  EXPECT_EQ(parseBlinnConversion("exact"), BlinnConversion::Exact);
  EXPECT_EQ(parseBlinnConversion("4n"), BlinnConversion::FourN);
  EXPECT_EQ(parseBlinnConversion("fit"), BlinnConversion::Fit);
  EXPECT_THROW(parseBlinnConversion("4N"), Error);
}

}  // namespace
}  // namespace brdfbake
