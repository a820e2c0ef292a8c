// Where lobes fail: exponents 0, 1e-6 and 1e6 (a lobe far narrower than a texel), the N.H
// conversion at N.H -> 1 and N.H <= 1/sqrt 2, lights of zero length or below the horizon.
#include <gtest/gtest.h>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/paraboloid_map.hpp>
#include <brdfbake/maps/sphere_map.hpp>

namespace brdfbake {
namespace {

MaterialMapFunction phong(double n, const Vec3& light) {
  return MaterialMapFunction(std::make_shared<PhongMaterial>(Rgb::Ones(), n), {{light, Rgb::Ones()}}, Vec3::UnitZ());
}

// ∫ over the sphere of the baked map (texel value x exact texel solid angle).
double mapIntegral(const Image& image, const Parameterization& map) {
  double sum = 0.0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) sum += image.at(x, y)[0] * map.texelSolidAngle(x, y);
  return sum;
}

// ∫ max(0, cos)^n dω = 2 pi / (n + 1).
double lobeIntegral(double n) { return kTwoPi / (n + 1.0); }

class Exponent : public ::testing::TestWithParam<double> {};

TEST_P(Exponent, KeepsTheLobesEnergyAndStaysFinite) {
  const double n = GetParam();
  for (auto kind : {ParameterizationKind::Sphere, ParameterizationKind::Paraboloid}) {
    const auto map = makeParameterization(kind, 64);
    const auto [image, summary] = bakeMap(*map, phong(n, Vec3(0.3, 0.2, 1).normalized()));
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) ASSERT_TRUE(allFinite(image.at(x, y)));
    EXPECT_NEAR(mapIntegral(image, *map), lobeIntegral(n), 2e-3 * lobeIntegral(n)) << toString(kind) << " n " << n;
    EXPECT_EQ(summary.deltaLobes, n >= 1e5 ? 1 : 0) << "n = " << n;
  }
}

// 0 is the hemisphere (documented: 0^0 only for c > 0), 1e-6 nearly so; 1e6 is a lobe about
// 0.001 rad wide, far below the sample spacing of a 64^2 map: deposited as a delta.
INSTANTIATE_TEST_SUITE_P(Extremes, Exponent, ::testing::Values(0.0, 1e-6, 1.0, 1e4, 1e5, 1e6));

TEST(Exponent, DeltaLobeLandsWhereTheLightPoints) {
  const SphereMap map(64);
  const Vec3 light = Vec3(0.3, 0.2, 1).normalized();
  const Image image = bake(map, phong(1e6, light));
  const MapAddress at = map.getAddressFor(light);
  const int x = static_cast<int>(at.pixel.x()), y = static_cast<int>(at.pixel.y());
  EXPECT_NEAR(image.at(x, y)[0] * map.texelSolidAngle(x, y), lobeIntegral(1e6), 1e-3 * lobeIntegral(1e6));
  EXPECT_EQ(image.at(x + 2, y)[0], 0.0);
}

TEST(Exponent, DeltaOnATexelCornerIsSharedByTheFourTexels) {
  // Light at the eye: the axis +z is the centre of an even-sized sphere map, a corner of four texels.
  const SphereMap map(32);
  const Image image = bake(map, phong(1e7, Vec3::UnitZ()));
  for (const auto& [x, y] : {std::pair{15, 15}, std::pair{16, 15}, std::pair{15, 16}, std::pair{16, 16}}) {
    EXPECT_NEAR(image.at(x, y)[0] * map.texelSolidAngle(x, y), lobeIntegral(1e7) / 4, 1e-3 * lobeIntegral(1e7));
  }
}

TEST(BlinnConversion, ExactPolicyIsFiniteAtTheLimits) {
  // N.H -> 1 at the highlight (0/0, limit 4) and N.H <= 1/sqrt 2 (no value: 0, as Phong is).
  const SphereMap map(128);
  const MaterialMapFunction blinn(std::make_shared<BlinnPhongMaterial>(Rgb::Ones(), 50.0, BlinnConversion::Exact),
                                  {{Vec3::UnitZ(), Rgb::Ones()}}, Vec3::UnitZ());
  const Image image = bake(map, blinn);
  const Image reference = bake(map, phong(50, Vec3::UnitZ()));
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) {
      ASSERT_TRUE(allFinite(image.at(x, y)));
      ASSERT_NEAR(image.at(x, y)[0], reference.at(x, y)[0], 1e-5);  // eye light: exactly Phong
    }
  // Beyond 90 degrees of reflection (N.H < 1/sqrt 2) the map is zero.
  EXPECT_EQ(sampleBilinear(image, map, Vec3(1, 0, -0.2).normalized())[0], 0.0);
}

TEST(Lights, ZeroLengthDirectionIsRefused) {
  EXPECT_THROW(phong(10, Vec3::Zero()), Error);
  EXPECT_THROW(phong(10, Vec3(NAN, 0, 1)), Error);
}

TEST(Lights, BelowTheHorizonLightsNoDiffuseAndNoBlinn) {
  // View +z; a light from below (-z side): no visible normal has n.l > 0 for l = -z, so diffuse and
  // Blinn-Phong give exactly 0; the Phong lobe (a function of r alone, documented) lights r near -z.
  const SphereMap map(64);
  const Vec3 below(0, 0, -1);
  const MaterialMapFunction diffuse(std::make_shared<PhongMaterial>(Rgb::Zero(), 1.0, Rgb::Ones()),
                                    {{below, Rgb::Ones()}}, Vec3::UnitZ());
  const MaterialMapFunction blinn(std::make_shared<BlinnPhongMaterial>(Rgb::Ones(), 10.0), {{below, Rgb::Ones()}},
                                  Vec3::UnitZ());
  const Image a = bake(map, diffuse), b = bake(map, blinn);
  double worst = 0.0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) worst = std::max({worst, double(a.at(x, y)[0]), double(b.at(x, y)[0])});
  EXPECT_LT(worst, 1e-6);
  const ParaboloidMap paraboloid(64);  // no rim singularity at -z
  EXPECT_GT(sampleBilinear(bake(paraboloid, phong(10, below)), paraboloid, Vec3(0.01, 0, -1))[0], 0.98);
}

}  // namespace
}  // namespace brdfbake
