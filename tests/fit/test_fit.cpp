// Lobe fitting (fit/): the lobe formula against hand-written formulas, the Cornell geometry against
// the real files, recovery of known lobes from synthetic tables on that geometry (holes, 1 %
// noise), degenerate tables, fit.json, table interpolation, the mirror-direction tables and the
// "measured" / "lobes" spec materials.
#include <gtest/gtest.h>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/cornell_grid.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/fit/lobe_fit.hpp>
#include <brdfbake/fit/mirror_direction.hpp>
#include <brdfbake/fit/table_interpolation.hpp>
#include <brdfbake/maps/sphere_map.hpp>
#include <brdfbake/measured/measured_io.hpp>
#include <brdfbake/run/fit_report.hpp>
#include <brdfbake/spec/spec.hpp>

#include <fstream>
#include <random>
#include <set>

#include "fit_file_errors.hpp"
#include "test_support.hpp"

namespace brdfbake {
namespace {

bool imageIsFinite(const Image& image) {
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      if (!image.at(x, y).allFinite()) return false;
  return true;
}

// Hand-written model of one channel: the formula of brdf/lobes.hpp typed out again.
double phongLobeByHand(double c, double n, double cosine) {
  return cosine > 0.0 ? c * (n + 2.0) / (2.0 * kPi) * std::pow(cosine, n) : 0.0;
}

LobeModel constantModel() {
  LobeModel m;
  m.elevation = LobeElevation::Constant;
  m.channels = {{"R", 0.20, {{{0.30}, {12.0}}, {{0.50}, {300.0}}}},
                {"G", 0.10, {{{0.20}, {30.0}}, {{0.45}, {800.0}}}},
                {"B", 0.05, {{{0.10}, {5.0}}, {{0.60}, {150.0}}}}};
  return m;
}

// The elevation range of the Cornell views: theta_s from 0 to 79.05 degrees.
double cornellMinCos() { return std::cos(2.0 * std::asin(0.9 / std::sqrt(2.0))); }

LobeModel varyingModel() {
  LobeModel m;
  m.elevation = LobeElevation::Varying;
  m.minCos = cornellMinCos();
  m.maxCos = 1.0;
  // Lobes that grow and sharpen towards grazing, as measured lacquers do.
  m.channels = {{"R", 0.15, {{{0.80, 0.25, 0.08}, {120.0, 60.0, 25.0}}}},
                {"G", 0.05, {{{0.90, 0.30, 0.10}, {150.0, 70.0, 30.0}}}},
                {"B", 0.02, {{{1.00, 0.35, 0.12}, {180.0, 80.0, 35.0}}}}};
  return m;
}

// Geometric Bernstein blend typed out: p0^((1-t)^2) p1^(2t(1-t)) p2^(t^2).
double blendByHand(const std::vector<double>& p, double u, double minCos, double maxCos) {
  const double t = std::clamp(std::log(u / minCos) / std::log(maxCos / minCos), 0.0, 1.0);
  return std::pow(p[0], (1 - t) * (1 - t)) * std::pow(p[1], 2 * t * (1 - t)) * std::pow(p[2], t * t);
}

// A direction from Cornell angles typed out: (sin theta cos phi, sin theta sin phi, cos theta).
Vec3 directionByHand(double theta, double phi) {
  return Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

// The whole model of one channel typed out (brdf/lobes.hpp): k_d / pi + sum_k C_k(u) (n_k(u) + 2)
// / (2 pi) max(0, r_v . wi)^n_k(u), r_v = wo mirrored about +z, u = wo.z; 0 below the horizon.
double modelByHand(const LobeModel& m, std::size_t c, const Vec3& wi, const Vec3& wo) {
  if (wi.z() <= 0.0 || wo.z() <= 0.0) return 0.0;
  const Vec3 rv(-wo.x(), -wo.y(), wo.z());
  double value = m.channels[c].diffuse / kPi;
  for (const auto& lobe : m.channels[c].lobes) {
    const bool varying = m.elevation == LobeElevation::Varying;
    const double u = std::max(wo.z(), m.minCos);
    const double weight = varying ? blendByHand(lobe.weight, u, m.minCos, m.maxCos) : lobe.weight[0];
    const double exponent = varying ? blendByHand(lobe.exponent, u, m.minCos, m.maxCos) : lobe.exponent[0];
    value += phongLobeByHand(weight, exponent, rv.dot(wi));
  }
  return value;
}

double modelByHand(const LobeModel& m, std::size_t c, const SampleAngles& a) {
  return modelByHand(m, c, directionByHand(a.thetaIn, a.phiIn), directionByHand(a.thetaOut, a.phiOut));
}

TEST(LobeFormula, MatchesTheFormulaTypedOut) {
  const LobeModel m = constantModel();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const Vec3 wi = directionFromAngles(0.5 * kPi * uniform(rng), kTwoPi * uniform(rng));
    const Vec3 wo = directionFromAngles(0.5 * kPi * uniform(rng), kTwoPi * uniform(rng));
    const Vec3 rv(-wo.x(), -wo.y(), wo.z());
    for (std::size_t c = 0; c < 3; ++c) {
      double expected = m.channels[c].diffuse / kPi;
      for (const auto& lobe : m.channels[c].lobes)
        expected += phongLobeByHand(lobe.weight[0], lobe.exponent[0], rv.dot(wi));
      EXPECT_NEAR(m.evaluate(c, wi, wo), expected, 1e-12 * std::max(1.0, expected));
    }
  }
  // Below the horizon there is no BRDF.
  EXPECT_EQ(m.evaluate(0, Vec3(0, 0, -1), Vec3(0, 0, 1)), 0.0);
  // On the mirror direction the lobes peak at C (n + 2) / (2 pi).
  EXPECT_NEAR(m.mirrorValue(0, 0.7), 0.2 / kPi + 0.3 * 14.0 / kTwoPi + 0.5 * 302.0 / kTwoPi, 1e-12);
}

TEST(LobeFormula, VaryingParametersAreGeometricBernsteinBlends) {
  const LobeModel m = varyingModel();
  for (double theta : {0.0, 0.3, 0.8, 1.2, 1.38, 1.5}) {
    const double u = std::cos(theta);
    const auto& lobe = m.channels[1].lobes[0];
    EXPECT_NEAR(m.weight(1, 0, u), blendByHand(lobe.weight, std::max(u, m.minCos), m.minCos, m.maxCos), 1e-12);
    EXPECT_NEAR(m.exponent(1, 0, u), blendByHand(lobe.exponent, std::max(u, m.minCos), m.minCos, m.maxCos), 1e-9);
  }
  // The ends of the range are the first and last values; beyond the range they are held.
  EXPECT_NEAR(m.weight(0, 0, m.minCos), 0.80, 1e-12);
  EXPECT_NEAR(m.weight(0, 0, 0.01), 0.80, 1e-12);
  EXPECT_NEAR(m.exponent(0, 0, 1.0), 25.0, 1e-9);
  // The whole model, one channel and every channel at once (which blends each value once per point;
  // here each channel has its own exponents, so each takes its own powers).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const Vec3 wo = directionFromAngles(0.5 * kPi * uniform(rng), kTwoPi * uniform(rng));
    const Vec3 rv(-wo.x(), -wo.y(), wo.z());
    const Vec3 wi = i % 2 ? (rv + 0.2 * directionFromAngles(kPi * uniform(rng), kTwoPi * uniform(rng))).normalized()
                          : directionFromAngles(0.5 * kPi * uniform(rng), kTwoPi * uniform(rng));
    const Eigen::VectorXd all = m.evaluate(wi, wo);
    for (std::size_t c = 0; c < 3; ++c) {
      const double expected = modelByHand(m, c, wi, wo);
      EXPECT_NEAR(m.evaluate(c, wi, wo), expected, 1e-9 * std::max(1.0, expected)) << i << " channel " << c;
      EXPECT_NEAR(all[static_cast<Eigen::Index>(c)], expected, 1e-9 * std::max(1.0, expected)) << i << " channel " << c;
    }
  }
}

TEST(LobeFormula, NormalisedLobeReflectsItsWeightAboutItsAxis) {
  // Integral over the hemisphere about the axis of C (n+2)/(2 pi) cos^n cos dw = C, by quadrature.
  for (double n : {1.0, 10.0, 300.0}) {
    double sum = 0.0;
    const int steps = 200000;
    for (int i = 0; i < steps; ++i) {
      const double theta = (i + 0.5) * (0.5 * kPi) / steps;
      sum += normalizedLobe(0.7, n, std::cos(theta)) * std::cos(theta) * std::sin(theta) * kTwoPi * (0.5 * kPi / steps);
    }
    EXPECT_NEAR(sum, 0.7, 1e-6) << "n = " << n;
  }
}

TEST(LobeFormula, ValidationNamesTheChannel) {
  LobeModel m = constantModel();
  m.channels[1].lobes[0].exponent[0] = 2e5;
  try {
    m.validate();
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("channel 'G' lobe 0"), std::string::npos) << e.what();
  }
  m = varyingModel();
  m.channels[0].lobes[0].weight[1] = 0.0;  // a geometric blend needs positive values
  EXPECT_THROW(m.validate(), Error);
}

TEST(CornellGrid, HasTheGeometryOfTheCornellFiles) {
  const auto full = cornellSampleAngles(false);
  EXPECT_EQ(full.size(), 8u * 190u);
  const auto measured = cornellSampleAngles(true);
  EXPECT_EQ(measured.size(), 1439u);
  // Every hole lies within 17 degrees of the source, but one.
  int far = 0;
  for (const auto& a : full) {
    if (!isCornellHole(a)) continue;
    const double angle =
        std::acos(directionFromAngles(a.thetaIn, a.phiIn).dot(directionFromAngles(a.thetaOut, a.phiOut)));
    far += angle > radians(17.0);
  }
  EXPECT_EQ(far, 1);
}

TEST(CornellGrid, MatchesEveryRealFileSampleForSample) {
  BRDFBAKE_REQUIRE_SHARED(dir, "data/cornell");
  const auto ours = cornellSampleAngles(true);
  auto key = [](const SampleAngles& a) {
    return std::tuple(std::llround(a.thetaIn * 1e6), std::llround(a.phiIn * 1e6), std::llround(a.thetaOut * 1e6),
                      std::llround(a.phiOut * 1e6));
  };
  std::set<decltype(key(ours[0]))> expected;
  for (const auto& a : ours) expected.insert(key(a));
  for (const char* name : {"garnet_red.astm", "krylon_blue_RGB.astm", "krylon_blue.brdf"}) {
    const MeasuredTable table = readMeasuredTable(dir / name);
    std::set<decltype(key(ours[0]))> got;
    for (const auto& a : table.angles) got.insert(key(a));
    EXPECT_EQ(got, expected) << name;
  }
}

TEST(SyntheticTable, IsTheModelWithRelativeNoise) {
  const MeasuredTable clean = makeSyntheticTable(constantModel(), 0.0, 1);
  const MeasuredTable noisy = makeSyntheticTable(constantModel(), 0.01, 1);
  ASSERT_EQ(clean.size(), 1439u);
  double sum = 0.0, sumSquares = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < clean.size(); ++i) {
    for (Eigen::Index c = 0; c < 3; ++c) {
      const double v = clean.values(static_cast<Eigen::Index>(i), c);
      const double expected = modelByHand(constantModel(), static_cast<std::size_t>(c), clean.angles[i]);
      EXPECT_NEAR(v, expected, 1e-12 * std::max(1.0, expected));
      const double ratio = noisy.values(static_cast<Eigen::Index>(i), c) / v - 1.0;
      sum += ratio, sumSquares += ratio * ratio, ++count;
    }
  }
  EXPECT_NEAR(sum / count, 0.0, 0.001);
  EXPECT_NEAR(std::sqrt(sumSquares / count), 0.01, 0.0005);
}

// The per-channel method with `lobes` lobes of `elevation`, without a held-out estimate.
FitOptions perChannelOptions(int lobes, ElevationChoice elevation) {
  FitOptions options;
  options.method = FitMethod::PerChannel;
  options.lobes = lobes;
  options.elevation = elevation;
  options.estimateHeldOut = false;
  return options;
}

// C within 2 %, n within 5 %, for every lobe of every channel.
void expectRecovered(const LobeModel& truth, const LobeModel& fitted, double u) {
  ASSERT_EQ(fitted.channelCount(), truth.channelCount());
  for (std::size_t c = 0; c < truth.channelCount(); ++c) {
    ASSERT_EQ(fitted.channels[c].lobes.size(), truth.channels[c].lobes.size());
    for (std::size_t k = 0; k < truth.channels[c].lobes.size(); ++k) {
      const double C = truth.weight(c, k, u), n = truth.exponent(c, k, u);
      EXPECT_NEAR(fitted.weight(c, k, u), C, 0.02 * C) << "channel " << c << " lobe " << k << " u " << u;
      EXPECT_NEAR(fitted.exponent(c, k, u), n, 0.05 * n) << "channel " << c << " lobe " << k << " u " << u;
    }
  }
}

TEST(LobeFit, RecoversKnownConstantLobesFromANoisyCornellTable) {
  const LobeModel truth = constantModel();
  const MeasuredTable table = makeSyntheticTable(truth, 0.01, 7);
  // Each channel has its own exponents: the per-channel method (the shared one shares them).
  const FitOptions options = perChannelOptions(2, ElevationChoice::Constant);
  const FitResult fit = fitLobes(table, options);
  ASSERT_TRUE(fit.usable()) << fit.briefReport();
  EXPECT_EQ(fit.model.elevation, LobeElevation::Constant) << fit.briefReport();
  expectRecovered(truth, fit.model, 0.5);
  for (std::size_t c = 0; c < 3; ++c) {
    EXPECT_NEAR(fit.model.channels[c].diffuse, truth.channels[c].diffuse, 0.02 * truth.channels[c].diffuse);
    // 1 % noise on values is 1/3 % on cube roots: the fit sits at the noise level.
    EXPECT_LT(fit.channels[c].logRmse, 0.012);
    EXPECT_EQ(fit.channels[c].solver.termination, "CONVERGENCE");
  }
}

TEST(LobeFit, RecoversKnownVaryingLobesFromANoisyCornellTable) {
  const LobeModel truth = varyingModel();
  const MeasuredTable table = makeSyntheticTable(truth, 0.01, 11);
  const FitOptions options = perChannelOptions(1, ElevationChoice::Varying);
  const FitResult fit = fitLobes(table, options);
  ASSERT_TRUE(fit.usable()) << fit.briefReport();
  EXPECT_NEAR(fit.model.minCos, truth.minCos, 1e-6);
  // At the elevations of the table's incident angles, where the highlights are measured.
  for (int degreesIn = 10; degreesIn <= 80; degreesIn += 10)
    expectRecovered(truth, fit.model, std::cos(radians(degreesIn)));
}

// A spectral table of 20 wavelengths whose lobes change across the spectrum (weights by 3x, the sharp
// lobe's exponent from 150 to 800), as a paint's do. The per-channel method fits a few channels from
// their own starts and the others from a neighbouring wavelength's fit: every channel must still be
// recovered; a black channel fits exactly, and the channel next to it, which would start from it,
// starts from its own starts instead.
LobeModel spectralModel(std::size_t black) {
  LobeModel m;
  m.elevation = LobeElevation::Constant;
  for (int c = 0; c < 20; ++c) {
    const double s = c / 19.0;
    m.wavelengthsNm.push_back(400.0 + 10.0 * c);
    LobeChannel channel{std::to_string(400 + 10 * c) + "nm",
                        0.05 + 0.15 * s,
                        {{{0.30 - 0.2 * s}, {8.0 + 10.0 * s}}, {{0.2 + 0.4 * s * s}, {150.0 + 650.0 * s}}}};
    if (static_cast<std::size_t>(c) == black) channel = {channel.name, 0.0, {{{0.0}, {8.0}}, {{0.0}, {150.0}}}};
    m.channels.push_back(channel);
  }
  return m;
}

TEST(LobeFit, PerChannelRecoversEveryWavelengthOfASpectralTable) {
  const std::size_t black = 2;
  const LobeModel truth = spectralModel(black);
  const FitOptions options = perChannelOptions(2, ElevationChoice::Constant);
  const FitResult fit = fitLobes(makeSyntheticTable(truth, 0.01, 17), options);
  ASSERT_TRUE(fit.usable()) << fit.briefReport();
  ASSERT_EQ(fit.model.channelCount(), truth.channelCount());
  for (std::size_t c = 0; c < truth.channelCount(); ++c) {
    if (c == black) {
      EXPECT_EQ(fit.model.channels[c].diffuse, 0.0);
      for (std::size_t k = 0; k < 2; ++k) EXPECT_EQ(fit.model.weight(c, k, 0.5), 0.0);
      continue;
    }
    EXPECT_NEAR(fit.model.channels[c].diffuse, truth.channels[c].diffuse, 0.02 * truth.channels[c].diffuse) << c;
    for (std::size_t k = 0; k < 2; ++k) {
      const double C = truth.weight(c, k, 0.5), n = truth.exponent(c, k, 0.5);
      EXPECT_NEAR(fit.model.weight(c, k, 0.5), C, 0.02 * C) << "channel " << c << " lobe " << k;
      EXPECT_NEAR(fit.model.exponent(c, k, 0.5), n, 0.05 * n) << "channel " << c << " lobe " << k;
    }
    EXPECT_LT(fit.channels[c].logRmse, 0.012) << c;
  }
}

// Varying lobes across 17 wavelengths (the per-channel fit's anchors are channels 0 and 16; the others
// start from a neighbour, their weights' logarithms shifted): each wavelength's lobe is recovered at the
// table's incident elevations, and the channels started from a neighbour took fewer Ceres iterations
// than the anchors, which start from their own grids and slices.
TEST(LobeFit, PerChannelRecoversVaryingLobesAtEveryWavelength) {
  LobeModel truth = varyingModel();
  const LobeChannel base = truth.channels[0];
  truth.channels.clear();
  for (int c = 0; c < 17; ++c) {
    const double s = c / 16.0;
    truth.wavelengthsNm.push_back(400.0 + 20.0 * c);
    LobeChannel channel = base;
    channel.name = std::to_string(400 + 20 * c) + "nm";
    channel.diffuse = 0.05 + 0.1 * s;
    for (double& w : channel.lobes[0].weight) w *= 0.5 + s;
    for (double& n : channel.lobes[0].exponent) n *= 1.0 + s;
    truth.channels.push_back(channel);
  }
  const FitOptions options = perChannelOptions(1, ElevationChoice::Varying);
  const FitResult fit = fitLobes(makeSyntheticTable(truth, 0.01, 19), options);
  ASSERT_TRUE(fit.usable()) << fit.briefReport();
  for (int degreesIn = 10; degreesIn <= 80; degreesIn += 10)
    expectRecovered(truth, fit.model, std::cos(radians(degreesIn)));
  int anchors = 0, others = 0;
  for (std::size_t c = 0; c < 17; ++c) (c % 16 == 0 ? anchors : others) += fit.channels[c].totalIterations;
  EXPECT_LT(others / 15.0, 0.5 * anchors / 2.0) << fit.briefReport();
}

// The per-channel fit's cost, sum_i 1/2 rho(r_i^2) with Cauchy's rho(s) = a^2 ln(1 + s / a^2), a = 0.2 of
// the channel's largest cube-root target (docs/fitting.md, "Per-channel fits with Ceres"), computed
// here from the fitted model typed out: the cost Ceres reports minimising must be that one, not the
// plain squares, on a table with outliers where the two differ.
TEST(LobeFit, PerChannelReportsTheRobustCostOfItsModel) {
  const LobeModel truth = varyingModel();
  MeasuredTable table = makeSyntheticTable(truth, 0.01, 23);
  for (std::size_t i = 0; i < table.size(); i += 97) table.values.row(static_cast<Eigen::Index>(i)) *= 10.0;
  const FitResult fit = fitLobes(table, perChannelOptions(1, ElevationChoice::Varying));
  ASSERT_TRUE(fit.usable()) << fit.briefReport();
  for (std::size_t c = 0; c < 3; ++c) {
    const auto column = static_cast<Eigen::Index>(c);
    double eps = 0.0, maxTarget = 0.0;
    for (std::size_t i = 0; i < table.size(); ++i) {
      const double cosIn = std::cos(table.angles[i].thetaIn);
      eps = std::max(eps, 1e-6 * std::abs(cosIn * table.values(static_cast<Eigen::Index>(i), column)));
    }
    eps = std::max(eps, 1e-12);
    std::vector<double> r;
    for (std::size_t i = 0; i < table.size(); ++i) {
      const double cosIn = std::cos(table.angles[i].thetaIn);
      const double target = std::cbrt(cosIn * table.values(static_cast<Eigen::Index>(i), column) + eps);
      maxTarget = std::max(maxTarget, target);
      r.push_back(std::cbrt(cosIn * modelByHand(fit.model, c, table.angles[i]) + eps) - target);
    }
    const double a2 = std::pow(0.2 * maxTarget, 2);
    double robust = 0.0, plain = 0.0;
    for (double ri : r) robust += 0.5 * a2 * std::log1p(ri * ri / a2), plain += 0.5 * ri * ri;
    EXPECT_NEAR(fit.channels[c].solver.finalCost, robust, 1e-7 * robust) << "channel " << c;
    EXPECT_GT(plain, 1.2 * robust) << "channel " << c;  // the outliers make the loss matter
  }
}

TEST(LobeFit, AutoElevationPrefersVaryingOnlyWhenTheDataVaries) {
  // The per-channel method with --elevation auto chooses by held-out error (fit/held_out.hpp).
  FitOptions options;
  options.method = FitMethod::PerChannel;
  options.lobes = 1;
  auto scoreOf = [](const FitResult& fit, LobeElevation elevation) {
    for (const auto& candidate : fit.candidates)
      if (candidate.lobes == 1 && candidate.elevation == elevation) return candidate.heldOutScore;
    ADD_FAILURE() << "no 1-lobe " << toString(elevation) << " candidate:\n" << fit.briefReport();
    return 0.0;
  };
  const FitResult varying = fitLobes(makeSyntheticTable(varyingModel(), 0.01, 5), options);
  EXPECT_EQ(varying.model.elevation, LobeElevation::Varying) << varying.briefReport();
  EXPECT_LT(scoreOf(varying, LobeElevation::Varying), scoreOf(varying, LobeElevation::Constant));
  // Data from constant lobes (one per channel, 1 % noise): the fit stays constant and recovers them.
  LobeModel constant;
  constant.channels = {
      {"R", 0.15, {{{0.50}, {80.0}}}}, {"G", 0.10, {{{0.40}, {120.0}}}}, {"B", 0.05, {{{0.60}, {60.0}}}}};
  const FitResult flat = fitLobes(makeSyntheticTable(constant, 0.01, 6), options);
  ASSERT_TRUE(flat.usable()) << flat.briefReport();
  EXPECT_EQ(flat.model.elevation, LobeElevation::Constant) << flat.briefReport();
  for (std::size_t c = 0; c < 3; ++c) {
    EXPECT_NEAR(flat.model.channels[c].lobes[0].weight[0], constant.channels[c].lobes[0].weight[0],
                0.02 * constant.channels[c].lobes[0].weight[0]);
    EXPECT_NEAR(flat.model.channels[c].lobes[0].exponent[0], constant.channels[c].lobes[0].exponent[0],
                0.05 * constant.channels[c].lobes[0].exponent[0]);
  }
}

TEST(LobeFit, OptionsAreValidatedBeforeWork) {
  const MeasuredTable table = makeSyntheticTable(constantModel(), 0.01, 1);
  for (auto change : std::vector<std::function<void(FitOptions&)>>{
           [](FitOptions& o) { o.lobes = 7; }, [](FitOptions& o) { o.autoMargin = 0.0; },
           [](FitOptions& o) { o.lossScale = -1.0; }, [](FitOptions& o) { o.maxIterations = 0; },
           [](FitOptions& o) { o.maxAutoLobes = 0; }}) {
    FitOptions options;
    change(options);
    try {
      fitLobes(table, options);
      ADD_FAILURE() << "accepted bad options";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::InvalidArgument) << e.what();
    }
  }
}

// Degenerate tables: a clear error or a sane documented result, never a crash.
TEST(LobeFitDegenerate, AllZeroChannelFitsExactlyWithZeroWeights) {
  MeasuredTable table = makeSyntheticTable(constantModel(), 0.01, 2);
  table.values.col(1).setZero();
  FitOptions options;
  options.method = FitMethod::PerChannel;
  options.lobes = 2;
  options.elevation = ElevationChoice::Constant;
  const FitResult fit = fitLobes(table, options);
  ASSERT_TRUE(fit.usable()) << fit.briefReport();
  const auto& g = fit.model.channels[1];
  EXPECT_NEAR(g.diffuse, 0.0, 1e-9);
  for (const auto& lobe : g.lobes) EXPECT_NEAR(lobe.weight[0], 0.0, 1e-9);
  EXPECT_NEAR(fit.channels[1].rmsCosineWeighted, 0.0, 1e-9);
  expectRecovered(LobeModel{constantModel().elevation, 0.1, 1.0, {constantModel().channels[0]}, {}},
                  LobeModel{fit.model.elevation, 0.1, 1.0, {fit.model.channels[0]}, {}}, 0.5);
}

TEST(LobeFitDegenerate, OneIncidentAngleFits) {
  const MeasuredTable full = makeSyntheticTable(constantModel(), 0.01, 3);
  MeasuredTable table = full;
  const auto rows = full.samplesAtIncidentTheta(radians(40.0));
  table.angles.clear();
  table.values.resize(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t j = 0; j < rows.size(); ++j) {
    table.angles.push_back(full.angles[rows[j]]);
    table.values.row(static_cast<Eigen::Index>(j)) = full.values.row(static_cast<Eigen::Index>(rows[j]));
  }
  FitOptions perChannel;  // the channels' exponents differ: the per-channel method
  perChannel.method = FitMethod::PerChannel;
  perChannel.lobes = 2;
  perChannel.elevation = ElevationChoice::Constant;
  const FitResult fit = fitLobes(table, perChannel);
  ASSERT_TRUE(fit.usable()) << fit.briefReport();
  // The noise level in the metric of logRmse: the RMS over these samples of ln((cos theta_i f_noisy
  // + d) / (cos theta_i f_true + d)), d = 1e-3 1/sr, i.e. the logRmse the true model itself has here
  // (about 1 %, the noise). A least-squares fit of the samples it saw beats that only by what its
  // parameters absorb, a factor of about sqrt(1 - p / N) = 0.98 for p ~ 5 parameters and N ~ 180
  // samples, and it minimises cube-root residuals rather than log ones: within 10 % of the noise
  // (0.96 to 1.00 of it here).
  const MeasuredTable clean = makeSyntheticTable(constantModel(), 0.0, 3);
  for (std::size_t c = 0; c < 3; ++c) {
    double sum = 0.0;
    for (std::size_t j = 0; j < rows.size(); ++j) {
      const double cosIn = std::cos(full.angles[rows[j]].thetaIn), d = 1e-3;
      const double noisy = full.values(static_cast<Eigen::Index>(rows[j]), static_cast<Eigen::Index>(c));
      const double truth = clean.values(static_cast<Eigen::Index>(rows[j]), static_cast<Eigen::Index>(c));
      sum += std::pow(std::log((cosIn * std::max(noisy, 0.0) + d) / (cosIn * truth + d)), 2);
    }
    const double noise = std::sqrt(sum / rows.size());
    EXPECT_GT(noise, 0.008) << c;
    EXPECT_LT(noise, 0.012) << c;
    EXPECT_LT(fit.channels[c].logRmse, 1.1 * noise) << fit.channels[c].name << "\n" << fit.briefReport();
    EXPECT_GT(fit.channels[c].logRmse, 0.9 * noise) << fit.channels[c].name << "\n" << fit.briefReport();
  }
}

TEST(LobeFitDegenerate, ThreeSamplesFitOneConstantLobeAndTwoAreRefused) {
  const MeasuredTable full = makeSyntheticTable(constantModel(), 0.0, 1);
  MeasuredTable table = full;
  const auto rows = full.samplesAtIncidentTheta(radians(30.0));
  const std::size_t picked[3] = {rows[0], rows[5], rows[9]};
  table.angles.clear();
  table.values.resize(3, 3);
  for (int j = 0; j < 3; ++j) {
    table.angles.push_back(full.angles[picked[j]]);
    table.values.row(j) = full.values.row(static_cast<Eigen::Index>(picked[j]));
  }
  FitOptions perChannel;  // three parameters per channel: the per-channel method
  perChannel.method = FitMethod::PerChannel;
  perChannel.lobes = 1;
  perChannel.elevation = ElevationChoice::Constant;
  const FitResult fit = fitLobes(table, perChannel);
  EXPECT_EQ(fit.model.channels[0].lobes.size(), 1u);
  EXPECT_EQ(fit.model.elevation, LobeElevation::Constant);
  // Three parameters per channel (k_d, C, n) for three noise-free samples: the fitted model, typed
  // out, passes through them (to 3e-10 here; 1e-6 leaves room for the solver's tolerance).
  for (std::size_t c = 0; c < 3; ++c)
    for (int j = 0; j < 3; ++j) {
      const double measured = table.values(j, static_cast<Eigen::Index>(c));
      EXPECT_NEAR(modelByHand(fit.model, c, table.angles[static_cast<std::size_t>(j)]), measured, 1e-6 * measured)
          << "channel " << c << " sample " << j << "\n"
          << fit.briefReport();
    }
  // Asking for more than three samples can determine is an error, not a silent fallback.
  FitOptions options = perChannel;
  options.lobes = 2;
  EXPECT_THROW(fitLobes(table, options), Error);
  table.angles.pop_back();
  table.values.conservativeResize(2, 3);
  try {
    fitLobes(table, perChannel);
    FAIL() << "two samples accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::InvalidInput);
    EXPECT_NE(std::string(e.what()).find("cannot determine"), std::string::npos) << e.what();
  }
}

TEST(LobeFitDegenerate, NaNFieldsAreRejectedNamingTheFileAndLine) {
  test::TempDir dir;
  MeasuredTable table = makeSyntheticTable(constantModel(), 0.0, 1);
  table.values(5, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(fitLobes(table), Error);  // an in-memory table with NaN does not validate
  table.values(5, 1) = 0.5;
  writeAstm(dir / "t.astm", table);
  // Corrupt one field of the written file.
  std::ifstream in(dir / "t.astm");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  const auto vars = s.find("VARS");
  const auto row = s.find('\n', vars) + 1;
  const auto comma = s.find(',', row);
  s.replace(row, comma - row, "nan");
  std::ofstream(dir / "t.astm") << s;
  try {
    readTableForFitting(dir / "t.astm");
    FAIL() << "NaN accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::InvalidInput);
    EXPECT_NE(std::string(e.what()).find("t.astm:"), std::string::npos) << e.what();
  }
}

TEST(FitFile, RoundTripsModelAndStatistics) {
  test::TempDir dir;
  FitOptions options;
  options.method = FitMethod::PerChannel;
  options.lobes = 1;
  options.elevation = ElevationChoice::Varying;
  FitFile file;
  file.source = {"synthetic", "synthetic", 1439, "rgb", {"a note"}};
  file.fit = fitLobes(makeSyntheticTable(varyingModel(), 0.01, 4), options);
  writeFitFile(dir / "fit.json", file);
  const FitFile back = readFitFile(dir / "fit.json");
  EXPECT_EQ(back.source.notes, file.source.notes);
  EXPECT_EQ(back.fit.model.elevation, LobeElevation::Varying);
  EXPECT_EQ(back.fit.model.minCos, file.fit.model.minCos);
  for (std::size_t c = 0; c < 3; ++c) {
    EXPECT_EQ(back.fit.model.channels[c].diffuse, file.fit.model.channels[c].diffuse);
    EXPECT_EQ(back.fit.model.channels[c].lobes[0].weight, file.fit.model.channels[c].lobes[0].weight);
    EXPECT_EQ(back.fit.model.channels[c].lobes[0].exponent, file.fit.model.channels[c].lobes[0].exponent);
    EXPECT_EQ(back.fit.channels[c].logRmse, file.fit.channels[c].logRmse);
    EXPECT_EQ(back.fit.channels[c].solver.termination, file.fit.channels[c].solver.termination);
    EXPECT_EQ(back.fit.channels[c].worst.index, file.fit.channels[c].worst.index);
  }
  EXPECT_EQ(back.fit.candidates.size(), file.fit.candidates.size());
  EXPECT_TRUE(back.fit.usable());
}

TEST(FitFile, ErrorsNameTheJsonPath) {
  FitFile file;
  file.fit.model = constantModel();
  file.hasFitInfo = false;
  const nlohmann::json good = nlohmann::json::parse(fitFileToJson(file).dump());
  EXPECT_NO_THROW(fitFileFromJson(good, "fit.json"));
  const auto expectError = test::expectFitFileError;
  nlohmann::json d = good;
  d["channels"][1]["lobes"][0]["exponent"][0] = 2e5;
  expectError(d, "channels[1].lobes[0].exponent[0]");
  d = good;
  d["version"] = 2;
  expectError(d, "version");
  d = good;
  d["channels"][0]["diffuse"] = -1;
  expectError(d, "channels[0].diffuse");
  // Weights as large as a double allows once passed and crashed the matcap's lobe sampler (exit 139):
  // weights and diffuse terms lie in [0, 1e6], the bound of a spec's colours.
  d = good;
  d["channels"][0]["diffuse"] = 1e308;
  expectError(d, "channels[0].diffuse");
  d = good;
  d["channels"][0]["lobes"][0]["weight"][0] = 1e308;
  expectError(d, "channels[0].lobes[0].weight[0]");
  d = good;
  d["channels"][0]["lobes"][0]["weight"][0] = 1e6;
  EXPECT_NO_THROW(fitFileFromJson(d, "fit.json"));
  LobeModel huge = constantModel();
  huge.channels[1].lobes[0].weight[0] = 2e6;
  EXPECT_THROW(huge.validate(), Error);
  d = good;
  d["channels"][2]["lobes"][1]["wieght"] = 1;
  expectError(d, "wieght");
  d = good;
  d["model"]["elevation"] = "varying";  // then one value per parameter is too few
  expectError(d, "channels[0].lobes[0].weight");
  d = good;
  d["channels"][0]["lobes"].erase(1);
  expectError(d, "channels[0].lobes");
}

TEST(TableInterpolation, ReturnsSamplesAndUsesSymmetryAndIsotropy) {
  const MeasuredTable table = makeSyntheticTable(constantModel(), 0.01, 9);
  const TableInterpolator interpolator(table);
  for (std::size_t i : {0ul, 100ul, 777ul, 1400ul}) {
    const Vec3 wi = table.incidentDirection(i), wo = table.outgoingDirection(i);
    const Eigen::VectorXd expected = table.values.row(static_cast<Eigen::Index>(i)).transpose();
    EXPECT_TRUE(interpolator.evaluate(wi, wo).isApprox(expected, 1e-12));
    // The mirror image (phi_s -> -phi_s) and any rotation about the normal give the same value.
    const Vec3 mirrored(wo.x(), -wo.y(), wo.z());
    EXPECT_TRUE(interpolator.evaluate(wi, mirrored).isApprox(expected, 1e-12));
    const Eigen::AngleAxisd rotation(1.234, Vec3::UnitZ());
    EXPECT_TRUE(interpolator.evaluate(rotation * wi, rotation * wo).isApprox(expected, 1e-9));
  }
  // Between samples: a weighted mean of the 4 nearest, so inside their range.
  const Vec3 wi = directionFromAngles(radians(30.0), 0.0), wo = directionFromAngles(radians(45.0), radians(-100.0));
  const Eigen::VectorXd v = interpolator.evaluate(wi, wo);
  const auto rows = table.samplesAtIncidentTheta(radians(30.0));
  std::vector<std::pair<double, std::size_t>> byDistance;
  for (std::size_t r : rows) byDistance.emplace_back(std::acos(std::min(1.0, wo.dot(table.outgoingDirection(r)))), r);
  std::sort(byDistance.begin(), byDistance.end());
  for (Eigen::Index c = 0; c < 3; ++c) {
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (int k = 0; k < 4; ++k) {
      lo = std::min(lo, table.values(static_cast<Eigen::Index>(byDistance[static_cast<std::size_t>(k)].second), c));
      hi = std::max(hi, table.values(static_cast<Eigen::Index>(byDistance[static_cast<std::size_t>(k)].second), c));
    }
    EXPECT_GE(v[c], lo);
    EXPECT_LE(v[c], hi);
  }
  EXPECT_EQ(interpolator.evaluate(wi, Vec3(0, 0, -1)).norm(), 0.0);
}

TEST(MirrorDirectionTable, SeedsWayTakesTheStrongestSampleNearTheMirror) {
  const MeasuredTable table = makeSyntheticTable(constantModel(), 0.0, 1);
  const MirrorDirectionTable seed = strongestNearMirrorTable(table, radians(10.0));
  ASSERT_EQ(seed.thetas.size(), 8u);
  for (std::size_t r = 0; r < 8; ++r) {
    const Vec3 mirror = reflect(directionFromAngles(seed.thetas[r], 0.0), Vec3(Vec3::UnitZ()));
    for (Eigen::Index c = 0; c < 3; ++c) {
      double best = -1.0;
      for (std::size_t i : table.samplesAtIncidentTheta(seed.thetas[r])) {
        if (std::acos(std::min(1.0, mirror.dot(table.outgoingDirection(i)))) <= radians(10.0)) {
          best = std::max(best, table.values(static_cast<Eigen::Index>(i), c));
        }
      }
      EXPECT_EQ(seed.values(static_cast<Eigen::Index>(r), c), best);
      EXPECT_GT(seed.offsets(static_cast<Eigen::Index>(r), c), radians(0.1));  // never on the mirror itself
    }
  }
  // The fitted table is the model on the exact mirror direction, so Zimmons & Bastos 1999's way is lower
  // for these sharp lobes.
  const MirrorDirectionTable fitted = fittedMirrorTable(constantModel(), seed.thetas);
  for (std::size_t r = 0; r < 8; ++r) {
    EXPECT_NEAR(fitted.values(static_cast<Eigen::Index>(r), 0), 0.2 / kPi + 0.3 * 14 / kTwoPi + 0.5 * 302 / kTwoPi,
                1e-12);
    EXPECT_LT(seed.values(static_cast<Eigen::Index>(r), 0), fitted.values(static_cast<Eigen::Index>(r), 0));
  }
  // Linear in theta between angles, held beyond them.
  const double mid = 0.5 * (seed.thetas[2] + seed.thetas[3]);
  EXPECT_NEAR(seed.at(mid)[1], 0.5 * (seed.values(2, 1) + seed.values(3, 1)), 1e-12);
  EXPECT_EQ(seed.at(0.0)[2], seed.values(0, 2));
  EXPECT_EQ(seed.at(1.5)[2], seed.values(7, 2));
}

TEST(LobeMaterialTest, ReflectanceAndLightingFollowTheModel) {
  const LobeModel model = varyingModel();
  const LobeMaterial reflectance(model, LobeMaterialMode::Reflectance);
  const LobeMaterial lighting(model, LobeMaterialMode::Lighting);
  EXPECT_FALSE(reflectance.usesLights());
  EXPECT_TRUE(lighting.usesLights());
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  for (int i = 0; i < 50; ++i) {
    const Vec3 r = Vec3(g(rng), g(rng), g(rng)).normalized();
    const ShadingGeometry geometry = geometryForReflection(r, Vec3::UnitZ());
    const double nv = geometry.normal.dot(geometry.view);
    const Rgb value = reflectance.unlit(geometry);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(value[c], model.mirrorValue(static_cast<std::size_t>(c), nv), 1e-12);
    // Lighting in any frame equals the model in the local frame of the normal, times n.l.
    const Vec3 light = Vec3(g(rng), g(rng), std::abs(g(rng))).normalized();
    const Eigen::Quaterniond toLocal = Eigen::Quaterniond::FromTwoVectors(geometry.normal, Vec3::UnitZ());
    const Vec3 wi = toLocal * light, wo = toLocal * geometry.view;
    const Rgb lit = lighting.shade(geometry, light);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(lit[c], model.evaluate(static_cast<std::size_t>(c), wi, wo) * std::max(0.0, wi.z()),
                  1e-9 * (1.0 + lit[c]));
    }
  }
}

TEST(SpecMaterials, LobesAndMeasuredBakeIntoSphereMaps) {
  test::TempDir dir;
  FitFile file;
  file.fit.model = varyingModel();
  file.hasFitInfo = false;
  file.hasSource = false;
  writeFitFile(dir / "fit.json", file);
  writeAstm(dir / "table.astm", makeSyntheticTable(constantModel(), 0.0, 1));
  const nlohmann::json spec = {{"maps",
                                {{{"output", "lobes.exr"},
                                  {"parameterization", "sphere"},
                                  {"resolution", 32},
                                  {"samples_per_texel", 1},
                                  {"material", {{"model", "lobes"}, {"file", "fit.json"}}}},
                                 {{"output", "mirror.exr"},
                                  {"parameterization", "sphere"},
                                  {"resolution", 32},
                                  {"samples_per_texel", 1},
                                  {"material", {{"model", "measured"}, {"file", "table.astm"}, {"method", "mirror"}}}},
                                 {{"output", "lit.exr"},
                                  {"parameterization", "paraboloid"},
                                  {"resolution", 32},
                                  {"samples_per_texel", 1},
                                  {"view", {0, 0, 1}},
                                  {"material", {{"model", "lobes"}, {"file", "fit.json"}, {"mode", "lighting"}}},
                                  {"lights", {{{"direction", {0.3, 0.2, 1.0}}}}}}}}};
  const BakeSpec parsed = parseBakeSpec(spec, dir.path(), "spec.json");
  ASSERT_EQ(parsed.maps.size(), 3u);
  BakeOptions options;
  options.samplesPerTexel = 1;
  const SphereMap sphere(32);
  // Texel centres: the sphere map's normal at a texel is n = (x, y, sqrt(1 - x^2 - y^2)).
  const Image lobes = bake(sphere, *parsed.maps[0].makeFunction(), options);
  const Image mirror = bake(sphere, *parsed.maps[1].makeFunction(), options);
  const MirrorDirectionTable table = strongestNearMirrorTable(makeSyntheticTable(constantModel(), 0.0, 1));
  for (int y = 2; y < 30; y += 5) {
    for (int x = 2; x < 30; x += 5) {
      const double sx = (x + 0.5) / 32 * 2 - 1, sy = 1 - (y + 0.5) / 32 * 2;
      if (sx * sx + sy * sy > 0.95) continue;
      const double nz = std::sqrt(1 - sx * sx - sy * sy);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(lobes.at(x, y)[c], varyingModel().mirrorValue(static_cast<std::size_t>(c), nz),
                    1e-4 * (1 + lobes.at(x, y)[c]));
        EXPECT_NEAR(mirror.at(x, y)[c], table.at(std::acos(nz))[c], 1e-4 * (1 + mirror.at(x, y)[c]));
      }
    }
  }
  // Lighting mode, view +z, one white light l: texel r holds f(l, v) max(0, n.l) with n =
  // normalize(r + v), u = n.v and, in the frame of n, r_v = r: k_d / pi + sum_k C_k(u) (n_k(u) + 2)
  // / (2 pi) max(0, r.l)^n_k(u) (typed out), times n.l.
  const auto paraboloid = makeParameterization(ParameterizationKind::Paraboloid, 32);
  const Image lit = bake(*paraboloid, *parsed.maps[2].makeFunction(), options);
  const LobeModel truth = varyingModel();
  const Vec3 light = Vec3(0.3, 0.2, 1.0).normalized();
  int checked = 0;
  for (int y = 0; y < lit.height(); ++y)
    for (int x = 0; x < lit.width(); ++x) {
      if (paraboloid->texelCoverage(x, y) < 1.0) continue;
      const Vec3 r = *paraboloid->getDirectionFor(Vec2(x + 0.5, y + 0.5));
      const Vec3 n = (r + Vec3::UnitZ()).normalized();
      const double u = n.z(), nl = n.dot(light);
      for (std::size_t c = 0; c < 3; ++c) {
        double expected = 0.0;
        if (nl > 0.0) {
          expected = truth.channels[c].diffuse / kPi;
          for (const auto& lobe : truth.channels[c].lobes) {
            const double uc = std::max(u, truth.minCos);
            expected += phongLobeByHand(blendByHand(lobe.weight, uc, truth.minCos, truth.maxCos),
                                        blendByHand(lobe.exponent, uc, truth.minCos, truth.maxCos), r.dot(light));
          }
          expected *= nl;
        }
        EXPECT_NEAR(lit.at(x, y)[static_cast<int>(c)], expected, 1e-5 * (1.0 + expected))
            << "texel " << x << "," << y << " channel " << c;
      }
      ++checked;
    }
  EXPECT_GT(checked, 1000);
}

TEST(SpecMaterials, ErrorsNameTheJsonPath) {
  test::TempDir dir;
  writeAstm(dir / "table.astm", makeSyntheticTable(constantModel(), 0.0, 1));
  auto errorFor = [&](const nlohmann::json& material) -> std::string {
    try {
      parseBakeSpec({{"maps", {{{"output", "a.exr"}, {"parameterization", "sphere"}, {"material", material}}}}},
                    dir.path(), "spec.json");
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::InvalidInput) << e.what();
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(errorFor({{"model", "measured"}, {"file", "table.astm"}}).find("maps[0].material.method: required"),
            std::string::npos);
  EXPECT_NE(errorFor({{"model", "measured"}, {"file", "table.astm"}, {"method", "mirror"}, {"lobes", 2}})
                .find("maps[0].material.lobes"),
            std::string::npos);
  EXPECT_NE(
      errorFor({{"model", "measured"}, {"file", "missing.astm"}, {"method", "mirror"}}).find("maps[0].material.file"),
      std::string::npos);
  EXPECT_NE(errorFor({{"model", "lobes"}, {"file", "table.astm"}}).find("maps[0].material.file"), std::string::npos);
  EXPECT_NE(errorFor({{"model", "lobes"}, {"file", "x.json"}, {"mode", "shiny"}}).find("maps[0].material.mode"),
            std::string::npos);
}

TEST(FitReport, ScriptPlotsThePlaneOfIncidence) {
  const LobeModel model = constantModel();
  const MeasuredTable table = makeSyntheticTable(model, 0.0, 1);
  const std::string script = fitReportScript("/tmp/x.png", table, model, "t");
  EXPECT_NE(script.find("multiplot layout 2,4"), std::string::npos);
  // The measured mirror-side sample at theta_i = 40, theta_s = 41.41 degrees (ring 5) is listed
  // with its value.
  const auto rows = table.samplesAtIncidentTheta(radians(40.0));
  for (std::size_t i : rows) {
    if (std::abs(table.angles[i].phiOut - kPi) < 1e-5 && std::abs(degrees(table.angles[i].thetaOut) - 41.4096) < 1e-3) {
      std::ostringstream line;
      line.precision(9);
      line << degrees(table.angles[i].thetaOut) << " " << table.values(static_cast<Eigen::Index>(i), 0);
      EXPECT_NE(script.find(line.str()), std::string::npos) << line.str();
    }
  }
}

// The real tables: fit with the defaults, converge, bake. Errors and times are printed for docs.
class RealTable : public ::testing::TestWithParam<const char*> {};

TEST_P(RealTable, FitsConvergesAndBakes) {
  BRDFBAKE_REQUIRE_SHARED(dir, "data/cornell");
  const MeasuredTable table = readTableForFitting(dir / GetParam()).toRgb();
  const FitResult fit = fitLobes(table);
  ASSERT_TRUE(fit.usable()) << fit.briefReport();
  for (const auto& c : fit.channels) {
    EXPECT_EQ(c.solver.termination, "CONVERGENCE") << c.name;
    // Radiance-weighted RMS error against peaks of 5-10 1/sr (cos 80 x 30-60 1/sr).
    EXPECT_LT(c.rmsCosineWeighted, 0.1) << c.name << "\n" << fit.briefReport();
  }
  std::cout << GetParam() << ": " << fit.briefReport();
  const LobeMaterial material(fit.model, LobeMaterialMode::Reflectance);
  const Image image =
      bake(SphereMap(32), MaterialMapFunction(std::make_shared<LobeMaterial>(material), {}, Vec3::UnitZ()));
  EXPECT_TRUE(imageIsFinite(image));
  EXPECT_GT(image.at(16, 16)[0], 0.0);
}

INSTANTIATE_TEST_SUITE_P(Cornell, RealTable,
                         ::testing::Values("garnet_red.astm", "garnet_red_RGB.astm", "krylon_blue.astm",
                                           "krylon_blue_RGB.astm", "krylon_blue.brdf"),
                         [](const ::testing::TestParamInfo<const char*>& param) {
                           std::string name = param.param;
                           for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

TEST(RealTableSpectral, EveryWavelengthFits) {
  BRDFBAKE_REQUIRE_SHARED(dir, "data/cornell");
  const MeasuredTable table = readTableForFitting(dir / "krylon_blue.astm");
  const FitOptions options = perChannelOptions(1, ElevationChoice::Varying);
  const FitResult fit = fitLobes(table, options);
  ASSERT_TRUE(fit.usable()) << fit.briefReport();
  ASSERT_EQ(fit.channels.size(), 31u);
  EXPECT_EQ(fit.model.wavelengthsNm, table.wavelengthsNm);
  std::cout << fit.briefReport();
  // Held-in error per wavelength, the fitted model typed out against every sample of the table:
  // the RMS of cos theta_i (f_fit - f_measured) is what the fit reports, and under 4 % of the
  // brightest cos theta_i f of that wavelength (measured: 0.5 to 0.8 % from 410 to 510 nm, 2.7 to
  // 3.0 % at 400 nm and from 520 nm on).
  for (std::size_t c = 0; c < 31; ++c) {
    double sum = 0.0, peak = 0.0;
    for (std::size_t i = 0; i < table.size(); ++i) {
      const double cosIn = std::cos(table.angles[i].thetaIn);
      const double measured = table.values(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c));
      sum += std::pow(cosIn * (modelByHand(fit.model, c, table.angles[i]) - measured), 2);
      peak = std::max(peak, cosIn * measured);
    }
    const double rms = std::sqrt(sum / table.size());
    EXPECT_NEAR(fit.channels[c].rmsCosineWeighted, rms, 1e-9 * rms) << table.channelNames[c];
    EXPECT_LT(rms, 0.04 * peak) << table.channelNames[c] << ": rms " << rms << " peak " << peak;
  }
  // A spectral fit bakes through the CIE 1931 conversion.
  const auto material = std::make_shared<LobeMaterial>(fit.model, LobeMaterialMode::Reflectance);
  const Image image = bake(SphereMap(16), MaterialMapFunction(material, {}, Vec3::UnitZ()));
  EXPECT_TRUE(imageIsFinite(image));
}

TEST(MerlSampling, SamplesTheFullCornellGridAndSkipsUnmeasuredBins) {
  // A constant MERL table: stored 1500 in every bin gives BRDF (1, 1.15, 1.66); one bin unmeasured.
  std::vector<double> stored(3 * MerlTable::kBinsPerChannel, 1500.0);
  const MerlTable probe(stored);
  const auto a = cornellSampleAngles(false)[100];
  const auto hd = MerlTable::halfDiffCoordinates(directionFromAngles(a.thetaIn, a.phiIn),
                                                 directionFromAngles(a.thetaOut, a.phiOut));
  const std::size_t bin =
      static_cast<std::size_t>(MerlTable::phiDiffIndex(hd.phiDiff)) +
      MerlTable::kPhiDiffBins *
          (static_cast<std::size_t>(MerlTable::thetaDiffIndex(hd.thetaDiff)) +
           MerlTable::kThetaDiffBins * static_cast<std::size_t>(MerlTable::thetaHalfIndex(hd.thetaHalf)));
  stored[bin] = -1.0;
  const MeasuredTable table = sampleMerlOnCornellGrid(MerlTable(std::move(stored)));
  EXPECT_LT(table.size(), 1520u);
  EXPECT_GE(table.size(), 1519u - 8u);  // the unmeasured bin may be hit by a few grid directions
  for (std::size_t i = 0; i < table.size(); i += 97) {
    EXPECT_NEAR(table.values(static_cast<Eigen::Index>(i), 0), 1.0, 1e-12);
    EXPECT_NEAR(table.values(static_cast<Eigen::Index>(i), 2), 1.66, 1e-12);
  }
}

// Linear in theta: a quarter of the way from 0.2 to 0.6 rad is 1 + (5 - 1) / 4 (the midpoint alone
// cannot tell the two weights apart).
TEST(MirrorDirectionTable, AtWeighsTheNearerAngleMore) {
  MirrorDirectionTable table;
  table.thetas = {0.2, 0.6};
  table.values.resize(2, 1);
  table.values << 1.0, 5.0;
  table.offsets = Eigen::MatrixXd::Zero(2, 1);
  table.channelNames = {"Y"};
  table.validate();
  EXPECT_NEAR(table.at(0.3)[0], 2.0, 1e-12);
  EXPECT_NEAR(table.at(0.5)[0], 4.0, 1e-12);
}

// The weights are 1 / angle^2 (table_interpolation.hpp): a query 5 and 15 degrees from the two
// nearest samples (both in the plane of incidence, so the mirror image is the query itself) gets
// (1/25 v1 + 1/225 v2) / (1/25 + 1/225) = (9 v1 + v2) / 10.
TEST(TableInterpolation, NeighboursWeighOneOverTheirAngleSquared) {
  MeasuredTable table;
  table.kind = ChannelKind::Monochrome;
  table.channelNames = {"Y"};
  table.angles = {
      {radians(30), 0, radians(20), kPi}, {radians(30), 0, radians(40), kPi}, {radians(30), 0, radians(80), kPi}};
  table.values.resize(3, 1);
  table.values << 1.0, 10.0, 100.0;
  const TableInterpolator interpolator(table, 2);
  const Vec3 wi = directionFromAngles(radians(30), 0.0), wo = directionFromAngles(radians(25), kPi);
  EXPECT_NEAR(interpolator.evaluate(wi, wo)[0], (9.0 * 1.0 + 10.0) / 10.0, 1e-9);
}

}  // namespace
}  // namespace brdfbake
