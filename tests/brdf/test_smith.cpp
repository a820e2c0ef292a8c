// Smith's masking-shadowing (brdf/smith.hpp) against independent values: the closed forms written
// out again with tan theta, a numerical integration of the masking function's definition, the
// grazing limits, and the white furnace of a Smith microfacet BRDF without Fresnel.
#include <gtest/gtest.h>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/smith.hpp>
#include <brdfbake/core/error.hpp>

#include <random>

#include "brdf_references.hpp"

namespace brdfbake {
namespace {

// Independent Lambda, as the papers write it: a = 1 / (roughness tan theta).
double lambdaGgx(double theta, double alpha) {
  const double t = std::tan(theta);
  return 0.5 * (-1.0 + std::sqrt(1.0 + alpha * alpha * t * t));
}
double lambdaBeckmann(double theta, double m) {
  const double a = 1.0 / (m * std::tan(theta));
  return 0.5 * (std::erf(a) - 1.0) + std::exp(-a * a) / (2.0 * a * std::sqrt(kPi));
}

TEST(Smith, LambdaMatchesThePublishedClosedForms) {
  for (double r : {0.05, 0.1, 0.3, 0.6, 1.0, 2.0}) {
    for (double deg : {1.0, 10.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0, 89.9}) {
      const double theta = radians(deg), c = std::cos(theta);
      EXPECT_NEAR(smithLambda(c, r, true), lambdaGgx(theta, r), 1e-10 * (1 + lambdaGgx(theta, r))) << r << " " << deg;
      EXPECT_NEAR(smithLambda(c, r, false), lambdaBeckmann(theta, r), 1e-10 * (1 + lambdaBeckmann(theta, r)))
          << r << " " << deg;
      EXPECT_NEAR(smithG1(c, r, true), 1.0 / (1.0 + lambdaGgx(theta, r)), 1e-12);
    }
  }
  // Worked values: GGX alpha = 1 at 45 degrees: (sqrt 2 - 1) / 2; Beckmann a = 1 (m tan theta = 1):
  // (erf(1) - 1) / 2 + exp(-1) / (2 sqrt pi) = -0.0786496 + 0.1037769 = 0.0251273.
  EXPECT_NEAR(smithLambda(std::cos(kPi / 4), 1.0, true), (std::sqrt(2.0) - 1.0) / 2.0, 1e-14);
  EXPECT_NEAR(smithLambda(std::cos(kPi / 4), 1.0, false), 0.0251273, 1e-7);
  EXPECT_EQ(smithG1(1.0, 0.3, true), 1.0);
  EXPECT_EQ(smithG1(1.0, 0.3, false), 1.0);
  EXPECT_EQ(smithG1(0.0, 0.3, true), 0.0);
  EXPECT_EQ(smithG1(-0.2, 0.3, false), 0.0);
}

// 1 + Lambda(v) = ∫ max(0, v.m) D(m) dω_m / cos theta_v: the projected area of the visible microfacets
// equals the projected area of the surface (Heitz 2014 Eq. 2 with Smith's G1 independent of m).
// Midpoint rule over the hemisphere of microfacet normals m.
double maskingIntegral(double thetaV, double roughness, bool ggx) {
  const Vec3 v(std::sin(thetaV), 0.0, std::cos(thetaV));
  const int nt = 4000, np = 720;
  const double dt = (kPi / 2) / nt, dp = kTwoPi / np;
  double sum = 0.0;
  for (int i = 0; i < nt; ++i) {
    const double t = (i + 0.5) * dt, c = std::cos(t), s = std::sin(t);
    const double d = ggx ? ggxD(c, roughness) : beckmannD(c, roughness);
    if (d == 0.0) continue;
    for (int j = 0; j < np; ++j) {
      const double p = (j + 0.5) * dp;
      const double vm = v.x() * s * std::cos(p) + v.z() * c;
      if (vm > 0.0) sum += vm * d * s;
    }
  }
  return sum * dt * dp / v.z();
}

TEST(Smith, G1IsTheNumericalMaskingOfTheDistribution) {
  for (bool ggx : {true, false}) {
    for (double r : {0.1, 0.3, 0.7}) {
      for (double deg : {0.0, 40.0, 70.0, 85.0}) {
        const double theta = radians(deg);
        const double numeric = maskingIntegral(theta, r, ggx);
        const double lambda = deg == 0.0 ? 0.0 : smithLambda(std::cos(theta), r, ggx);
        EXPECT_NEAR(1.0 + lambda, numeric, 2e-4 * numeric) << (ggx ? "ggx " : "beckmann ") << r << " at " << deg;
      }
    }
  }
}

TEST(Smith, GOverNlNvIsG2OverTheCosinesAndFiniteAtGrazing) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.02, kPi / 2 - 0.02);
  for (int i = 0; i < 500; ++i) {
    const double tv = u(rng), tl = u(rng), r = 0.05 + u(rng) / 2;
    const double nv = std::cos(tv), nl = std::cos(tl);
    for (bool ggx : {true, false}) {
      const double lv = ggx ? lambdaGgx(tv, r) : lambdaBeckmann(tv, r);
      const double ll = ggx ? lambdaGgx(tl, r) : lambdaBeckmann(tl, r);
      const double correlated = 1.0 / (1.0 + lv + ll) / (nl * nv);
      const double separable = 1.0 / ((1.0 + lv) * (1.0 + ll)) / (nl * nv);
      EXPECT_NEAR(smithGOverNlNv(nv, nl, 0.5, 0.5, r, ggx, true), correlated, 1e-9 * correlated);
      EXPECT_NEAR(smithGOverNlNv(nv, nl, 0.5, 0.5, r, ggx, false), separable, 1e-9 * separable);
      EXPECT_GE(correlated, separable);  // 1 + a + b <= (1 + a)(1 + b)
    }
  }
  // As n.v -> 0, n.v Lambda(v) -> alpha / 2 (GGX) and m / (2 sqrt pi) (Beckmann).
  const double nl = 0.6, alpha = 0.3;
  const double ggxLimit = 1.0 / (nl * alpha / 2), beckmannLimit = 1.0 / (nl * alpha / (2 * std::sqrt(kPi)));
  EXPECT_NEAR(smithGOverNlNv(0.0, nl, 0.5, 0.5, alpha, true, true), ggxLimit, 1e-12 * ggxLimit);
  EXPECT_NEAR(smithGOverNlNv(1e-9, nl, 0.5, 0.5, alpha, true, true), ggxLimit, 1e-6 * ggxLimit);
  EXPECT_NEAR(smithGOverNlNv(0.0, nl, 0.5, 0.5, alpha, false, true), beckmannLimit, 1e-12 * beckmannLimit);
  EXPECT_EQ(smithGOverNlNv(0.0, 0.0, 0.5, 0.5, alpha, true, true), 0.0);
  EXPECT_EQ(smithGOverNlNv(0.5, -0.1, 0.5, 0.5, alpha, true, false), 0.0);
  EXPECT_EQ(smithGOverNlNv(0.5, 0.5, -0.1, 0.5, alpha, false, false), 0.0);
}

// The albedo of a microfacet BRDF (360 azimuth steps).
double albedo(const CookTorranceMaterial& m, double thetaV) { return test::halfVectorAlbedo(m, thetaV, 360); }

CookTorranceMaterial smithMaterial(MicrofacetDistribution distribution, double roughness,
                                   MicrofacetShadowing shadowing) {
  CookTorranceParams p;
  p.mode = CookTorranceMode::Lighting;
  p.distribution = distribution;
  p.roughness = roughness;
  p.fresnel = FresnelTerm::fromF0(Rgb::Ones());  // F = 1
  p.shadowing = shadowing;
  return CookTorranceMaterial(p);
}

// The albedo at normal incidence written as a 1-D integral over the half-vector angle t (v = n:
// l at 2t, n.l = cos 2t, v.h = cos t, G2 = G1(l) for both forms since Lambda(v) = 0):
// E = ∫_0^{pi/4} D(t) cos(t) / (1 + Lambda(2t)) 2 pi sin(t) dt, with the independent Lambda above.
double normalAlbedo(double roughness, bool ggx) {
  const int steps = 200000;
  const double dt = (kPi / 4) / steps;
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) {
    const double t = (i + 0.5) * dt, c = std::cos(t);
    const double d = ggx ? ggxD(c, roughness) : beckmannD(c, roughness);
    const double lambda = ggx ? lambdaGgx(2 * t, roughness) : lambdaBeckmann(2 * t, roughness);
    sum += d * c / (1.0 + lambda) * kTwoPi * std::sin(t);
  }
  return sum * dt;
}

TEST(Smith, WhiteFurnaceOfTheMicrofacetBrdfWithoutFresnel) {
  // Single scattering loses energy (light masked or shadowed is not reflected again, and microfacets
  // tilted beyond 45 degrees reflect a normal view below the horizon): the albedo is at most 1,
  // correlated >= separable (G2 correlated >= separable pointwise), close to 1 for smooth surfaces.
  for (auto d : {MicrofacetDistribution::Ggx, MicrofacetDistribution::Beckmann}) {
    const bool ggx = d == MicrofacetDistribution::Ggx;
    for (double r : {0.05, 0.3, 1.0}) {
      for (double deg : {0.0, 45.0, 75.0, 88.0}) {
        const double correlated = albedo(smithMaterial(d, r, MicrofacetShadowing::SmithCorrelated), radians(deg));
        const double separable = albedo(smithMaterial(d, r, MicrofacetShadowing::SmithSeparable), radians(deg));
        EXPECT_LE(correlated, 1.0 + 2e-3) << r << " " << deg;
        EXPECT_LE(separable, correlated + 1e-9) << r << " " << deg;
        EXPECT_GT(separable, 0.0);
        if (r <= 0.05 && deg <= 45.0) {
          EXPECT_GT(correlated, 0.99) << r << " " << deg;
        }
      }
      // The energy lost at normal incidence, from the 1-D integral: e.g. GGX alpha 0.3 keeps 0.877
      // (at most 1 / (1 + alpha^2) = 0.917 reach the upper hemisphere), alpha 1 keeps 0.307.
      const double expected = normalAlbedo(r, ggx);
      EXPECT_NEAR(albedo(smithMaterial(d, r, MicrofacetShadowing::SmithCorrelated), 0.0), expected, 2e-3)
          << (ggx ? "ggx " : "beckmann ") << r;
      if (ggx) {
        EXPECT_LE(expected, 1.0 / (1.0 + r * r) + 1e-9);
      }
    }
  }
  EXPECT_NEAR(normalAlbedo(0.3, true), 0.877, 1e-3);
  EXPECT_NEAR(normalAlbedo(1.0, true), 0.307, 1e-3);
}

TEST(Smith, ShadowingSelectsTheTermAndNames) {
  // With the light on the mirror direction at normal view, H = N, every G is about 1 for a smooth
  // surface, so the three BRDFs agree there; at grazing they differ (V-cavity against Smith).
  const Vec3 n = Vec3::UnitZ(), v = Vec3::UnitZ();
  const double vc = smithMaterial(MicrofacetDistribution::Ggx, 0.05, MicrofacetShadowing::VCavity).brdf(n, v, v)[0];
  const double sc =
      smithMaterial(MicrofacetDistribution::Ggx, 0.05, MicrofacetShadowing::SmithCorrelated).brdf(n, v, v)[0];
  EXPECT_NEAR(sc / vc, 1.0, 1e-12);
  const double theta = radians(80.0);
  const Vec3 grazing(std::sin(theta), 0.0, std::cos(theta)), mirror(-grazing.x(), 0.0, grazing.z());
  const double vg =
      smithMaterial(MicrofacetDistribution::Ggx, 0.3, MicrofacetShadowing::VCavity).brdf(n, grazing, mirror)[0];
  const double sg =
      smithMaterial(MicrofacetDistribution::Ggx, 0.3, MicrofacetShadowing::SmithSeparable).brdf(n, grazing, mirror)[0];
  EXPECT_GT(std::abs(sg / vg - 1.0), 0.1) << "at the rim V-cavity and Smith differ by 10 % or more";
  for (auto s :
       {MicrofacetShadowing::VCavity, MicrofacetShadowing::SmithCorrelated, MicrofacetShadowing::SmithSeparable}) {
    EXPECT_EQ(parseMicrofacetShadowing(toString(s)), s);
  }
  EXPECT_THROW(parseMicrofacetShadowing("smith"), Error);
  // The baker's tabulated microfacet path holds the V-cavity G only.
  EXPECT_TRUE(smithMaterial(MicrofacetDistribution::Ggx, 0.3, MicrofacetShadowing::VCavity)
                  .microfacetLobe(Vec3(0, 0.6, 0.8), v));
  EXPECT_FALSE(smithMaterial(MicrofacetDistribution::Ggx, 0.3, MicrofacetShadowing::SmithCorrelated)
                   .microfacetLobe(Vec3(0, 0.6, 0.8), v));
}

}  // namespace
}  // namespace brdfbake
