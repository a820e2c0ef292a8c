// Reflection lobes (brdf/reflection_lobe.hpp): each density integrates to the probability of a valid
// draw (numerical quadrature over the sphere), the draws follow it (their share within caps about
// the peak against the quadrature of the density there), and the materials describe their BRDFs.
#include <gtest/gtest.h>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/brdf/npr.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/brdf/reflection_lobe.hpp>

#include <cmath>

namespace brdfbake {
namespace {

// ∫ density over the directions within `capCos` of `centre` (midpoint rule in angle about it).
double densityIntegral(const ReflectionLobe& lobe, const Vec3& view, const Vec3& centre, double capCos) {
  const Vec3 t = anyPerpendicular(centre), b = centre.cross(t);
  const double capAngle = std::acos(std::clamp(capCos, -1.0, 1.0));
  const int nt = 3000, np = 360;
  const double dt = capAngle / nt, dp = kTwoPi / np;
  double sum = 0.0;
  for (int i = 0; i < nt; ++i) {
    const double a = (i + 0.5) * dt;
    for (int j = 0; j < np; ++j) {
      const double p = (j + 0.5) * dp;
      const Vec3 l = std::sin(a) * (std::cos(p) * t + std::sin(p) * b) + std::cos(a) * centre;
      sum += reflectionLobeDensity(lobe, view, l) * std::sin(a);
    }
  }
  return sum * dt * dp;
}

struct DrawStats {
  double valid = 0.0, inCap = 0.0;
};
// The share of draws on a stratified grid of (u1, u2) that are valid, and that fall within the cap.
DrawStats drawShares(const ReflectionLobe& lobe, const Vec3& view, const Vec3& centre, double capCos) {
  const int n1 = 1000, n2 = 100;
  DrawStats s;
  for (int i = 0; i < n1; ++i)
    for (int j = 0; j < n2; ++j) {
      const auto l = sampleReflectionLobe(lobe, view, (i + 0.5) / n1, (j + 0.5) / n2);
      if (!l) continue;
      EXPECT_NEAR(l->norm(), 1.0, 1e-12);
      s.valid += 1.0;
      if (l->dot(centre) >= capCos) s.inCap += 1.0;
    }
  s.valid /= n1 * n2;
  s.inCap /= n1 * n2;
  return s;
}

TEST(ReflectionLobe, DrawsFollowTheirDensity) {
  const Vec3 n = Vec3::UnitZ();
  for (double viewDeg : {0.0, 40.0, 75.0}) {
    const Vec3 v(std::sin(radians(viewDeg)), 0.0, std::cos(radians(viewDeg)));
    const Vec3 r = reflect(v, n);
    const std::vector<ReflectionLobe> lobes{
        {ReflectionLobeShape::Cosine, n, 0.0, 1.0},       {ReflectionLobeShape::PowerCosine, r, 50.0, 1.0},
        {ReflectionLobeShape::PowerCosine, r, 0.0, 1.0},  {ReflectionLobeShape::Beckmann, n, 0.3, 1.0},
        {ReflectionLobeShape::Ggx, n, 0.2, 1.0},          {ReflectionLobeShape::Ggx, n, 0.6, 1.0},
        {ReflectionLobeShape::BlinnPhong, n, 200.0, 1.0},
    };
    for (const auto& lobe : lobes) {
      const Vec3 peak = reflectionLobePeak(lobe, v);
      const double width = reflectionLobeWidth(lobe);
      // Half-vector densities p(h) / (4 v.h) are singular (integrably) towards l = -v, 30 degrees from
      // the peak at a 75-degree view, where the quadrature converges slowly.
      const double tolerance = viewDeg > 60.0 ? 6e-3 : 2e-3;
      const DrawStats all = drawShares(lobe, v, peak, -1.0);
      const double total = densityIntegral(lobe, v, peak, -1.0);
      EXPECT_NEAR(total, all.valid, tolerance) << int(lobe.shape) << " " << lobe.parameter << " at " << viewDeg;
      if (lobe.shape == ReflectionLobeShape::Cosine || lobe.shape == ReflectionLobeShape::PowerCosine) {
        EXPECT_NEAR(total, 1.0, 2e-3);
      }
      const double capCos = std::cos(std::min(kPi / 2, 1.5 * width));
      const DrawStats cap = drawShares(lobe, v, peak, capCos);
      EXPECT_NEAR(densityIntegral(lobe, v, peak, capCos), cap.inCap, 1.5 * tolerance)
          << int(lobe.shape) << " " << lobe.parameter << " at " << viewDeg;
    }
  }
}

TEST(ReflectionLobe, WidthsAreTheHalfMaximumAngles) {
  // max(0, cos)^N halves at acos(2^(-1/N)) ~ sqrt(2 ln 2 / N): width 1/sqrt(N) for large N.
  EXPECT_NEAR(reflectionLobeWidth({ReflectionLobeShape::PowerCosine, Vec3::UnitZ(), 10000.0, 1.0}), 0.01, 1e-5);
  // A half vector tilted by t tilts the mirrored view by 2t: Blinn-Phong N is twice as wide in l.
  EXPECT_NEAR(reflectionLobeWidth({ReflectionLobeShape::BlinnPhong, Vec3::UnitZ(), 10000.0, 1.0}), 0.02, 2e-5);
  // Beckmann exp(-tan^2 / m^2): sqrt(2) m in l for small m.
  EXPECT_NEAR(reflectionLobeWidth({ReflectionLobeShape::Beckmann, Vec3::UnitZ(), 0.01, 1.0}), std::sqrt(2.0) * 0.01,
              1e-6);
  EXPECT_EQ(reflectionLobeWidth({ReflectionLobeShape::Cosine, Vec3::UnitZ(), 0.0, 1.0}), 1.0);
}

TEST(ReflectionLobe, MaterialsDescribeTheirBrdfs) {
  const Vec3 v = Vec3::UnitZ(), n = Vec3(0.3, 0.0, 1.0).normalized();
  const ShadingGeometry g{n, v, reflect(v, n)};
  const auto phong = PhongMaterial(Rgb::Ones(), 50.0, Rgb::Constant(0.5)).reflectionLobes(g);
  ASSERT_TRUE(phong);
  ASSERT_EQ(phong->size(), 2u);
  EXPECT_EQ((*phong)[0].shape, ReflectionLobeShape::PowerCosine);
  EXPECT_NEAR(((*phong)[0].axis - g.reflected).norm(), 0.0, 1e-12);
  EXPECT_EQ((*phong)[1].shape, ReflectionLobeShape::Cosine);
  EXPECT_NEAR(PhongMaterial(Rgb::Ones(), 50.0).lightColorPerIrradiance(), 1.0 / kPi, 1e-15);

  CookTorranceParams p;
  p.mode = CookTorranceMode::Lighting;
  p.distribution = MicrofacetDistribution::Ggx;
  p.roughness = 0.2;
  const auto ct = CookTorranceMaterial(p).reflectionLobes(g);
  ASSERT_TRUE(ct);
  EXPECT_EQ(ct->front().shape, ReflectionLobeShape::Ggx);
  EXPECT_EQ(ct->front().parameter, 0.2);
  EXPECT_EQ(CookTorranceMaterial(p).lightColorPerIrradiance(), 1.0);
  p.mode = CookTorranceMode::Reflectance;
  EXPECT_FALSE(CookTorranceMaterial(p).reflectionLobes(g)) << "no light to integrate in reflectance mode";
  EXPECT_FALSE(SilhouetteMaterial(20.0).reflectionLobes(g)) << "hand-designed maps have no BRDF";

  // A fitted model: one Phong lobe per channel with exponents within 1.5x merge into one; a
  // Lafortune lobe keeps its own axis; the diffuse term is a cosine lobe.
  LobeModel model;
  for (const char* name : {"R", "G", "B"}) {
    LobeChannel channel{name, 0.1, {}};
    channel.lobes.push_back({{0.5}, {std::string(name) == "R" ? 100.0 : 120.0}, -1.0, false, 0.0});
    channel.lobes.push_back({{0.2}, {10.0}, -1.4, false, 0.0});
    model.channels.push_back(channel);
  }
  const auto fitted = LobeMaterial(model, LobeMaterialMode::Lighting).reflectionLobes(g);
  ASSERT_TRUE(fitted);
  ASSERT_EQ(fitted->size(), 3u);
  EXPECT_NEAR(((*fitted)[0].axis - g.reflected).norm(), 0.0, 1e-12);
  EXPECT_GT((*fitted)[0].parameter, 100.0);
  EXPECT_LT((*fitted)[0].parameter, 120.0);
  EXPECT_GT(((*fitted)[1].axis - g.reflected).norm(), 1e-3) << "the Lafortune axis tilts towards the horizon";
  EXPECT_EQ((*fitted)[2].shape, ReflectionLobeShape::Cosine);
  EXPECT_FALSE(LobeMaterial(model, LobeMaterialMode::Reflectance).reflectionLobes(g));
}

// Phong's two parts are weighed by their shares of a white furnace (only the ratio matters): the
// integrals of max(0, r.l)^n and of max(0, n.l) over the sphere, summed here with the midpoint rule
// in theta (the azimuth gives 2 pi), times the parts' luminances 1 and 0.5.
TEST(ReflectionLobe, PhongWeightsAreTheFurnaceSharesOfItsParts) {
  const auto cosinePowerIntegral = [](double exponent) {
    constexpr int kSteps = 200000;
    double sum = 0.0;
    for (int i = 0; i < kSteps; ++i) {
      const double theta = (i + 0.5) / kSteps * 0.5 * kPi;
      sum += std::pow(std::cos(theta), exponent) * std::sin(theta);
    }
    return 2.0 * kPi * sum * 0.5 * kPi / kSteps;
  };
  const Vec3 v = Vec3::UnitZ(), n = Vec3(0.3, 0.0, 1.0).normalized();
  const ShadingGeometry g{n, v, reflect(v, n)};
  for (const double exponent : {1.0, 10.0, 50.0}) {
    const auto lobes = PhongMaterial(Rgb::Ones(), exponent, Rgb::Constant(0.5)).reflectionLobes(g);
    ASSERT_TRUE(lobes);
    ASSERT_EQ(lobes->size(), 2u);
    const double expected = cosinePowerIntegral(exponent) / (0.5 * cosinePowerIntegral(1.0));
    EXPECT_NEAR((*lobes)[0].weight / (*lobes)[1].weight, expected, 1e-6 * expected) << exponent;
  }
}

}  // namespace
}  // namespace brdfbake
