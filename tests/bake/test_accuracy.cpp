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

TEST(Accuracy, MeasuringLookedUpValuesEqualsMeasuringTheLookup) {
  const Lobe function;
  ErrorOptions options;
  options.samples = 500;
  const ErrorProbes probes(function, options);
  auto lookup = [&](const Vec3& r) -> Rgb { return 1.05 * function.evaluate(r) + 0.01; };
  for (bool visible : {false, true}) {
    std::vector<Rgb> looked;
    for (const Vec3& d : probes.directions(visible)) looked.push_back(lookup(d));
    const ErrorStats direct = probes.measure(lookup, 0.5, visible), values = probes.measureValues(looked, 0.5, visible);
    EXPECT_EQ(direct.highlightRms, values.highlightRms);
    EXPECT_EQ(direct.visibleRms, values.visibleRms);
    EXPECT_EQ(direct.rms, values.rms);
    looked.pop_back();
    EXPECT_THROW(probes.measureValues(looked, 0.5, visible), Error);
  }
}

}  // namespace
}  // namespace brdfbake
