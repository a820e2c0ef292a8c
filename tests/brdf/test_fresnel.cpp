// Fresnel formulas against an independent complex-amplitude implementation, analytic values
// (normal incidence, grazing, Brewster angle, total internal reflection) and published optical
// constants.
#include <gtest/gtest.h>
#include <brdfbake/brdf/fresnel.hpp>
#include <brdfbake/core/error.hpp>

#include <complex>

#if __has_include(<ceres/jet.h>)
#include <ceres/jet.h>
#define BRDFBAKE_HAVE_JET 1
#endif

namespace brdfbake {
namespace {

// Reference: the Fresnel amplitude coefficients with a complex index m = n + i k, for light from
// index 1 at incidence angle with cosine c (Born & Wolf section 13.4):
//   w = sqrt(m^2 - sin^2), r_s = (c - w) / (c + w), r_p = (m^2 c - w) / (m^2 c + w),
// F = (|r_s|^2 + |r_p|^2) / 2. The principal square root (Re >= 0) picks the decaying wave, which
// also gives |r| = 1 under total internal reflection (m real < 1).
double referenceFresnel(double c, double n, double k) {
  const std::complex<double> m(n, k);
  const std::complex<double> m2 = m * m;
  const double s2 = 1.0 - c * c;
  const std::complex<double> w = std::sqrt(m2 - s2);
  const std::complex<double> rs = (c - w) / (c + w);
  const std::complex<double> rp = (m2 * c - w) / (m2 * c + w);
  return 0.5 * (std::norm(rs) + std::norm(rp));
}

TEST(FresnelDielectric, MatchesComplexAmplitudeReference) {
  for (double eta : {1.01, 1.33, 1.5, 2.4, 5.0, 200.0, 1.0 / 1.5, 0.75}) {
    for (int i = 0; i <= 900; ++i) {
      const double theta = radians(i * 0.1);
      const double c = std::cos(theta);
      if (c <= 0.0) continue;  // both 1 at exactly grazing; the reference is 0/0 there for eta = 1
      EXPECT_NEAR(fresnelDielectric(c, eta), referenceFresnel(c, eta, 0.0), 1e-12)
          << "eta " << eta << " theta " << i * 0.1;
    }
  }
}

TEST(FresnelDielectric, NormalIncidenceAndGrazing) {
  // eta = 1.5 gives F0 = (0.5 / 2.5)^2 = 0.04.
  EXPECT_NEAR(fresnelDielectric(1.0, 1.5), 0.04, 1e-15);
  EXPECT_NEAR(f0FromIor(1.5), 0.04, 1e-15);
  EXPECT_NEAR(iorFromF0(0.04), 1.5, 1e-14);
  for (double eta : {1.001, 1.33, 1.5, 5.0, 1e4, 0.5}) {
    EXPECT_NEAR(fresnelDielectric(1.0, eta), std::pow((eta - 1) / (eta + 1), 2), 1e-14) << eta;
    EXPECT_EQ(fresnelDielectric(0.0, eta), 1.0) << eta;   // F(90 deg) = 1
    EXPECT_EQ(fresnelDielectric(-0.2, eta), 1.0) << eta;  // c < 0 clamps to grazing
    // Continuous into grazing: 1 - F ~ 4 c g / (g^2 + 1) for c g << 1 (g = sqrt(eta^2 - 1)).
    EXPECT_NEAR(fresnelDielectric(1e-12, eta), 1.0, 1e-6) << eta;
  }
}

TEST(FresnelDielectric, BrewsterAngle) {
  // At Brewster's angle tan(theta_B) = eta, R_p = 0 and theta_i + theta_t = 90 deg, so
  // R_s = sin^2(theta_i - theta_t) = cos^2(2 theta_B) and F = cos^2(2 theta_B) / 2 (0.07396 for 1.5).
  for (double eta : {1.33, 1.5, 2.4}) {
    const double thetaB = std::atan(eta);
    EXPECT_NEAR(fresnelDielectric(std::cos(thetaB), eta), 0.5 * std::pow(std::cos(2 * thetaB), 2), 1e-14) << eta;
  }
  EXPECT_NEAR(fresnelDielectric(std::cos(std::atan(1.5)), 1.5), 0.07396, 1e-5);
}

TEST(FresnelDielectric, GrowsTowardsGrazing) {
  // For moderate indices (glass, water, diamond) the unpolarised F rises monotonically with the
  // angle; for large eta it first dips slightly (the p-wave's pseudo-Brewster minimum), so those are
  // not included.
  for (double eta : {1.33, 1.5, 2.4}) {
    double previous = 0.0;
    for (int i = 0; i <= 1000; ++i) {
      const double f = fresnelDielectric(1.0 - i / 1000.0, eta);
      EXPECT_GE(f, previous - 1e-15) << eta << " " << i;
      previous = f;
    }
  }
}

TEST(FresnelDielectric, TotalInternalReflectionBelowUnitIndex) {
  // eta < 1: light inside the denser medium. F = 1 beyond the critical angle asin(eta), and
  // continuous there; at normal incidence F0 is the same as for 1 / eta.
  const double eta = 1.0 / 1.5;
  const double critical = std::asin(eta);
  EXPECT_NEAR(fresnelDielectric(1.0, eta), 0.04, 1e-15);
  for (double theta = critical; theta <= kPi / 2; theta += 0.01)
    EXPECT_EQ(fresnelDielectric(std::cos(theta), eta), 1.0);
  // Approaching the critical angle 1 - F falls like the square root of the distance to it.
  EXPECT_NEAR(fresnelDielectric(std::cos(critical - 1e-10), eta), 1.0, 1e-3);
  // Stokes: the reflectance is the same from both sides at Snell-conjugate angles.
  for (double ti = 0.0; ti < critical; ti += 0.02) {
    const double to = std::asin(std::sin(ti) / eta);  // the matching angle outside
    EXPECT_NEAR(fresnelDielectric(std::cos(ti), eta), fresnelDielectric(std::cos(to), 1.0 / eta), 1e-12) << ti;
  }
}

TEST(FresnelDielectric, MatchedIndexReflectsNothing) {
  for (double c : {0.0, 1e-12, 0.3, 1.0}) EXPECT_EQ(fresnelDielectric(c, 1.0), 0.0) << c;
}

TEST(FresnelConductor, CopperJohnsonChristy) {
  // P. B. Johnson and R. W. Christy, "Optical constants of the noble metals", Phys. Rev. B 6,
  // 4370 (1972), Table I: copper at 1.88 eV (659.5 nm): n = 0.22, k = 3.747 (also in the
  // refractiveindex.info database, Cu/Johnson). Normal-incidence reflectance
  // ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2) = 14.6484 / 15.5284 = 0.9433.
  const double n = 0.22, k = 3.747;
  EXPECT_NEAR(fresnelConductor(1.0, n, k), 0.9433, 1e-4);
  EXPECT_NEAR(fresnelConductor(1.0, n, k), f0FromConductor(n, k), 1e-14);
  EXPECT_EQ(fresnelConductor(0.0, n, k), 1.0);
  for (int i = 0; i < 900; ++i) {
    const double c = std::cos(radians(i * 0.1));
    EXPECT_NEAR(fresnelConductor(c, n, k), referenceFresnel(c, n, k), 1e-12) << i * 0.1;
  }
  // Copper at 548.6 nm (n = 1.02, k = 2.577) and 450.9 nm (n = 1.24, k = 2.397), same table:
  // F0 = 0.6194 and 0.5392, the copper colour (red > green > blue).
  EXPECT_NEAR(fresnelConductor(1.0, 1.02, 2.577), 0.6194, 1e-4);
  EXPECT_NEAR(fresnelConductor(1.0, 1.24, 2.397), 0.5392, 1e-4);
}

TEST(FresnelConductor, ReducesToDielectricWithoutAbsorption) {
  for (double eta : {1.33, 1.5, 3.0, 0.7}) {
    for (int i = 0; i <= 90; ++i) {
      const double c = std::cos(radians(i));
      EXPECT_NEAR(fresnelConductor(c, eta, 0.0), fresnelDielectric(c, eta), 1e-13) << eta << " " << i;
    }
  }
  EXPECT_EQ(fresnelConductor(0.0, 1.0, 0.0), 0.0);
  EXPECT_NEAR(fresnelConductor(0.5, 1.0, 0.0), 0.0, 1e-15);
}

TEST(FresnelTerm, FromF0) {
  // eta from F0 reproduces F0 at normal incidence; F0 = 0 and 1 are the two limits.
  for (double f0 : {0.0, 0.02, 0.04, 0.5, 0.955, 0.999999}) {
    const FresnelTerm f = FresnelTerm::fromF0(Rgb::Constant(f0));
    EXPECT_NEAR(f(1.0)[0], f0, 1e-12) << f0;
    if (f0 > 0.0) {
      EXPECT_EQ(f(0.0)[0], 1.0) << f0;
    }
  }
  const FresnelTerm zero = FresnelTerm::fromF0(Rgb::Zero()), one = FresnelTerm::fromF0(Rgb::Ones());
  for (int i = 0; i <= 100; ++i) {
    const double c = i / 100.0;
    EXPECT_EQ(zero(c).maxCoeff(), 0.0) << c;  // no interface: nothing reflected, grazing included
    EXPECT_EQ(one(c).minCoeff(), 1.0) << c;   // perfect mirror
  }
  // Per channel, and eta = 1.5 <-> F0 = 0.04.
  const FresnelTerm copper = FresnelTerm::fromF0(Rgb(0.955, 0.638, 0.538));
  EXPECT_LT((copper.f0() - Rgb(0.955, 0.638, 0.538)).abs().maxCoeff(), 1e-12);
  EXPECT_NEAR(FresnelTerm::fromF0(Rgb::Constant(0.04)).eta()[0], 1.5, 1e-12);
  EXPECT_THROW(FresnelTerm::fromF0(Rgb(1.1, 0, 0)), Error);
  EXPECT_THROW(FresnelTerm::fromF0(Rgb(-0.1, 0, 0)), Error);
  EXPECT_THROW(FresnelTerm::dielectric(Rgb(0, 1, 1)), Error);
  EXPECT_THROW(FresnelTerm::conductor(Rgb(1, 1, 1), Rgb(-1, 0, 0)), Error);
}

TEST(FresnelTerm, SchlickIsTheEnginesApproximation) {
  // Schlick 1994, typed out: F = f0 + (1 - f0)(1 - c)^5. Gold-like f0 (Filament's table).
  const Rgb f0(1.0, 0.782, 0.344);
  const FresnelTerm term = FresnelTerm::schlick(f0);
  EXPECT_EQ(term.kind(), FresnelTerm::Kind::Schlick);
  for (double c : {0.0, 0.1, 0.5, 0.9, 1.0}) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(term(c)[i], f0[i] + (1.0 - f0[i]) * std::pow(1.0 - c, 5.0), 1e-15) << "c " << c;
    }
  }
  EXPECT_NEAR(term(0.5)[2], 0.344 + 0.656 / 32.0, 1e-15);  // (1 - 0.5)^5 = 1/32
  // Where Schlick and the exact dielectric part: at 60 degrees for glass (f0 = 0.04) the exact
  // Fresnel gives 0.0892 (Eq. 13 with eta 1.5), Schlick 0.04 + 0.96/32 = 0.07.
  EXPECT_NEAR(FresnelTerm::schlick(Rgb::Constant(0.04))(0.5)[0], 0.07, 1e-12);
  EXPECT_NEAR(FresnelTerm::fromF0(Rgb::Constant(0.04))(0.5)[0], referenceFresnel(0.5, 1.5, 0.0), 1e-9);
  EXPECT_THROW(FresnelTerm::schlick(Rgb(1.2, 0.5, 0.5)), Error);
}

TEST(FresnelTerm, FiniteEverywhere) {
  const std::vector<FresnelTerm> terms{FresnelTerm::dielectric(Rgb(1.5, 1.0, 0.5)), FresnelTerm::fromF0(Rgb(0, 0.5, 1)),
                                       FresnelTerm::conductor(Rgb(0.22, 1.02, 1.0), Rgb(3.747, 2.577, 0.0))};
  for (const auto& f : terms) {
    for (double c : {-1.0, -1e-300, 0.0, 1e-300, 1e-8, 0.5, 1.0 - 1e-16, 1.0, 1.5, std::nan("")}) {
      const Rgb v = f(c);
      EXPECT_TRUE(allFinite(v)) << c;
      EXPECT_TRUE((v >= 0.0).all() && (v <= 1.0).all()) << c;
    }
  }
}

TEST(FresnelTerm, SpectralTablesReduceThroughCie) {
  // A spectrally flat index must give the grey RGB formula; F(0) = 1 exactly (white-balanced).
  const std::vector<double> wl{400, 500, 600, 700};
  const std::vector<double> n(4, 1.5), k(4, 0.0);
  const FresnelTerm flat = FresnelTerm::spectralConductor(wl, n, k);
  for (int i = 0; i <= 64; ++i) {
    const double c = i / 64.0;
    const Rgb v = flat(c);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(v[ch], fresnelDielectric(c, 1.5), 2e-6) << c;
  }
  EXPECT_EQ(flat(0.0).minCoeff(), 1.0);
  // Copper, Johnson & Christy 1972 (the rows between 450 and 756 nm): reddish, whiter at grazing.
  const std::vector<double> cuWl{450.9, 471.4, 495.9, 520.9, 548.6, 582.1, 616.8, 659.5, 704.5, 756.0};
  const std::vector<double> cuN{1.24, 1.25, 1.22, 1.18, 1.02, 0.70, 0.30, 0.22, 0.21, 0.24};
  const std::vector<double> cuK{2.397, 2.483, 2.564, 2.608, 2.577, 2.704, 3.205, 3.747, 4.205, 4.665};
  const FresnelTerm cu = FresnelTerm::spectralConductor(cuWl, cuN, cuK);
  const Rgb f0 = cu.f0();
  EXPECT_GT(f0[0], f0[1]);
  EXPECT_GT(f0[1], f0[2]);
  EXPECT_GT(f0[0], 0.8);
  EXPECT_LT(f0[2], 0.7);
  const Rgb f85 = cu(std::cos(radians(85)));
  EXPECT_GT(f85[2] / f85[0], f0[2] / f0[0]);  // colour goes towards white at grazing
  EXPECT_THROW(FresnelTerm::spectralConductor(cuWl, cuN, std::vector<double>(3, 1.0)), Error);
  // Spectral F0 table: constant 0.04 is glass.
  const FresnelTerm glass = FresnelTerm::spectralF0(wl, std::vector<double>(4, 0.04));
  EXPECT_NEAR(glass(0.5)[1], fresnelDielectric(0.5, 1.5), 2e-6);
}

TEST(FresnelTable, TexelCentres) {
  const FresnelTerm f = FresnelTerm::dielectric(Rgb(1.5, 2.0, 3.0));
  const auto profile = fresnelTable(f, 8);
  ASSERT_EQ(profile.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    for (int ch = 0; ch < 3; ++ch) EXPECT_DOUBLE_EQ(profile[i][ch], fresnelDielectric((i + 0.5) / 8, f.eta()[ch]));
  }
  EXPECT_THROW(fresnelTable(f, 0), Error);
}

#ifdef BRDFBAKE_HAVE_JET
TEST(FresnelFormulas, JetDerivativesMatchFiniteDifferences) {
  using J = ceres::Jet<double, 2>;
  for (double c : {0.2, 0.6, 0.95}) {
    const J fd = fresnelDielectric(J(c, 0), J(1.5, 1));
    const double h = 1e-6;
    EXPECT_NEAR(fd.a, fresnelDielectric(c, 1.5), 1e-15);
    EXPECT_NEAR(fd.v[0], (fresnelDielectric(c + h, 1.5) - fresnelDielectric(c - h, 1.5)) / (2 * h), 1e-6);
    EXPECT_NEAR(fd.v[1], (fresnelDielectric(c, 1.5 + h) - fresnelDielectric(c, 1.5 - h)) / (2 * h), 1e-6);
    const J fc = fresnelConductor(J(c, 0), J(0.22, 1), J(3.747));
    EXPECT_NEAR(fc.v[1], (fresnelConductor(c, 0.22 + h, 3.747) - fresnelConductor(c, 0.22 - h, 3.747)) / (2 * h), 1e-6);
  }
}
#endif

}  // namespace
}  // namespace brdfbake
