// Phong and Blinn-Phong against their defining formulas, and their radial decompositions against
// direct evaluation.
#include <gtest/gtest.h>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/core/error.hpp>

#include <random>

namespace brdfbake {
namespace {

std::vector<ShadingGeometry> randomGeometries(int count, const Vec3& view = Vec3::UnitZ()) {
  std::mt19937 rng(17);
  std::normal_distribution<double> g;
  std::vector<ShadingGeometry> out;
  while (static_cast<int>(out.size()) < count) {
    Vec3 n(g(rng), g(rng), g(rng));
    n.normalize();
    if (n.dot(view) <= 0.01) continue;  // visible normals
    out.push_back({n, view, reflect(view, n)});
  }
  return out;
}

Rgb sumOfLobes(const std::vector<RadialLobe>& lobes, const Vec3& r) {
  Rgb sum = Rgb::Zero();
  for (const auto& lobe : lobes) sum += lobe.weight * lobe.profile(r.dot(lobe.axis));
  return sum;
}

TEST(PhongLobe, Basics) {
  EXPECT_DOUBLE_EQ(phongLobe(0.5, 2.0), 0.25);
  EXPECT_EQ(phongLobe(-0.5, 2.0), 0.0);
  EXPECT_EQ(phongLobe(0.3, 0.0), 1.0);  // exponent 0: the hemisphere
  EXPECT_EQ(phongLobe(0.0, 0.0), 0.0);
  EXPECT_NEAR(phongLobe(1.0 - 1e-9, 1e6), std::exp(-1e-3), 1e-9);
}

TEST(PhongLobe, NormalizedLobeIntegratesToOne) {
  // (n + 2)/(2 pi) ∫ cos^n(t) cos(t) dω over the hemisphere = 1, by midpoint quadrature.
  for (double n : {0.0, 1.0, 10.0, 100.0, 1000.0}) {
    const int steps = 200000;
    double sum = 0.0;
    for (int i = 0; i < steps; ++i) {
      const double t = (i + 0.5) * (kPi / 2) / steps;
      sum += phongLobe(std::cos(t), n) * std::cos(t) * std::sin(t);
    }
    EXPECT_NEAR(phongNormalization(n) * kTwoPi * sum * (kPi / 2) / steps, 1.0, 1e-6) << n;
  }
}

TEST(PhongMaterial, ShadeIsTheDefiningFormula) {
  const PhongMaterial m(Rgb(1, 0.5, 0.25), 20, Rgb(0.1, 0.2, 0.3));
  const Vec3 l = Vec3(0.3, 0.4, 0.8).normalized();
  for (const auto& g : randomGeometries(200)) {
    const Rgb expected = Rgb(1, 0.5, 0.25) * std::pow(std::max(0.0, g.reflected.dot(l)), 20) +
                         Rgb(0.1, 0.2, 0.3) * std::max(0.0, g.normal.dot(l));
    EXPECT_LT((m.shade(g, l) - expected).abs().maxCoeff(), 1e-14);
  }
}

TEST(PhongMaterial, RadialLobesReproduceShade) {
  const PhongMaterial specularOnly(Rgb::Ones(), 30);
  const PhongMaterial withDiffuse(Rgb::Ones(), 30, Rgb(0.5, 0.5, 0.5));
  const Vec3 l = Vec3(1, 1, 1).normalized();
  for (const auto& g : randomGeometries(200)) {
    const auto a = specularOnly.radialLobes(l, g.view);
    ASSERT_TRUE(a.has_value());
    EXPECT_NEAR((sumOfLobes(*a, g.reflected) - specularOnly.shade(g, l)).abs().maxCoeff(), 0.0, 1e-13);
    const auto b = withDiffuse.radialLobes(g.view, g.view);  // light at the eye: diffuse is radial too
    ASSERT_TRUE(b.has_value());
    EXPECT_NEAR((sumOfLobes(*b, g.reflected) - withDiffuse.shade(g, g.view)).abs().maxCoeff(), 0.0, 1e-12);
  }
  EXPECT_FALSE(withDiffuse.radialLobes(l, Vec3::UnitZ()).has_value());  // diffuse under a general light needs n
  EXPECT_TRUE(specularOnly.viewIndependent());
  EXPECT_FALSE(withDiffuse.viewIndependent());
}

TEST(PhongMaterial, RejectsBadParameters) {
  EXPECT_THROW(PhongMaterial(Rgb::Ones(), -1), Error);
  EXPECT_THROW(PhongMaterial(Rgb::Ones(), NAN), Error);
  EXPECT_THROW(PhongMaterial(Rgb(1, -1, 1), 10), Error);
}

TEST(BlinnPhong, ExactConversionEqualsPhongForALightAtTheEye) {
  // Light at the eye: every normal is in the plane of incidence, so the exact conversion matches.
  const PhongMaterial phong(Rgb::Ones(), 50);
  const BlinnPhongMaterial blinn(Rgb::Ones(), 50, BlinnConversion::Exact);
  for (const auto& g : randomGeometries(500)) {
    EXPECT_NEAR(blinn.shade(g, g.view)[0], phong.shade(g, g.view)[0], 1e-12) << g.normal.transpose();
  }
}

TEST(BlinnPhong, ShadeIsTheDefiningFormula) {
  const BlinnPhongMaterial m(Rgb::Ones(), 40, Rgb(0.2, 0.2, 0.2));
  const Vec3 l = Vec3(-0.2, 0.5, 0.8).normalized();
  for (const auto& g : randomGeometries(200)) {
    const double nl = g.normal.dot(l);
    const Vec3 h = (l + g.view).normalized();
    const double expected = nl > 0 ? std::pow(std::max(0.0, g.normal.dot(h)), 40) + 0.2 * nl : 0.0;
    EXPECT_NEAR(m.shade(g, l)[0], expected, 1e-13);
  }
}

TEST(BlinnPhong, PoliciesSetTheExponent) {
  EXPECT_EQ(BlinnPhongMaterial(Rgb::Ones(), 25, BlinnConversion::FourN).exponent(), 100);
  EXPECT_NEAR(BlinnPhongMaterial(Rgb::Ones(), 25, BlinnConversion::Fit).exponent(), blinnFitExponent(25), 1e-9);
}

TEST(BlinnPhong, LightBelowTheHorizonGivesNothing) {
  const BlinnPhongMaterial m(Rgb::Ones(), 10, Rgb::Ones());
  const ShadingGeometry g{Vec3::UnitZ(), Vec3(0, 0.6, 0.8), reflect(Vec3(0, 0.6, 0.8), Vec3(Vec3::UnitZ()))};
  EXPECT_EQ(m.shade(g, Vec3(0, -0.6, -0.8))[0], 0.0);
  EXPECT_EQ(m.shade(g, Vec3(1, 0, 0))[0], 0.0);  // exactly on the horizon
}

TEST(BlinnPhong, EyeLightLobesReproduceShade) {
  const BlinnPhongMaterial m(Rgb::Ones(), 30, BlinnConversion::Exact, Rgb(0.3, 0.3, 0.3));
  for (const auto& g : randomGeometries(200)) {
    const auto lobes = m.radialLobes(g.view, g.view);
    ASSERT_TRUE(lobes.has_value());
    EXPECT_NEAR((sumOfLobes(*lobes, g.reflected) - m.shade(g, g.view)).abs().maxCoeff(), 0.0, 1e-12);
  }
}

TEST(ShadingGeometry, ReflectionRecoversTheNormal) {
  for (const auto& g : randomGeometries(100)) {
    const ShadingGeometry back = geometryForReflection(g.reflected, g.view);
    EXPECT_NEAR((back.normal - g.normal).norm(), 0.0, 1e-12);
  }
  // r = -v (the sphere map's rim): a grazing normal, finite.
  const ShadingGeometry rim = geometryForReflection(-Vec3::UnitZ(), Vec3::UnitZ());
  EXPECT_TRUE(rim.normal.allFinite());
  EXPECT_NEAR(rim.normal.dot(Vec3::UnitZ()), 0.0, 1e-15);
}

}  // namespace
}  // namespace brdfbake
