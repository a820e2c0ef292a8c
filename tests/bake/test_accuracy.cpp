// Error measurement against hand-made cases with known answers.
#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/bake/sphere_map.hpp>
#include <brdfbake/bake/paraboloid_map.hpp>
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace brdfbake
