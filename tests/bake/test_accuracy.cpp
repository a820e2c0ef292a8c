// Error measurement against hand-made cases with known answers.
#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/bake/radial_profile.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/paraboloid_map.hpp>
#include <brdfbake/maps/sphere_map.hpp>

#include <gtest/gtest.h>
#include <cmath>

namespace brdfbake {
namespace {

class Constant final : public MapFunction {
 public:
  explicit Constant(double v) : v_(v) {}
  Rgb evaluate(const Vec3&) const override { return Rgb::Constant(v_); }

 private:
  double v_;
};

TEST(Accuracy, ExactMapHasNoErrorAndAnOffsetMapItsOffset) {
  const ParaboloidMap map(16);
  const Image image = bake(map, Constant(2.0));
  EXPECT_NEAR(measureMapError(image, map, Constant(2.0)).rms, 0.0, 1e-7);
  // Against 2.5 the error is 0.5 everywhere: relative to the peak 2.5, 0.2, both RMS and max.
  const ErrorStats off = measureMapError(image, map, Constant(2.5));
  EXPECT_NEAR(off.rms, 0.2, 1e-6);
  EXPECT_NEAR(off.max, 0.2, 1e-6);
  EXPECT_NEAR(off.peak, 2.5, 1e-12);
  EXPECT_EQ(off.visibleRms, off.rms);  // not a sphere map
}

TEST(Accuracy, SphereMapsAlsoMeasureTheVisibleSphere) {
  const SphereMap map(32);
  const ErrorStats stats = measureMapError(bake(map, Constant(1.0)), map, Constant(0.5));
  EXPECT_NEAR(stats.visibleRms, 1.0, 1e-6);  // |1 - 0.5| / peak 0.5
}

// A lobe about an off-axis direction plus a colour gradient; no radial lobes declared, so the
// baker takes its general path (the model at every sample), which the estimate reproduces.
class Lobe final : public MapFunction {
 public:
  Rgb evaluate(const Vec3& r) const override {
    const double c = std::max(0.0, r.dot(Vec3(0.3, 0.4, 0.866).normalized()));
    return Rgb(std::pow(c, 60.0) + 0.1 * (1.0 + r.x()), std::pow(c, 20.0), 0.2 + 0.1 * r.y());
  }
};

TEST(Accuracy, EstimatesEqualTheMeasureOfTheBakedMap) {
  // estimateMapError reads only the texels the probes read, computed one at a time; the baker
  // computes every texel row by row. Both are the general path, so the errors agree, to the float
  // rounding of a texel (a few texels round the other way: 1e-8 of the errors).
  const Lobe function;
  ErrorOptions options;
  options.samples = 3000;
  const ErrorProbes probes(function, options);
  for (auto kind : {ParameterizationKind::Sphere, ParameterizationKind::Paraboloid, ParameterizationKind::Cube,
                    ParameterizationKind::LatLong}) {
    for (int spt : {1, 4, 6}) {
      const auto map = makeParameterization(kind, 24);
      BakeOptions bakeOptions;
      bakeOptions.samplesPerTexel = spt;
      const ErrorStats baked = measureMapError(bake(*map, function, bakeOptions), *map, probes);
      const ErrorStats estimated = estimateMapError(*map, function, spt, probes);
      const std::string what = std::string(toString(kind)) + ", " + std::to_string(spt) + " samples";
      EXPECT_GT(baked.highlightRms, 1e-3) << what;  // a real error, not zero against zero
      EXPECT_NEAR(estimated.highlightRms, baked.highlightRms, 1e-6 * baked.highlightRms) << what;
      EXPECT_NEAR(estimated.rms, baked.rms, 1e-6 * baked.rms) << what;
      EXPECT_NEAR(estimated.visibleRms, baked.visibleRms, 1e-6 * baked.visibleRms) << what;
      EXPECT_NEAR(estimated.max, baked.max, 1e-6 * baked.max) << what;
      EXPECT_EQ(estimated.peak, baked.peak) << what;
    }
  }
  // Profiles about the view and about another axis.
  for (const Vec3& axis : {Vec3(Vec3::UnitZ()), Vec3(0.3, 0.4, 0.866)}) {
    for (int spt : {1, 3}) {
      const ErrorStats baked = measureProfileError(bakeRadialProfile(function, axis, 40, spt), probes);
      const ErrorStats estimated = estimateProfileError(function, axis, 40, spt, probes);
      EXPECT_GT(baked.highlightRms, 1e-3);
      EXPECT_NEAR(estimated.highlightRms, baked.highlightRms, 1e-12 * baked.highlightRms);
      EXPECT_NEAR(estimated.visibleRms, baked.visibleRms, 1e-12 * baked.visibleRms);
    }
  }
}

// A grey ramp f(r) = a + b r_z: its integrals over the sphere are integrals over z in [-1, 1]
// (dw = 2 pi dz), so every measure of a lookup k f + d has a closed form.
class Ramp final : public MapFunction {
 public:
  static constexpr double a = 0.5, b = 0.4;
  Rgb evaluate(const Vec3& r) const override { return Rgb::Constant(a + b * r.z()); }
};

TEST(Accuracy, MeasuresOfLookedUpValuesMatchTheirIntegrals) {
  // The lookup (1 + k) f + d errs by e(z) = k (a + b z) + d in every channel. Over directions uniform
  // on the sphere, and over the visible sphere's reflected vectors (r_z = 1 - 2 rho^2 with rho^2
  // uniform on the disc: uniform too), mean e^2 = (k a + d)^2 + (k b)^2 / 3; the largest error is
  // e(1); the value-weighted mean is int f e^2 dz / int f dz (midpoint rule below); the peak is
  // f(1) = a + b. Tolerances: 5 standard errors of the Monte Carlo means over 20000 directions
  // (std(e^2) / sqrt(20000) = 6e-6 here, 0.43 % of mean e^2: 1.1 % on the RMS), doubled for the importance-weighted
  // set.
  constexpr double k = 0.05, d = 0.01, a = Ramp::a, b = Ramp::b;
  const Ramp function;
  ErrorOptions options;
  options.samples = 20000;
  const ErrorProbes probes(function, options);
  auto e = [&](double z) { return k * (a + b * z) + d; };
  const double meanSquare = (k * a + d) * (k * a + d) + k * k * b * b / 3.0;
  double weighted = 0.0, weight = 0.0, meanFourth = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const double z = -1.0 + (i + 0.5) / 100000.0, f = a + b * z;
    weighted += f * e(z) * e(z);
    weight += f;
    meanFourth += std::pow(e(z), 4) / 200000.0;
  }
  const double peak = a + b, rms = std::sqrt(meanSquare) / peak, highlight = std::sqrt(weighted / weight) / peak;
  const double standardError = std::sqrt((meanFourth - meanSquare * meanSquare) / options.samples);
  const double tolerance = 5.0 * standardError / (2.0 * meanSquare);  // relative, on the RMS
  ASSERT_LT(tolerance, 0.012);
  for (bool visible : {false, true}) {
    std::vector<Rgb> looked;
    for (const Vec3& r : probes.directions(visible)) looked.push_back((1.0 + k) * function.evaluate(r) + d);
    const ErrorStats stats = probes.measureValues(looked, 2.0, visible);
    EXPECT_NEAR(stats.peak, peak, 1e-3 * peak);  // the highlight set reaches z = 1 within 1e-3
    EXPECT_NEAR(stats.rms, rms, tolerance * rms);
    EXPECT_NEAR(stats.visibleRms, rms, tolerance * rms) << "visible " << visible;
    EXPECT_NEAR(stats.highlightRms, highlight, 2.0 * tolerance * highlight);
    EXPECT_LE(stats.max, e(1.0) / stats.peak * (1 + 1e-9));  // errors are over the measured peak
    EXPECT_GT(stats.max, e(0.999) / stats.peak);             // 20000 uniform directions: some with z > 0.999
    // The same lookups made by measure() are measured the same way.
    const ErrorStats direct =
        probes.measure([&](const Vec3& r) -> Rgb { return (1.0 + k) * function.evaluate(r) + d; }, 2.0, visible);
    EXPECT_NEAR(direct.rms, rms, tolerance * rms);
    EXPECT_NEAR(direct.highlightRms, highlight, 2.0 * tolerance * highlight);
    looked.pop_back();
    EXPECT_THROW(probes.measureValues(looked, 2.0, visible), Error);
  }
  // Leaving out the rim (-r_z > 0.5) leaves z in [-0.5, 1]: mean e^2 over that band.
  std::vector<Rgb> looked;
  for (const Vec3& r : probes.directions(false)) looked.push_back((1.0 + k) * function.evaluate(r) + d);
  double band = 0.0;
  for (int i = 0; i < 150000; ++i) {
    const double z = -0.5 + (i + 0.5) / 100000.0;
    band += e(z) * e(z) / 150000.0;
  }
  const double bandRms = std::sqrt(band) / peak;
  EXPECT_NEAR(probes.measureValues(looked, 0.5, false).rms, bandRms, 1.5 * tolerance * bandRms);
}

}  // namespace
}  // namespace brdfbake
