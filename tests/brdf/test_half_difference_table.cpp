// The half-difference table term of a lobe model (brdf/half_difference_table.hpp, brdf/lobes.hpp),
// against its formula typed out here from the vectors: h = normalize(l + v), theta_h = acos(h.z),
// theta_d = acos(l.h), hats max(0, 1 - |x - k|), Bernstein polynomials from their binomials.
#include <gtest/gtest.h>

#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/core/error.hpp>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace brdfbake {
namespace {

constexpr double kPiHere = std::numbers::pi;

// A direction above the horizon, uniform in (cos theta, phi) with cos theta in [0.02, 1].
Vec3 randomUpper(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.02, 1.0), phi(0.0, 2.0 * kPiHere);
  const double c = u(rng), s = std::sqrt(1.0 - c * c), p = phi(rng);
  return {s * std::cos(p), s * std::sin(p), c};
}

// ln f of the table typed out: sum_kj a_kj hat_k(x) B_j(s) with K knots and degree 3.
double typedOutLog(const std::vector<double>& a, int knots, const Vec3& l, const Vec3& v) {
  const Vec3 h = (l + v).normalized();
  const double thetaH = std::acos(std::min(1.0, h.z())), thetaD = std::acos(std::min(1.0, l.dot(h)));
  const double x = std::sqrt(thetaH / (kPiHere / 2.0)) * (knots - 1), s = thetaD / (kPiHere / 2.0);
  const double binomial[4] = {1.0, 3.0, 3.0, 1.0};
  double sum = 0.0;
  for (int k = 0; k < knots; ++k) {
    const double hat = std::max(0.0, 1.0 - std::abs(x - k));
    for (int j = 0; j < 4; ++j)
      sum += a[static_cast<std::size_t>(k * 4 + j)] * hat * binomial[j] * std::pow(s, j) * std::pow(1.0 - s, 3 - j);
  }
  return sum;
}

LobeModel tableModel(int knots, std::vector<double> coefficients) {
  LobeModel model;
  model.halfDifference = {knots, 3};
  LobeChannel channel;
  channel.name = "Y";
  channel.halfDifferenceCoefficients = std::move(coefficients);
  model.channels.push_back(channel);
  model.validate();
  return model;
}

std::vector<double> randomCoefficients(int count, std::mt19937& rng) {
  std::uniform_real_distribution<double> a(-3.0, 2.0);
  std::vector<double> out(static_cast<std::size_t>(count));
  for (double& x : out) x = a(rng);
  return out;
}

TEST(HalfDifferenceTable, EvaluatesItsFormulaTypedOutAndIsReciprocal) {
  std::mt19937 rng(5);
  const int knots = 5;
  const std::vector<double> a = randomCoefficients(knots * 4, rng);
  const LobeModel model = tableModel(knots, a);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 l = randomUpper(rng), v = randomUpper(rng);
    const double expected = std::exp(typedOutLog(a, knots, l, v));
    ASSERT_NEAR(model.evaluate(0, l, v), expected, 1e-9 * expected) << l.transpose() << " | " << v.transpose();
    ASSERT_NEAR(model.evaluate(0, v, l), model.evaluate(0, l, v), 1e-12 * expected);
  }
  // Below the horizon the model is 0, as every lobe model.
  EXPECT_EQ(model.evaluate(0, Vec3(0.6, 0.0, -0.8), Vec3(0.0, 0.0, 1.0)), 0.0);
}

TEST(HalfDifferenceTable, OnTheMirrorItIsTheFirstKnotsProfileInThetaD) {
  // On the mirror direction h = n: theta_h = 0 (only knot 0's hat is 1) and theta_d = theta_v.
  std::mt19937 rng(6);
  const std::vector<double> a = randomCoefficients(6 * 4, rng);
  const LobeModel model = tableModel(6, a);
  for (double u : {0.05, 0.3, 0.71, 1.0}) {
    const double s = std::acos(u) / (kPiHere / 2.0);
    const double profile =
        a[0] * std::pow(1 - s, 3) + a[1] * 3 * s * std::pow(1 - s, 2) + a[2] * 3 * s * s * (1 - s) + a[3] * s * s * s;
    EXPECT_NEAR(model.mirrorValue(0, u), std::exp(profile), 1e-12 * std::exp(profile)) << u;
  }
}

TEST(HalfDifferenceTable, EqualCoefficientsGiveAConstant) {
  // Hats and Bernstein polynomials each sum to 1: every a_kj = c gives f = e^c everywhere.
  std::mt19937 rng(7);
  const LobeModel model = tableModel(12, std::vector<double>(12 * 4, -1.5));
  for (int i = 0; i < 500; ++i) {
    const Vec3 l = randomUpper(rng), v = randomUpper(rng);
    ASSERT_NEAR(model.evaluate(0, l, v), std::exp(-1.5), 1e-13);
  }
}

TEST(HalfDifferenceTable, ValidationNamesWhatIsWrong) {
  const auto message = [](const LobeModel& model) {
    try {
      model.validate();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  LobeModel model = tableModel(4, std::vector<double>(16, 0.0));
  model.channels[0].halfDifferenceCoefficients.pop_back();
  EXPECT_NE(message(model).find("channel 'Y' table: 16 coefficient(s) expected"), std::string::npos) << message(model);
  model.channels[0].halfDifferenceCoefficients = std::vector<double>(16, 0.0);
  model.channels[0].halfDifferenceCoefficients[3] = 51.0;
  EXPECT_NE(message(model).find("|a| <= 50"), std::string::npos) << message(model);
  model.channels[0].halfDifferenceCoefficients[3] = std::nan("");
  EXPECT_NE(message(model).find("finite"), std::string::npos) << message(model);
  model.channels[0].halfDifferenceCoefficients = std::vector<double>(16, 0.0);
  model.channels[0].diffuse = 0.1;
  EXPECT_NE(message(model).find("channel 'Y': a half-difference table has no diffuse term and no lobes"),
            std::string::npos)
      << message(model);
  model.channels[0].diffuse = 0.0;
  model.elevation = LobeElevation::Varying;
  EXPECT_NE(message(model).find("constant elevation and no colour profile"), std::string::npos) << message(model);
  model.elevation = LobeElevation::Constant;
  model.halfDifference = {};
  model.channels[0].halfDifferenceCoefficients = {1.0};
  EXPECT_NE(message(model).find("0 coefficient(s) expected"), std::string::npos) << message(model);
  model.halfDifference = {1, 3};
  EXPECT_NE(message(model).find("2 to 64 knots"), std::string::npos) << message(model);
  model.halfDifference = {4, kMaxTableDegree + 1};
  EXPECT_NE(message(model).find("degree in theta_d"), std::string::npos) << message(model);
}

TEST(HalfDifferenceTable, HasNoPrefilteredFormAndSamplesWhereItsValueIs) {
  std::vector<double> a(12 * 4);
  for (int k = 0; k < 12; ++k)
    for (int j = 0; j < 4; ++j) a[static_cast<std::size_t>(k * 4 + j)] = 4.0 - 1.5 * k;  // a highlight at theta_h = 0
  LobeModel model = tableModel(12, a);
  EXPECT_FALSE(model.allAboutMirror());
  EXPECT_THROW(LobeMaterial(model, LobeMaterialMode::Prefiltered), Error);
  const LobeMaterial material(model, LobeMaterialMode::Lighting);
  ShadingGeometry g;
  g.normal = Vec3::UnitZ();
  g.view = Vec3(0.6, 0.0, 0.8);
  g.reflected = Vec3(-0.6, 0.0, 0.8);
  const auto lobes = material.reflectionLobes(g);
  ASSERT_TRUE(lobes.has_value());
  // A diffuse part and a Blinn-Phong highlight: the table's value falls to half its rise at theta_h =
  // 0.16 degrees (ln f falling 1.5 per knot: at x = ln 2 / 1.5 = 0.46 of the first knot, 0.74 degrees
  // away); the lobe's half width is the first of 0.05, 0.1, 0.2, ... degrees past it, 0.2, an exponent
  // of 1.1e5 held to kMaxLobeExponent.
  ASSERT_EQ(lobes->size(), 2u);
  const ReflectionLobe& highlight = lobes->at(0);
  EXPECT_EQ(highlight.shape, ReflectionLobeShape::BlinnPhong);
  EXPECT_EQ(highlight.parameter, kMaxLobeExponent);
  EXPECT_EQ(lobes->at(1).shape, ReflectionLobeShape::Cosine);
  EXPECT_GT(highlight.weight, 0.0);
  EXPECT_GT(lobes->at(1).weight, 0.0);
}

}  // namespace
}  // namespace brdfbake
