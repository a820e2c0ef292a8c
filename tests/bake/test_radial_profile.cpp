// 1-D radial profiles: the coordinate is the sphere-map radius, texels are ring means, lookups
// follow the exact function, symmetry is detected only where it holds, and auto selection picks a
// profile when it is the cheapest way to meet the target.
#include <gtest/gtest.h>
#include <brdfbake/bake/auto_config.hpp>
#include <brdfbake/bake/radial_profile.hpp>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/npr.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/sphere_map.hpp>

#include <random>

namespace brdfbake {
namespace {

std::shared_ptr<const Material> copperReflectance() {
  CookTorranceParams copper;
  copper.mode = CookTorranceMode::Reflectance;
  copper.fresnel = FresnelTerm::fromF0(Rgb(0.955, 0.638, 0.538));
  copper.roughness = 0.4;
  return std::make_shared<CookTorranceMaterial>(copper);
}

// f(d) = d . axis = 1 - 2 u^2: linear in u^2, so a ring's solid-angle mean is known exactly.
class CosineToAxis final : public MapFunction {
 public:
  explicit CosineToAxis(const Vec3& axis) : axis_(axis.normalized()) {}
  Rgb evaluate(const Vec3& d) const override { return Rgb::Constant(d.dot(axis_)); }
  std::optional<Vec3> symmetryAxis() const override { return axis_; }

 private:
  Vec3 axis_;
};

TEST(RadialProfile, CoordinateIsTheSphereMapRadius) {
  const SphereMap sphere(512);
  const RadialProfile profile(Vec3::UnitZ(), {Rgb::Zero()});
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  for (int i = 0; i < 1000; ++i) {
    const Vec3 d = Vec3(g(rng), g(rng), g(rng)).normalized();
    if (d.z() < -0.999) continue;  // the rim, the sphere map's singular set
    const Vec2 pixel = sphere.getAddressFor(d).pixel;
    const double s = pixel.x() / 512.0, t = 1.0 - pixel.y() / 512.0;
    EXPECT_NEAR(profile.coordinateFor(d), std::hypot(2 * s - 1, 2 * t - 1), 1e-12);
    // directionFor inverts coordinateFor at any azimuth.
    const double u = profile.coordinateFor(d);
    EXPECT_NEAR(profile.coordinateFor(profile.directionFor(u, 0.37 * i)), u, 1e-12);
  }
}

TEST(RadialProfile, TexelsAreSolidAngleMeansOfTheirRings) {
  for (const Vec3& axis : {Vec3(0, 0, 1), Vec3(1, 2, -0.5)}) {
    const CosineToAxis function(axis);
    for (int samples : {1, 7}) {
      const RadialProfile profile = bakeRadialProfile(function, axis, 10, samples);
      for (int i = 0; i < 10; ++i) {
        const double a = i / 10.0, b = (i + 1) / 10.0;
        EXPECT_NEAR(profile.texels()[static_cast<std::size_t>(i)][0], 1.0 - (a * a + b * b), 1e-12) << i;
      }
    }
  }
}

TEST(RadialProfile, LookupsFollowTheExactFunctionAndConvergeSecondOrder) {
  // Phong lit from the eye, n = 40: smooth, so linear interpolation converges as 1/N^2.
  const MaterialMapFunction phong(std::make_shared<PhongMaterial>(Rgb::Ones(), 40.0), {{Vec3::UnitZ(), Rgb::Ones()}},
                                  Vec3::UnitZ());
  ASSERT_TRUE(phong.symmetryAxis());
  ErrorOptions options;
  options.samples = 5000;
  double previous = 0.0;
  for (int n : {32, 64, 128, 256}) {
    const RadialProfile profile = bakeRadialProfile(phong, Vec3::UnitZ(), n, 1);
    const ErrorStats stats = measureProfileError(profile, phong, options);
    EXPECT_TRUE(std::isfinite(stats.rms) && std::isfinite(stats.visibleRms));
    if (previous > 0.0) {
      EXPECT_LT(stats.visibleRms, previous / 2.5) << n;  // ~4x per doubling
    }
    previous = stats.visibleRms;
  }
  EXPECT_LT(previous, 2e-4);
}

TEST(RadialProfile, SymmetryIsDeclaredOnlyWhereItHolds) {
  const Vec3 light = Vec3(1, 1, 1).normalized();
  auto phong = std::make_shared<PhongMaterial>(Rgb::Ones(), 40.0);
  EXPECT_TRUE((MaterialMapFunction(phong, {{Vec3::UnitZ(), Rgb::Ones()}}, Vec3::UnitZ())
                   .symmetryAxis()
                   ->isApprox(Vec3::UnitZ())));
  EXPECT_TRUE((MaterialMapFunction(phong, {{light, Rgb::Ones()}}, Vec3::UnitZ()).symmetryAxis()->isApprox(light)));
  EXPECT_FALSE(
      MaterialMapFunction(phong, {{light, Rgb::Ones()}, {Vec3::UnitZ(), Rgb::Ones()}}, Vec3::UnitZ()).symmetryAxis());
  EXPECT_TRUE(MaterialMapFunction(copperReflectance(), {}, Vec3::UnitZ()).symmetryAxis());
  const ColorGradient gradient({{0.0, Rgb::Ones()}, {60.0, Rgb(1, 0, 0)}, {85.0, Rgb(0, 0, 1)}}, 2.0);
  EXPECT_TRUE(MaterialMapFunction(std::make_shared<ColorgramMaterial>(gradient, 0.0, ColorgramBlend::Replace), {},
                                  Vec3::UnitZ())
                  .symmetryAxis());
  EXPECT_FALSE(MaterialMapFunction(std::make_shared<ColorgramMaterial>(gradient, 20.0, ColorgramBlend::Replace), {},
                                   Vec3::UnitZ())
                   .symmetryAxis());
  // The claim checked numerically: a symmetric function is equal at equal angles to its axis.
  const MaterialMapFunction copper(copperReflectance(), {}, Vec3::UnitZ());
  const RadialProfile frame(Vec3::UnitZ(), {Rgb::Zero()});
  for (double u : {0.1, 0.5, 0.9}) {
    EXPECT_TRUE(
        copper.evaluate(frame.directionFor(u, 0.0)).isApprox(copper.evaluate(frame.directionFor(u, 2.0)), 1e-12));
  }
}

TEST(RadialProfile, AutoPicksAProfileWhenItIsTheCheapestWayToMeetTheTarget) {
  const MaterialMapFunction copper(copperReflectance(), {}, Vec3::UnitZ());
  AutoOptions options;
  options.parameterizations = {ParameterizationKind::Sphere};
  options.resolutions = {16, 32, 64, 128, 256, 512, 1024};
  options.samplesPerTexel = {1, 4};
  options.maxError = 0.002;
  options.error.samples = 4000;
  const AutoResult map = chooseConfiguration(copper, options);
  ASSERT_FALSE(map.chosen.radialProfile);
  options.allowRadialProfile = true;
  const AutoResult profile = chooseConfiguration(copper, options);
  ASSERT_TRUE(profile.chosen.radialProfile) << profile.chosen.describe();
  ASSERT_TRUE(profile.radialProfile.has_value());
  EXPECT_EQ(profile.image.width(), profile.chosen.resolution);
  EXPECT_EQ(profile.image.height(), 1);
  EXPECT_EQ(profile.image.metadata["parameterization"], "profile");
  EXPECT_LE(profile.error, options.maxError);
  // Measured again with other directions, it still meets the target (within sampling noise).
  ErrorOptions other = options.error;
  other.seed = 99;
  EXPECT_LE(measureProfileError(*profile.radialProfile, copper, other).visibleRms, 1.2 * options.maxError);
  // The next cheaper profile misses it; the sphere map that meets it costs far more.
  int cheaperProfiles = 0;
  for (const auto& [configuration, error] : profile.rejected) {
    EXPECT_GT(error, options.maxError) << configuration.describe();
    cheaperProfiles += configuration.radialProfile ? 1 : 0;
  }
  EXPECT_GT(cheaperProfiles, 0) << "the chosen profile was the cheapest candidate: the test would prove nothing";
  EXPECT_LT(profile.chosen.cost() * 16, map.chosen.cost())
      << profile.chosen.describe() << " vs " << map.chosen.describe();
}

TEST(RadialProfile, BadArgumentsAreRefused) {
  const CosineToAxis function(Vec3::UnitZ());
  EXPECT_THROW(bakeRadialProfile(function, Vec3::UnitZ(), 0, 1), Error);
  EXPECT_THROW(bakeRadialProfile(function, Vec3::UnitZ(), 8, 0), Error);
  EXPECT_THROW(bakeRadialProfile(function, Vec3::Zero(), 8, 1), Error);
  EXPECT_THROW(RadialProfile(Vec3::UnitZ(), {}), Error);
  EXPECT_THROW(RadialProfile(Vec3::UnitZ(), {Rgb::Constant(std::nan(""))}), Error);
  // Lookups clamp at both ends and never produce NaN, even at -axis.
  const RadialProfile profile = bakeRadialProfile(function, Vec3::UnitZ(), 8, 1);
  EXPECT_TRUE(profile.lookup(-Vec3::UnitZ()).allFinite());
  EXPECT_NEAR(profile.lookup(Vec3::UnitZ())[0], profile.texels().front()[0], 1e-15);
  EXPECT_NEAR(profile.lookup(-Vec3::UnitZ())[0], profile.texels().back()[0], 1e-15);
}

}  // namespace
}  // namespace brdfbake
