// Held-out error (fit/held_out.hpp), the shared-shape fit and Lafortune lobes (brdf/lobes.hpp):
// the error measure and the splits against sums typed out here, the noise level of a synthetic
// table, the Lambert ratio of a Lambertian table, Lafortune lobes against Lafortune et al. 1997
// Eq. 4 typed out, their symmetry axis, reciprocity and energy, and the real Cornell tables.
#include <gtest/gtest.h>
#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/cornell_grid.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/fit/held_out.hpp>
#include <brdfbake/fit/lobe_fit.hpp>

#include <cmath>
#include <map>
#include <mutex>
#include <numeric>
#include <random>

#include "fit_formula.hpp"
#include "test_support.hpp"

namespace brdfbake {
namespace {
using test::cornellDirection;
using test::lafortuneByHand;

LobeModel lafortuneModel(double cxy, double n, double c, double diffuse) {
  LobeModel m;
  m.channels = {{"R", diffuse, {{{c}, {n}, cxy}}}};
  return m;
}

TEST(LafortuneLobe, MatchesEquationFourTypedOut) {
  const LobeModel m = lafortuneModel(-1.4, 20.0, 0.3, 0.2);
  m.validate();
  for (const auto& [l, v] :
       std::vector<std::pair<Vec3, Vec3>>{{cornellDirection(0.5, 0.0), cornellDirection(0.6, kPi)},
                                          {cornellDirection(1.2, 0.3), cornellDirection(1.3, 3.0)},
                                          {cornellDirection(0.2, 1.0), cornellDirection(0.9, -2.0)}}) {
    const double expected = 0.2 / kPi + lafortuneByHand(0.3, 20.0, -1.4, l, v);
    EXPECT_NEAR(m.evaluate(0, l, v), expected, 1e-12 * expected);
  }
  // c_xy = -1 is the Phong lobe about the mirrored view: r_v . l.
  const LobeModel phong = lafortuneModel(-1.0, 20.0, 0.3, 0.0);
  const Vec3 l = cornellDirection(0.5, 0.2), v = cornellDirection(0.7, 3.0);
  const Vec3 rv(-v.x(), -v.y(), v.z());
  EXPECT_NEAR(phong.evaluate(0, l, v), 0.3 * 22.0 / (2.0 * kPi) * std::pow(rv.dot(l), 20.0), 1e-12);
}

TEST(LafortuneLobe, IsRadiallySymmetricAboutItsAxisWithAmplitudeAToTheN) {
  // Axis a = (c v_x, c v_y, v_z): lights at one angle beta from a / |a| see one value,
  // C (n + 2) / (2 pi) |a|^n cos^n beta, whatever their azimuth about the axis.
  for (double cxy : {-1.6, -1.0, 0.6, 1.0}) {
    const double n = 30.0, c = 0.5;
    const LobeModel m = lafortuneModel(cxy, n, c, 0.0);
    const Vec3 v = cornellDirection(radians(40.0), kPi * 0.25);
    const Vec3 a(cxy * v.x(), cxy * v.y(), v.z());
    const Vec3 axis = a.normalized();
    const Vec3 u = axis.cross(Vec3::UnitZ()).normalized(), w = axis.cross(u);
    const double beta = radians(6.0);
    const double expected = c * (n + 2.0) / (2.0 * kPi) * std::pow(a.norm() * std::cos(beta), n);
    for (double azimuth = 0.0; azimuth < 2.0 * kPi; azimuth += 0.7) {
      const Vec3 l = std::cos(beta) * axis + std::sin(beta) * (std::cos(azimuth) * u + std::sin(azimuth) * w);
      ASSERT_GT(l.z(), 0.0);
      EXPECT_NEAR(m.evaluate(0, l, v), expected, 1e-9 * expected) << "cxy " << cxy << " azimuth " << azimuth;
    }
    // c_xy = +1: the axis is the view itself (back-scatter).
    if (cxy == 1.0) {
      EXPECT_NEAR((axis - v).norm(), 0.0, 1e-12);
    }
  }
}

TEST(LafortuneLobe, IsReciprocal) {
  const LobeModel m = lafortuneModel(-1.3, 15.0, 0.4, 0.1);
  for (const auto& [l, v] :
       std::vector<std::pair<Vec3, Vec3>>{{cornellDirection(0.3, 0.0), cornellDirection(1.1, 2.9)},
                                          {cornellDirection(1.3, 0.5), cornellDirection(0.4, -2.5)}}) {
    EXPECT_NEAR(m.evaluate(0, l, v), m.evaluate(0, v, l), 1e-12);
  }
}

TEST(LafortuneLobe, ReflectsCTimesAToTheNTimesTheAxisElevation) {
  // Over the hemisphere about the axis, integral (a^ . l)^n l dl = 2 pi / (n + 2) a^, so the
  // reflected fraction of a narrow lobe (nothing clipped by the horizon) is C |a|^n a^_z:
  // the growth |a|^n is the Fresnel-like rise towards grazing of |c_xy| > 1.
  const double n = 400.0, c = 0.2, cxy = -1.2;
  const LobeModel m = lafortuneModel(cxy, n, c, 0.0);
  const Vec3 v = cornellDirection(radians(60.0), kPi);
  const Vec3 a(cxy * v.x(), cxy * v.y(), v.z());
  const Vec3 axis = a.normalized();
  const Vec3 u = axis.cross(Vec3::UnitZ()).normalized(), w = axis.cross(u);
  // Midpoint quadrature in polar coordinates about the axis, out to 20 degrees (cos^400 20 deg ~ 1e-11).
  double sum = 0.0;
  const int rings = 2000, sectors = 256;
  const double maxBeta = radians(20.0);
  for (int i = 0; i < rings; ++i) {
    const double beta = (i + 0.5) * maxBeta / rings;
    for (int j = 0; j < sectors; ++j) {
      const double phi = (j + 0.5) * 2.0 * kPi / sectors;
      const Vec3 l = std::cos(beta) * axis + std::sin(beta) * (std::cos(phi) * u + std::sin(phi) * w);
      sum += m.evaluate(0, l, v) * l.z() * std::sin(beta) * (maxBeta / rings) * (2.0 * kPi / sectors);
    }
  }
  const double expected = c * std::pow(a.norm(), n) * axis.z();
  EXPECT_NEAR(sum, expected, 1e-4 * expected);
}

TEST(LafortuneLobe, ValidationAndFitFileCarryCxy) {
  EXPECT_THROW(lafortuneModel(9.0, 10.0, 0.1, 0.0).validate(), Error);
  EXPECT_THROW(lafortuneModel(-2.0, 1000.0, 0.1, 0.0).validate(), Error);  // 1000 ln 2 > 50: overflow
  test::TempDir dir;
  FitFile file;
  file.hasFitInfo = false;
  file.hasSource = false;
  file.fit.model = lafortuneModel(0.8, 12.0, 0.25, 0.1);
  writeFitFile(dir / "fit.json", file);
  const FitFile back = readFitFile(dir / "fit.json");
  EXPECT_EQ(back.fit.model.channels[0].lobes[0].cxy, 0.8);
  EXPECT_FALSE(back.fit.model.allAboutMirror());
}

// Cook & Torrance 1981's microfacet BRDF typed out from the vectors, with Blinn 1977's normalised
// distribution (n + 2) / (2 pi) (n.h)^n and Schlick 1994's Fresnel shape with free weights, no
// shadowing: (C + C_F (1 - l.h)^5) D(h) / (4 (n.l) (n.v)).
double halfVectorByHand(double c, double cf, double n, const Vec3& l, const Vec3& v) {
  if (l.z() <= 0.0 || v.z() <= 0.0) return 0.0;
  const Vec3 h = (l + v).normalized();
  const double d = h.z() > 0.0 ? (n + 2.0) / (2.0 * kPi) * std::pow(h.z(), n) : 0.0;
  return (c + cf * std::pow(1.0 - l.dot(h), 5.0)) * d / (4.0 * l.z() * v.z());
}

LobeModel halfVectorModel(double c, double cf, double n, double diffuse) {
  LobeModel m;
  Lobe lobe{{c}, {n}};
  lobe.halfVector = true;
  lobe.fresnel = cf;
  m.channels = {{"R", diffuse, {lobe}}};
  return m;
}

TEST(HalfVectorLobe, MatchesMicrofacetFormTypedOut) {
  const LobeModel m = halfVectorModel(0.05, 0.6, 80.0, 0.1);
  m.validate();
  for (const auto& [l, v] :
       std::vector<std::pair<Vec3, Vec3>>{{cornellDirection(0.5, 0.0), cornellDirection(0.6, kPi)},
                                          {cornellDirection(1.2, 0.0), cornellDirection(1.35, 3.0)},
                                          {cornellDirection(0.2, 1.0), cornellDirection(0.9, -2.0)},
                                          {cornellDirection(1.3, 0.4), cornellDirection(1.1, 0.4)}}) {
    const double expected = 0.1 / kPi + halfVectorByHand(0.05, 0.6, 80.0, l, v);
    EXPECT_NEAR(m.evaluate(0, l, v), expected, 1e-12 * expected);
    EXPECT_NEAR(m.evaluate(0, v, l), expected, 1e-12 * expected);  // reciprocal
  }
  // On the mirror direction h = n, l.h = u: (C + C_F (1 - u)^5) (n + 2) / (2 pi) / (4 u^2).
  const double u = std::cos(radians(70.0));
  EXPECT_NEAR(m.mirrorValue(0, u),
              0.1 / kPi + (0.05 + 0.6 * std::pow(1.0 - u, 5.0)) * 82.0 / (2.0 * kPi) / (4.0 * u * u), 1e-12);
  // The lighting material evaluates the same BRDF (in a frame where the normal is not z).
  const Vec3 l = cornellDirection(1.2, 0.0), v = cornellDirection(1.35, 3.0);
  const LobeMaterial material(m, LobeMaterialMode::Lighting);
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.4, Vec3(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
  const Rgb rgb = material.brdf(rotation * Vec3::UnitZ(), rotation * v, rotation * l);
  EXPECT_NEAR(rgb[0], 0.1 / kPi + halfVectorByHand(0.05, 0.6, 80.0, l, v), 1e-12);
}

TEST(HalfVectorLobe, IsStretchedInThePlaneOfIncidenceAtGrazing) {
  // Light at 70 degrees, views 9 degrees from the mirror direction m: in the plane of incidence
  // (towards grazing, as the Cornell lacquers' ridge at theta_s = 79) h turns by 4.5 degrees, across
  // the plane by about 9 / (2 cos 70) degrees (h = (l + v) / |l + v|, |l + v| = 2 cos 70): the
  // in-plane view sees far more. Checked against the typed-out form.
  const double n = 200.0;
  const LobeModel m = halfVectorModel(1.0, 0.0, n, 0.0);
  const Vec3 l = cornellDirection(radians(70.0), 0.0);
  const Vec3 mirror = cornellDirection(radians(70.0), kPi);
  const Vec3 inPlane = cornellDirection(radians(79.0), kPi);
  const Vec3 axis = mirror.cross(Vec3::UnitY()).normalized();  // in the plane, perpendicular to m
  const Vec3 across = Eigen::AngleAxisd(radians(9.0), axis) * mirror;
  ASSERT_NEAR(std::abs(across.y()), std::sin(radians(9.0)), 1e-12);
  const double along = m.evaluate(0, l, inPlane), sideways = m.evaluate(0, l, across);
  EXPECT_NEAR(along, halfVectorByHand(1.0, 0.0, n, l, inPlane), 1e-12 * along);
  EXPECT_NEAR(sideways, halfVectorByHand(1.0, 0.0, n, l, across), 1e-12 * along);
  EXPECT_GT(along, 10.0 * sideways);
}

TEST(HalfVectorLobe, StaysExactWhereLightAndViewFaceEachOtherAtTheHorizon) {
  // n.h = (n.l + n.v) / sqrt(2 (1 + l.v)) loses every digit near l = -v: a matcap of a fitted
  // half-vector lobe (n = 1e4) under a sky came out NaN at its rim, where the rounded quotient reached
  // 5000 and its power overflowed. |l + v| is now taken from the vectors: the lobe matches the form
  // typed out with h = (l + v) / |l + v| (halfVectorByHand) down to 1e-15 of the horizon, from its
  // peak (light and view facing each other exactly: h = n) to nothing (h far from n).
  const double n = 1e4;
  const LobeModel m = halfVectorModel(0.2, 0.5, n, 0.0);
  const LobeMaterial material(m, LobeMaterialMode::Lighting);
  for (const double drop : {1e-3, 1e-6, 1e-9, 1e-12, 1e-15}) {
    for (const double turn : {0.0, 1e-9, 1e-6, 1e-4}) {
      for (const double tilt : {1.0, 0.37, 3.1}) {
        const Vec3 l = cornellDirection(kPi / 2.0 - drop * tilt, 0.0);
        const Vec3 v = cornellDirection(kPi / 2.0 - drop, kPi + turn);
        const double cosHalf = LobeGeometry::local(l, v).cosHalf();
        EXPECT_NEAR(cosHalf, (l + v).normalized().z(), 1e-12) << drop << " " << turn << " " << tilt;
        const double expected = halfVectorByHand(0.2, 0.5, n, l, v), value = m.evaluate(0, l, v);
        EXPECT_NEAR(value, expected, 1e-8 * expected) << drop << " " << turn << " " << tilt;
        EXPECT_TRUE(std::isfinite(value));
        const Rgb rgb = material.brdf(Vec3::UnitZ(), v, l);
        EXPECT_NEAR(rgb[0], expected, 1e-8 * expected) << drop << " " << turn << " " << tilt;
      }
    }
  }
}

// Midpoint quadrature of integral f(l, v) (n.v) dv over the hemisphere of views, light l.
double reflectedFraction(const LobeModel& m, const Vec3& l, int rings = 4000, int sectors = 64) {
  double sum = 0.0;
  for (int i = 0; i < rings; ++i) {
    const double theta = (i + 0.5) * (kPi / 2.0) / rings;
    for (int j = 0; j < sectors; ++j) {
      const double phi = (j + 0.5) * 2.0 * kPi / sectors;
      const Vec3 v = cornellDirection(theta, phi);
      sum += m.evaluate(0, l, v) * v.z() * std::sin(theta) * (kPi / 2.0 / rings) * (2.0 * kPi / sectors);
    }
  }
  return sum;
}

TEST(HalfVectorLobe, ReflectsCAtNormalIncidence) {
  // l = n: h = (n + v) / |n + v| is at theta_h = theta_v / 2, dv = 4 (n.h) dh, so the reflected
  // fraction is C times integral D (n.h) dh over theta_h < 45 degrees = C (1 - cos^(n+2) 45 deg),
  // plus C_F (n + 2) integral_{cos 45}^1 (1 - x)^5 x^(n+1) dx (x = n.h = l.h), done here by Simpson's rule.
  const double n = 10.0;
  EXPECT_NEAR(reflectedFraction(halfVectorModel(0.3, 0.0, n, 0.0), Vec3::UnitZ()), 0.3 * (1.0 - std::pow(0.5, 6.0)),
              2e-5);
  const double a = std::sqrt(0.5);
  const int steps = 2000;
  double simpson = 0.0;
  for (int i = 0; i <= steps; ++i) {
    const double x = a + (1.0 - a) * i / steps;
    const double w = (i == 0 || i == steps) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    simpson += w * std::pow(1.0 - x, 5.0) * std::pow(x, n + 1.0);
  }
  simpson *= (1.0 - a) / steps / 3.0 * (n + 2.0);
  EXPECT_NEAR(reflectedFraction(halfVectorModel(0.0, 1.0, n, 0.0), Vec3::UnitZ()), simpson, 1e-3 * simpson);
}

TEST(HalfVectorLobe, ValidationAndFitFileCarryAxisAndFresnel) {
  LobeModel bad = lafortuneModel(-1.0, 10.0, 0.1, 0.0);
  bad.channels[0].lobes[0].fresnel = 0.2;  // Fresnel weight on a Lafortune lobe
  EXPECT_THROW(bad.validate(), Error);
  EXPECT_THROW(halfVectorModel(0.1, -0.1, 10.0, 0.0).validate(), Error);
  test::TempDir dir;
  FitFile file;
  file.hasFitInfo = false;
  file.hasSource = false;
  file.fit.model = halfVectorModel(0.05, 0.7, 120.0, 0.1);
  writeFitFile(dir / "fit.json", file);
  const FitFile back = readFitFile(dir / "fit.json");
  EXPECT_TRUE(back.fit.model.channels[0].lobes[0].halfVector);
  EXPECT_EQ(back.fit.model.channels[0].lobes[0].fresnel, 0.7);
  EXPECT_FALSE(back.fit.model.allAboutMirror());
  const Vec3 l = cornellDirection(1.0, 0.0), v = cornellDirection(1.1, 3.0);
  EXPECT_DOUBLE_EQ(back.fit.model.evaluate(0, l, v), file.fit.model.evaluate(0, l, v));
}

TEST(HalfVectorLobe, SharedFitRecoversTheLobe) {
  // Three channels sharing one half-vector lobe shape, weights differing: the fit finds n, C, C_F.
  LobeModel truth;
  auto lobe = [](double c, double cf) {
    Lobe l{{c}, {300.0}};
    l.halfVector = true;
    l.fresnel = cf;
    return l;
  };
  truth.channels = {{"R", 0.30, {lobe(0.04, 0.9)}}, {"G", 0.15, {lobe(0.05, 0.7)}}, {"B", 0.05, {lobe(0.03, 0.5)}}};
  const MeasuredTable table = makeSyntheticTable(truth, 0.01, 11);
  FitOptions options;
  options.lobes = 1;
  options.kind = LobeKindChoice::HalfVector;
  options.estimateHeldOut = false;
  const FitResult fit = fitLobes(table, options);
  for (std::size_t c = 0; c < 3; ++c) {
    const Lobe& got = fit.model.channels[c].lobes[0];
    const Lobe& want = truth.channels[c].lobes[0];
    ASSERT_TRUE(got.halfVector);
    EXPECT_NEAR(got.exponent[0], 300.0, 15.0);
    EXPECT_NEAR(got.weight[0], want.weight[0], 0.1 * want.weight[0]) << c;
    EXPECT_NEAR(got.fresnel, want.fresnel, 0.1 * want.fresnel) << c;
    EXPECT_NEAR(fit.model.channels[c].diffuse, truth.channels[c].diffuse, 0.03 * truth.channels[c].diffuse) << c;
  }
}

// The log term of fit/held_out.hpp typed out.
double logTerm(double cosIn, double f) { return std::log(1.0 + cosIn * std::max(f, 0.0)); }

// A shared-shape model: every channel the same lobe shapes (one Lafortune lobe growing towards
// grazing, one back-scatter lobe), different weights.
LobeModel sharedModel() {
  LobeModel m;
  m.channels = {{"R", 0.30, {{{0.20}, {40.0}, -1.3}, {{0.05}, {4.0}, 1.0}}},
                {"G", 0.15, {{{0.15}, {40.0}, -1.3}, {{0.03}, {4.0}, 1.0}}},
                {"B", 0.05, {{{0.25}, {40.0}, -1.3}, {{0.02}, {4.0}, 1.0}}}};
  return m;
}

TEST(HeldOut, ErrorAndSplitsMatchSumsTypedOut) {
  // An oracle fit (the true model whatever it is given): the held-out error is the noise's
  // log error on the held-out rows, summed here independently.
  const LobeModel truth = sharedModel();
  const MeasuredTable table = makeSyntheticTable(truth, 0.05, 3);
  const HeldOutReport report = estimateHeldOutError(table, [&](const MeasuredTable&) { return truth; });
  double offSquares = 0.0, offLargest = 0.0;
  std::size_t offRows = 0, offLargestRow = 0;
  std::map<long, std::pair<double, std::size_t>> perElevation;
  std::map<long, std::pair<double, std::size_t>> largestPerElevation;  // the largest row's squares, its index
  for (std::size_t i = 0; i < table.size(); ++i) {
    const auto& a = table.angles[i];
    const Vec3 wi = cornellDirection(a.thetaIn, a.phiIn), wo = cornellDirection(a.thetaOut, a.phiOut);
    const Vec3 mirror(-wi.x(), -wi.y(), wi.z());
    double squares = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
      const double r = logTerm(wi.z(), truth.evaluate(c, wi, wo)) -
                       logTerm(wi.z(), table.values(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c)));
      squares += r * r;
    }
    if (std::acos(std::clamp(mirror.dot(wo), -1.0, 1.0)) > radians(5.0)) {
      offSquares += squares, ++offRows;
      if (squares > offLargest) offLargest = squares, offLargestRow = i;
    }
    auto& e = perElevation[std::lround(degrees(a.thetaIn))];
    e.first += squares, ++e.second;
    auto& largest = largestPerElevation[std::lround(degrees(a.thetaIn))];
    if (squares > largest.first) largest = {squares, i};
  }
  // The row holding the largest part of a split's squares, and its angle from the mirror direction.
  const auto expectLargestRow = [&](const HeldOutSplit& split, double squares, double total, std::size_t row) {
    EXPECT_NEAR(split.largestRowShare, squares / total, 1e-12) << split.name;
    EXPECT_EQ(split.largestRow.thetaIn, table.angles[row].thetaIn) << split.name;
    EXPECT_EQ(split.largestRow.thetaOut, table.angles[row].thetaOut) << split.name;
    EXPECT_EQ(split.largestRow.phiOut, table.angles[row].phiOut) << split.name;
    const Vec3 wi = cornellDirection(table.angles[row].thetaIn, table.angles[row].phiIn);
    const Vec3 wo = cornellDirection(table.angles[row].thetaOut, table.angles[row].phiOut);
    const double cosine = std::clamp(Vec3(-wi.x(), -wi.y(), wi.z()).dot(wo), -1.0, 1.0);
    EXPECT_NEAR(split.largestRowMirrorOffset, degrees(std::acos(cosine)), 1e-9);
  };
  expectLargestRow(report.kfold, offLargest, offSquares, offLargestRow);
  EXPECT_EQ(report.kfold.heldRows, offRows);
  EXPECT_NEAR(report.kfold.error, std::sqrt(offSquares / (3.0 * offRows)), 1e-12);
  // Interior elevations: 20 .. 70 degrees.
  ASSERT_EQ(report.elevations.size(), 6u);
  for (const auto& e : report.elevations) {
    const auto& [squares, rows] = perElevation.at(std::lround(e.elevationDegrees));
    EXPECT_EQ(e.heldRows, rows);
    EXPECT_NEAR(e.error, std::sqrt(squares / (3.0 * rows)), 1e-12) << e.name;
    const auto& [largest, row] = largestPerElevation.at(std::lround(e.elevationDegrees));
    expectLargestRow(e, largest, squares, row);
    // Lambert's part of that row, and the ratio without it, from the split's Lambertian constants.
    std::vector<std::size_t> train, held;
    for (std::size_t i = 0; i < table.size(); ++i)
      (std::lround(degrees(table.angles[i].thetaIn)) == std::lround(e.elevationDegrees) ? held : train).push_back(i);
    const std::vector<double> k = lambertianFit(table, train);
    double lambertTotal = 0.0, lambertRow = 0.0;
    for (std::size_t i : held) {
      double rowSquares = 0.0;
      for (std::size_t c = 0; c < 3; ++c) {
        const double cosIn = std::cos(table.angles[i].thetaIn);
        rowSquares += std::pow(logTerm(cosIn, k[c]) - logTerm(cosIn, table.values(static_cast<Eigen::Index>(i),
                                                                                  static_cast<Eigen::Index>(c))),
                               2);
      }
      lambertTotal += rowSquares;
      if (i == row) lambertRow = rowSquares;
    }
    EXPECT_NEAR(e.largestRowLambertShare, lambertRow / lambertTotal, 1e-9) << e.name;
    EXPECT_NEAR(e.ratioWithoutLargestRow(), std::sqrt((squares - largest) / (lambertTotal - lambertRow)), 1e-6)
        << e.name;
  }
}

TEST(HeldOut, OneSampleTheFitMissesHoldsItsSplitsError) {
  // A Lambertian table whose 50-degree mirror sample reads 100 times the rest (a highlight narrower
  // than the grid's steps): a constant fit to the other elevations predicts every other row of that
  // split exactly, so that sample holds all of the split's error; fit.json keeps it.
  LobeModel lambert;
  lambert.channels = {{"Y", 0.5, {}}};
  MeasuredTable table = makeSyntheticTable(lambert, 0.0, 1);
  std::size_t spike = table.size();
  for (std::size_t i : table.samplesAtIncidentTheta(radians(50.0), 1e-4))
    if (spike == table.size() || mirrorOffsetDegrees(table, i) < mirrorOffsetDegrees(table, spike)) spike = i;
  ASSERT_LT(spike, table.size());
  table.values(static_cast<Eigen::Index>(spike), 0) *= 100.0;
  const HeldOutReport report = estimateHeldOutError(table, [](const MeasuredTable& training) {
    LobeModel constant;
    constant.channels = {{"Y", kPi * training.values.minCoeff(), {}}};
    return constant;
  });
  const HeldOutSplit& fifty = report.elevations.at(3);
  ASSERT_EQ(std::lround(fifty.elevationDegrees), 50);
  EXPECT_NEAR(fifty.largestRowShare, 1.0, 1e-12);
  EXPECT_GT(fifty.largestRowLambertShare, 0.999);  // Lambert's constant, fitted without it, misses it too
  EXPECT_EQ(fifty.largestRow.thetaOut, table.angles[spike].thetaOut);
  EXPECT_LT(fifty.largestRowMirrorOffset, 1.0);     // the Cornell grid's 50-degree sample: 0.2 degrees off
  EXPECT_LT(report.elevations.at(0).error, 1e-12);  // 20 degrees: predicted exactly
  test::TempDir dir;
  FitFile file;
  file.hasSource = false;
  file.fit.model = lambert;
  file.fit.heldOut = report;
  writeFitFile(dir / "fit.json", file);
  const HeldOutSplit back = readFitFile(dir / "fit.json").fit.heldOut->elevations.at(3);
  EXPECT_EQ(back.largestRowShare, fifty.largestRowShare);
  EXPECT_EQ(back.largestRowLambertShare, fifty.largestRowLambertShare);
  EXPECT_EQ(back.largestRow.thetaIn, fifty.largestRow.thetaIn);
  EXPECT_EQ(back.largestRow.phiIn, fifty.largestRow.phiIn);
  EXPECT_EQ(back.largestRow.thetaOut, fifty.largestRow.thetaOut);
  EXPECT_EQ(back.largestRow.phiOut, fifty.largestRow.phiOut);
  EXPECT_EQ(back.largestRowMirrorOffset, fifty.largestRowMirrorOffset);
}

TEST(HeldOut, FitJsonNamesWhatIsWrongWithALargestRow) {
  FitFile file;
  file.hasSource = false;
  file.fit.model.channels = {{"Y", 0.5, {}}};
  HeldOutReport report;
  report.kfold = {"off-mirror 5-fold", 0.0, 10, 0.0, 0.1};  // predicted exactly: no largest row
  report.elevations = {{"theta_i 30 deg", 30.0, 10, 0.2, 0.4, 0.9, 0.8, {0.5, 0.0, 0.6, 3.1}, 3.0}};
  file.fit.heldOut = report;
  const nlohmann::ordered_json good = fitFileToJson(file);
  EXPECT_FALSE(good["fit"]["held_out"]["kfold"].contains("largest_row"));
  const auto& row = good["fit"]["held_out"]["elevations"][0]["largest_row"];
  // ratio() sqrt((1 - 0.9) / (1 - 0.8)), the offsets of 1e-9 aside.
  EXPECT_NEAR(row["ratio_without"].get<double>(), 0.5 * std::sqrt(0.1 / 0.2), 1e-8);
  const HeldOutReport back = *fitFileFromJson(good, "fit.json").fit.heldOut;
  EXPECT_EQ(back.kfold.largestRowShare, 0.0);
  EXPECT_EQ(back.elevations[0].largestRowLambertShare, 0.8);
  const auto refused = [&](const std::string& key, const nlohmann::json& value, const std::string& words) {
    nlohmann::json bad = good;
    bad["fit"]["held_out"]["elevations"][0]["largest_row"][key] = value;
    try {
      fitFileFromJson(bad, "fit.json");
      ADD_FAILURE() << key << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("fit.held_out.elevations[0].largest_row." + key), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  refused("share", 1.5, "1.5");
  refused("lambert_share", -0.1, "-0.1");
  refused("theta_s", 2.0, "2");
  refused("mirror_offset_deg", 200.0, "200");
  refused("theta_x", 0.1, "unknown key");
}

// HeldOutSplits makes the splits once: k-fold splits first, then one per interior elevation in
// ascending order; every split's fit gets its own index and training table, and the report is the
// one estimateHeldOutError makes.
TEST(HeldOut, SplitsAreMadeOnceAndIndexed) {
  const LobeModel truth = sharedModel();
  const MeasuredTable table = makeSyntheticTable(truth, 0.05, 3);
  const HeldOutSplits splits(table);
  ASSERT_EQ(splits.size(), 5u + 6u);
  std::vector<int> calls(splits.size(), 0);
  std::mutex mutex;
  const HeldOutReport indexed = splits.estimate([&](std::size_t s, const MeasuredTable& training) {
    EXPECT_EQ(&training, &splits.training(s));
    const std::lock_guard<std::mutex> lock(mutex);
    ++calls.at(s);
    return truth;
  });
  for (int c : calls) EXPECT_EQ(c, 1);
  // The k-fold training tables leave out about a fifth of the off-mirror rows; an elevation's
  // training table leaves out exactly the rows of that theta_i.
  for (std::size_t s = 0; s < 5; ++s) EXPECT_LT(splits.training(s).size(), table.size()) << s;
  const std::vector<double> thetas = table.incidentThetas();
  for (std::size_t e = 0; e < 6; ++e) {
    const MeasuredTable& training = splits.training(5 + e);
    EXPECT_EQ(training.size(), table.size() - table.samplesAtIncidentTheta(thetas[e + 1]).size()) << e;
    for (const auto& a : training.angles) EXPECT_NE(a.thetaIn, thetas[e + 1]);
  }
  const HeldOutReport plain = estimateHeldOutError(table, [&](const MeasuredTable&) { return truth; });
  EXPECT_DOUBLE_EQ(indexed.kfold.error, plain.kfold.error);
  EXPECT_DOUBLE_EQ(indexed.kfold.lambertError, plain.kfold.lambertError);
  ASSERT_EQ(indexed.elevations.size(), plain.elevations.size());
  for (std::size_t e = 0; e < plain.elevations.size(); ++e) {
    EXPECT_EQ(indexed.elevations[e].name, plain.elevations[e].name);
    EXPECT_DOUBLE_EQ(indexed.elevations[e].error, plain.elevations[e].error);
    EXPECT_DOUBLE_EQ(indexed.elevations[e].lambertError, plain.elevations[e].lambertError);
  }
}

TEST(HeldOut, LambertFitIsTheMinimumOfTheLogError) {
  const MeasuredTable table = makeSyntheticTable(sharedModel(), 0.05, 4);
  std::vector<std::size_t> rows(table.size());
  std::iota(rows.begin(), rows.end(), std::size_t(0));
  const std::vector<double> k = lambertianFit(table, rows);
  // Brute force over a grid of 20 000 constants in [0, 2] 1/sr.
  for (std::size_t c = 0; c < 3; ++c) {
    double best = 0.0, bestCost = HUGE_VAL;
    for (int j = 0; j <= 20000; ++j) {
      const double value = 2.0 * j / 20000.0, cost = [&] {
        double s = 0.0;
        for (std::size_t i : rows) {
          const double cosIn = std::cos(table.angles[i].thetaIn);
          s += std::pow(logTerm(cosIn, value) -
                            logTerm(cosIn, table.values(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c))),
                        2);
        }
        return s;
      }();
      if (cost < bestCost) bestCost = cost, best = value;
    }
    EXPECT_NEAR(k[c], best, 2.0 / 20000.0) << c;
  }
}

TEST(HeldOut, LambertianTableHasRatioOne) {
  // A Lambertian table with 5 % noise: the lobe fit can do no better than a constant.
  LobeModel lambert;
  lambert.channels = {{"R", 0.8, {}}, {"G", 0.5, {}}, {"B", 0.2, {}}};
  const MeasuredTable table = makeSyntheticTable(lambert, 0.05, 5);
  FitOptions options;
  options.lobes = 1;
  options.kind = LobeKindChoice::Mirror;
  const FitResult fit = fitLobes(table, options);
  ASSERT_TRUE(fit.heldOut);
  EXPECT_NEAR(fit.heldOut->kfold.ratio(), 1.0, 0.02);
  for (const auto& e : fit.heldOut->elevations) EXPECT_NEAR(e.ratio(), 1.0, 0.05) << e.name;
}

TEST(HeldOut, SharedFitOfASharedModelIsAtTheNoiseLevel) {
  // The noise level: the truth's own held-out error (the oracle of ErrorAndSplitsMatchSumsTypedOut).
  const LobeModel truth = sharedModel();
  const MeasuredTable table = makeSyntheticTable(truth, 0.02, 6);
  const HeldOutReport noise = estimateHeldOutError(table, [&](const MeasuredTable&) { return truth; });
  FitOptions options;
  options.lobes = 2;
  options.kind = LobeKindChoice::Lafortune;
  options.elevation = ElevationChoice::Constant;  // as the truth (varying lobes score 4 % lower here, at the noise)
  const FitResult fit = fitLobes(table, options);
  ASSERT_TRUE(fit.heldOut);
  // Measured: 1.12 times the noise on the 5-fold split, 1.0 to 1.27 times on held-out elevations
  // (the fitted weights and shapes carry the training rows' noise to the rows they predict).
  EXPECT_LT(fit.heldOut->kfold.error, 1.15 * noise.kfold.error)
      << fit.heldOut->kfold.error << " vs " << noise.kfold.error;
  EXPECT_GT(fit.heldOut->kfold.error, 0.95 * noise.kfold.error);
  for (std::size_t e = 0; e < noise.elevations.size(); ++e) {
    EXPECT_LT(fit.heldOut->elevations[e].error, 1.3 * noise.elevations[e].error) << noise.elevations[e].name;
  }
  // The shapes are recovered: lobe exponents 40 and 4, c_xy -1.3 and +1 (broadest first).
  const auto& lobes = fit.model.channels[0].lobes;
  ASSERT_EQ(lobes.size(), 2u);
  std::vector<std::pair<double, double>> shapes{{lobes[0].exponent[0], lobes[0].cxy},
                                                {lobes[1].exponent[0], lobes[1].cxy}};
  std::sort(shapes.begin(), shapes.end());
  EXPECT_NEAR(shapes[0].first, 4.0, 0.4);
  EXPECT_NEAR(shapes[0].second, 1.0, 0.05);
  EXPECT_NEAR(shapes[1].first, 40.0, 2.0);
  EXPECT_NEAR(shapes[1].second, -1.3, 0.02);
}

TEST(HeldOut, AutoChoosesByHeldOutScore) {
  const MeasuredTable table = makeSyntheticTable(sharedModel(), 0.02, 7);
  FitOptions options;
  options.maxAutoLobes = 2;
  const FitResult fit = fitLobes(table, options);
  ASSERT_FALSE(fit.candidates.empty());
  const ModelCandidate* chosen = nullptr;
  for (const auto& c : fit.candidates) {
    if (c.chosen) chosen = &c;
  }
  ASSERT_NE(chosen, nullptr);
  // No candidate with fewer parameters is within the margin, none with more beats it by the margin.
  for (const auto& c : fit.candidates) {
    if (c.parameters < chosen->parameters) {
      EXPECT_GT(c.heldOutScore * (1.0 - options.autoMargin), chosen->heldOutScore - 1e-12);
    }
  }
  EXPECT_EQ(chosen->kind, LobeKindChoice::Lafortune);  // the table has a back-scatter lobe mirror lobes cannot make
  EXPECT_EQ(chosen->lobes, 2);
  ASSERT_TRUE(fit.heldOut);
  EXPECT_NEAR(fit.heldOut->score(), chosen->heldOutScore, 1e-12);
}

TEST(HeldOut, TooFewRowsForTheSplitsTakeTheFewestParameters) {
  // Eight rows cannot make five folds of two off-mirror rows each: no estimate, one mirror lobe.
  const MeasuredTable full = makeSyntheticTable(sharedModel(), 0.0, 9);
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < full.size() && rows.size() < 8; i += 97) rows.push_back(i);
  const FitResult fit = fitLobes(tableRows(full, rows));
  EXPECT_FALSE(fit.heldOut.has_value());
  EXPECT_TRUE(fit.candidates.empty());
  ASSERT_EQ(fit.model.channels[0].lobes.size(), 1u);
  EXPECT_TRUE(fit.model.allAboutMirror());
}

TEST(HeldOut, OptionsAreValidated) {
  const MeasuredTable table = makeSyntheticTable(sharedModel(), 0.02, 8);
  auto oracle = [](const MeasuredTable&) { return sharedModel(); };
  HeldOutOptions options;
  options.folds = 1;
  EXPECT_THROW(estimateHeldOutError(table, oracle, options), Error);
  options.folds = 5;
  options.elevationsDegrees = {35.0};  // not an incident elevation of the table
  EXPECT_THROW(estimateHeldOutError(table, oracle, options), Error);
  options.elevationsDegrees = {30.0, 50.0, 70.0};
  EXPECT_EQ(estimateHeldOutError(table, oracle, options).elevations.size(), 3u);
}

// The real tables. Issue 11's target is 0.4x Lambert on every split; asserted here, with a margin,
// is what the shared fit with three half-vector lobes reaches on the RGB tables (docs/fitting.md has
// every table, measured by ../shared/tools/fit_heldout_check.py; this is the fit's own estimate,
// another shuffle of the folds).
struct RealTarget {
  const char* file;
  double kfold, at30, at50, at70;
};

class RealTableHeldOut : public ::testing::TestWithParam<RealTarget> {};

TEST_P(RealTableHeldOut, MeetsTheMeasuredRatios) {
  BRDFBAKE_REQUIRE_SHARED(dir, "data/cornell");
  const RealTarget target = GetParam();
  const MeasuredTable table = readTableForFitting(dir / target.file).toRgb();
  FitOptions options;
  options.lobes = 3;
  options.kind = LobeKindChoice::HalfVector;
  options.heldOut.elevationsDegrees = {30.0, 50.0, 70.0};
  const FitResult fit = fitLobes(table, options);
  ASSERT_TRUE(fit.heldOut);
  const HeldOutReport& h = *fit.heldOut;
  std::cout << target.file << ": k-fold " << h.kfold.ratio() << "x, 30 " << h.elevations[0].ratio() << "x, 50 "
            << h.elevations[1].ratio() << "x, 70 " << h.elevations[2].ratio() << "x Lambert\n";
  EXPECT_LT(h.kfold.ratio(), target.kfold);
  EXPECT_LT(h.elevations[0].ratio(), target.at30);
  EXPECT_LT(h.elevations[1].ratio(), target.at50);
  EXPECT_LT(h.elevations[2].ratio(), target.at70);
}

INSTANTIATE_TEST_SUITE_P(Cornell, RealTableHeldOut,
                         ::testing::Values(RealTarget{"garnet_red_RGB.astm", 0.20, 0.35, 0.30, 0.15},
                                           RealTarget{"krylon_blue_RGB.astm", 0.20, 0.40, 0.60, 0.30}),
                         [](const ::testing::TestParamInfo<RealTarget>& param) {
                           std::string name = param.param.file;
                           for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

}  // namespace
}  // namespace brdfbake
