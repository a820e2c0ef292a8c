// Cook-Torrance: distributions and G against their definitions, the reflectance model against the
// lighting model with the light on the mirror direction, the grazing policy, and energy
// conservation of the normalised form by numerical integration.
#include <gtest/gtest.h>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/core/error.hpp>

#include <random>

#include "brdf_references.hpp"

namespace brdfbake {
namespace {
using test::eq13;

// The specular term's albedo with F = 1 (180 azimuth steps).
double specularAlbedo(const CookTorranceMaterial& m, double thetaV) { return test::halfVectorAlbedo(m, thetaV, 180); }

CookTorranceParams params(CookTorranceMode mode, MicrofacetDistribution d, double roughness, FresnelTerm f) {
  CookTorranceParams p;
  p.mode = mode;
  p.distribution = d;
  p.roughness = roughness;
  p.fresnel = std::move(f);
  return p;
}

// 2 pi * integral over theta of f(cos theta) cos theta sin theta (midpoint rule).
template <class F>
double projectedIntegral(const F& f, int steps) {
  double sum = 0.0;
  const double dt = (kPi / 2) / steps;
  for (int i = 0; i < steps; ++i) {
    const double t = (i + 0.5) * dt;
    sum += f(std::cos(t)) * std::cos(t) * std::sin(t);
  }
  return kTwoPi * sum * dt;
}

TEST(Microfacet, DistributionsAreNormalised) {
  for (double m : {0.02, 0.05, 0.1, 0.3, 0.5, 1.0, 2.0}) {
    EXPECT_NEAR(projectedIntegral([m](double c) { return beckmannD(c, m); }, 400000), 1.0, 1e-6) << "beckmann " << m;
    EXPECT_NEAR(beckmannD(1.0, m), 1.0 / (kPi * m * m), 1e-12 / (m * m));
  }
  for (double a : {0.02, 0.05, 0.1, 0.3, 0.5, 1.0, 2.0}) {
    EXPECT_NEAR(projectedIntegral([a](double c) { return ggxD(c, a); }, 400000), 1.0, 1e-6) << "ggx " << a;
    EXPECT_NEAR(ggxD(1.0, a), 1.0 / (kPi * a * a), 1e-12 / (a * a));
  }
  // Beckmann as Cook & Torrance write it: exp(-(tan a / m)^2) / (m^2 cos^4 a), which is pi D.
  const double m = 0.3, alpha = 0.4;
  EXPECT_NEAR(kPi * beckmannD(std::cos(alpha), m),
              std::exp(-std::pow(std::tan(alpha) / m, 2)) / (m * m * std::pow(std::cos(alpha), 4)), 1e-12);
  EXPECT_EQ(beckmannD(0.0, m), 0.0);
  EXPECT_EQ(beckmannD(-0.5, m), 0.0);
  EXPECT_EQ(ggxD(-0.5, m), 0.0);
}

TEST(Microfacet, GeometricAttenuation) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 n = Vec3::UnitZ();
    Vec3 v(g(rng), g(rng), std::abs(g(rng))), l(g(rng), g(rng), std::abs(g(rng)));
    v.normalize();
    l.normalize();
    const Vec3 h = (l + v).normalized();
    const double nh = n.dot(h), nv = n.dot(v), nl = n.dot(l), vh = v.dot(h);
    const double expected = std::min({1.0, 2 * nh * nv / vh, 2 * nh * nl / vh});
    EXPECT_NEAR(cookTorranceG(nh, nv, nl, vh), expected, 1e-14);
    EXPECT_NEAR(cookTorranceGOverNlNv(nh, nv, nl, vh), expected / (nl * nv), 1e-9 * expected / (nl * nv));
  }
  // Zimmons & Bastos 1999 Eq. 8: with H = N (light on the mirror direction) both terms are 2, so G = 1.
  for (double nv : {1.0, 0.7, 0.2, 1e-3}) EXPECT_EQ(cookTorranceG(1.0, nv, nv, nv), 1.0) << nv;
  // Grazing view with the light above the horizon: G cancels 1/N.V, the limit is 2 nh / (vh nl).
  const double nh = 0.8, nl = 0.6, vh = 0.5;
  EXPECT_NEAR(cookTorranceGOverNlNv(nh, 0.0, nl, vh), 2 * nh / (vh * nl), 1e-15);
  EXPECT_NEAR(cookTorranceGOverNlNv(nh, 1e-9, nl, vh), 2 * nh / (vh * nl), 1e-12);
  EXPECT_EQ(cookTorranceGOverNlNv(nh, 0.0, 0.0, vh), 0.0);
  EXPECT_EQ(cookTorranceGOverNlNv(nh, 0.5, -0.1, vh), 0.0);
}

TEST(CookTorrance, ReflectanceIsLightingWithTheLightOnTheMirrorDirection) {
  // For each direction r of a sphere map's grid: lighting with l = r (the view mirrored about the
  // texel's normal) gives H = N and G exactly 1, and its BRDF equals the reflectance-mode value.
  for (auto dist : {MicrofacetDistribution::Beckmann, MicrofacetDistribution::Ggx}) {
    for (auto form : {CookTorranceNormalization::Microfacet, CookTorranceNormalization::CookTorrance1981}) {
      auto lp = params(CookTorranceMode::Lighting, dist, 0.3,
                       FresnelTerm::conductor(Rgb(0.22, 1.02, 1.24), Rgb(3.747, 2.577, 2.397)));
      lp.normalization = form;
      auto rp = lp;
      rp.mode = CookTorranceMode::Reflectance;
      const CookTorranceMaterial lighting(lp), reflectance(rp);
      const Vec3 v = Vec3::UnitZ();
      const int n = 64;
      int compared = 0;
      for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
          const double sx = 2.0 * (x + 0.5) / n - 1.0, sy = 2.0 * (y + 0.5) / n - 1.0;
          if (sx * sx + sy * sy >= 1.0) continue;
          const Vec3 normal(sx, sy, std::sqrt(1.0 - sx * sx - sy * sy));
          const Vec3 r = reflect(v, normal);
          const ShadingGeometry g = geometryForReflection(r, v);
          const double c = g.normal.dot(v);
          if (c < reflectance.grazingCos()) continue;
          const Vec3 h = (r + v).normalized();
          EXPECT_EQ(cookTorranceG(g.normal.dot(h), c, g.normal.dot(r), v.dot(h)), 1.0);
          const Rgb a = lighting.brdf(g.normal, v, r), b = reflectance.unlit(g);
          EXPECT_LT(((a - b) / b).abs().maxCoeff(), 1e-9) << x << " " << y;
          // shade() is radiance: the BRDF times N.L = N.V.
          EXPECT_LT(((lighting.shade(g, r) - c * b) / b).abs().maxCoeff(), 1e-9);
          ++compared;
        }
      }
      EXPECT_GT(compared, 2500);
    }
  }
}

TEST(CookTorrance, ReflectanceIsFOverCosSquaredWithGrazingPolicy) {
  auto p = params(CookTorranceMode::Reflectance, MicrofacetDistribution::Beckmann, 0.3,
                  FresnelTerm::dielectric(Rgb::Constant(1.5)));
  p.specularWeight = 0.7;
  const CookTorranceMaterial m(p);
  const double peak = 1.0 / (kPi * 0.09);  // Beckmann D(1) = 1 / (pi m^2)
  const double cmin = std::cos(radians(80.0));
  EXPECT_NEAR(m.grazingCos(), cmin, 1e-15);
  for (int i = 0; i <= 1000; ++i) {
    const double c = i / 1000.0;
    const double scale = std::max(c, cmin);
    const double expected = 0.7 * peak * (c > 0 ? eq13(c, 1.5) : 1.0) / (4.0 * scale * scale);
    EXPECT_NEAR(m.reflectance(c)[1], expected, 1e-12 * expected) << c;
  }
  // The stated limit at the rim: F(0) = 1 and the scale frozen at c_min.
  EXPECT_NEAR(m.reflectance(0.0)[0], 0.7 * peak / (4 * cmin * cmin), 1e-12);
  EXPECT_NEAR(m.reflectance(1.0)[0], 0.7 * peak * 0.04 / 4, 1e-14);
  // The 1981 form is four times the normalised one.
  p.normalization = CookTorranceNormalization::CookTorrance1981;
  EXPECT_NEAR(CookTorranceMaterial(p).reflectance(0.6)[0], 4 * m.reflectance(0.6)[0], 1e-12);
  // A smaller grazing angle holds the scale earlier.
  p.normalization = CookTorranceNormalization::Microfacet;
  p.grazingAngleDegrees = 60;
  EXPECT_NEAR(CookTorranceMaterial(p).reflectance(0.1)[0], 0.7 * peak * eq13(0.1, 1.5) / (4 * 0.25), 1e-12);
}

TEST(CookTorrance, CopperGoesTowardsWhiteAtGrazing) {
  const CookTorranceMaterial m(params(CookTorranceMode::Reflectance, MicrofacetDistribution::Beckmann, 0.5,
                                      FresnelTerm::conductor(Rgb(0.22, 1.02, 1.24), Rgb(3.747, 2.577, 2.397))));
  const Rgb centre = m.reflectance(1.0), rim = m.reflectance(0.0);
  EXPECT_NEAR(centre[1] / centre[0], 0.6194 / 0.9433, 1e-3);  // the copper F0 ratio
  EXPECT_NEAR(rim[1] / rim[0], 1.0, 1e-12);                   // F(90 deg) = 1: white
  EXPECT_NEAR(rim[2] / rim[0], 1.0, 1e-12);
}

TEST(CookTorrance, NormalisedFormConservesEnergy) {
  // For m in (0, 1], both distributions, every view angle: albedo <= 1 (plus quadrature error).
  for (auto dist : {MicrofacetDistribution::Beckmann, MicrofacetDistribution::Ggx}) {
    for (double m : {0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0}) {
      const CookTorranceMaterial mat(params(CookTorranceMode::Lighting, dist, m, FresnelTerm::fromF0(Rgb::Ones())));
      for (double deg : {0.0, 30.0, 60.0, 75.0, 85.0, 89.0}) {
        const double albedo = specularAlbedo(mat, radians(deg));
        EXPECT_LE(albedo, 1.0 + 1e-3) << (dist == MicrofacetDistribution::Beckmann ? "beckmann " : "ggx ") << m
                                      << " at " << deg;
        EXPECT_GT(albedo, 0.0);
        if (m <= 0.1 && deg <= 30.0) {
          EXPECT_GT(albedo, 0.97) << m << " " << deg;  // narrow lobe: G ~ 1, all reflected
        }
      }
    }
  }
  // The 1981 form is four times larger and so not energy conserving.
  auto p = params(CookTorranceMode::Lighting, MicrofacetDistribution::Beckmann, 0.1, FresnelTerm::fromF0(Rgb::Ones()));
  p.normalization = CookTorranceNormalization::CookTorrance1981;
  EXPECT_GT(specularAlbedo(CookTorranceMaterial(p), 0.0), 3.8);
}

TEST(CookTorrance, LightBelowTheHorizonAndGrazingGeometry) {
  auto p =
      params(CookTorranceMode::Lighting, MicrofacetDistribution::Ggx, 0.3, FresnelTerm::dielectric(Rgb::Constant(1.5)));
  p.specularWeight = 0.5;
  p.diffuse = Rgb(0.8, 0.2, 0.1);
  const CookTorranceMaterial m(p);
  const Vec3 v = Vec3::UnitZ();
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 r = Vec3(g(rng), g(rng), g(rng)).normalized();
    const ShadingGeometry geo = geometryForReflection(r, v);
    const Vec3 l = Vec3(g(rng), g(rng), g(rng)).normalized();
    const Rgb s = m.shade(geo, l);
    EXPECT_TRUE(allFinite(s));
    if (geo.normal.dot(l) <= 0.0) {
      EXPECT_EQ(s.maxCoeff(), 0.0);
    } else {
      EXPECT_GE(s.minCoeff(), 0.0);
    }
  }
  // The sphere map's rim: n perpendicular to v. Finite, and the diffuse part is (1 - s) rho / pi N.L.
  const ShadingGeometry rim = geometryForReflection(-v, v);
  const Vec3 l = (rim.normal + v).normalized();
  const Rgb s = m.shade(rim, l);
  EXPECT_TRUE(allFinite(s));
  const Vec3 h = (l + v).normalized();
  const double nl = rim.normal.dot(l), nh = rim.normal.dot(h), vh = v.dot(h);
  const double spec = ggxD(nh, 0.3) * 2 * nh / (vh * nl) / 4 * eq13(vh, 1.5);
  EXPECT_NEAR(s[0], (0.5 * spec + 0.5 * 0.8 / kPi) * nl, 1e-12);
}

TEST(CookTorrance, ExtremeRoughnessStaysFinite) {
  for (double m : {1e-4, 1e-2, 5.0, 10.0}) {
    for (auto dist : {MicrofacetDistribution::Beckmann, MicrofacetDistribution::Ggx}) {
      const CookTorranceMaterial refl(
          params(CookTorranceMode::Reflectance, dist, m, FresnelTerm::fromF0(Rgb(0, 0.5, 1))));
      const CookTorranceMaterial lit(params(CookTorranceMode::Lighting, dist, m, FresnelTerm::fromF0(Rgb(0, 0.5, 1))));
      EXPECT_NEAR(refl.peakDistribution(), 1.0 / (kPi * m * m), 1e-12 / (m * m));
      for (int i = 0; i <= 200; ++i) {
        const double c = i / 200.0;
        EXPECT_TRUE(allFinite(refl.reflectance(c)));
        const Vec3 n(std::sqrt(1 - c * c), 0, c);
        for (const Vec3& l : {Vec3(0, 0, 1), Vec3(-1, 0, 0.05), Vec3(0.6, 0.8, 0.0)}) {
          const Rgb b = lit.brdf(n, Vec3::UnitZ(), l.normalized());
          EXPECT_TRUE(allFinite(b));
          EXPECT_GE(b.minCoeff(), 0.0);
        }
      }
      // F0 = 0 reflects nothing at any angle; F0 = 1 is white.
      EXPECT_EQ(refl.reflectance(0.0)[0], 0.0);
      EXPECT_EQ(refl.reflectance(0.3)[0], 0.0);
      EXPECT_NEAR(refl.reflectance(0.3)[2], refl.peakDistribution() / (4 * 0.09), 1e-9 * refl.peakDistribution());
    }
  }
}

TEST(CookTorrance, RejectsBadParameters) {
  auto p =
      params(CookTorranceMode::Reflectance, MicrofacetDistribution::Beckmann, 0.3, FresnelTerm::fromF0(Rgb::Ones()));
  auto bad = [&](auto change) {
    auto q = p;
    change(q);
    return q;
  };
  EXPECT_THROW(CookTorranceMaterial(bad([](auto& q) { q.roughness = 0; })), Error);
  EXPECT_THROW(CookTorranceMaterial(bad([](auto& q) { q.roughness = 11; })), Error);
  EXPECT_THROW(CookTorranceMaterial(bad([](auto& q) { q.grazingAngleDegrees = 90; })), Error);
  EXPECT_THROW(CookTorranceMaterial(bad([](auto& q) { q.specularWeight = 1.5; })), Error);
  EXPECT_THROW(CookTorranceMaterial(bad([](auto& q) {
                 q.diffuse = Rgb::Constant(0.5);
                 q.specularWeight = 0.5;
               })),
               Error);
  EXPECT_THROW(CookTorranceMaterial(bad([](auto& q) {
                 q.mode = CookTorranceMode::Lighting;
                 q.diffuse = Rgb::Constant(0.5);
               })),
               Error);  // s = 1 leaves d = 0
  EXPECT_NO_THROW(CookTorranceMaterial(bad([](auto& q) {
    q.mode = CookTorranceMode::Lighting;
    q.diffuse = Rgb::Constant(0.5);
    q.specularWeight = 0.4;
  })));
  EXPECT_THROW(parseMicrofacetDistribution("phong"), Error);
  EXPECT_THROW(parseCookTorranceMode("mirror"), Error);
}

}  // namespace
}  // namespace brdfbake
