// Where parameterizations and the baker fail: the sphere-map rim, resolutions 1 and 16384.
#include <gtest/gtest.h>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/sphere_map.hpp>

#include "test_support.hpp"

namespace brdfbake {
namespace {

MaterialMapFunction phong(double n, const Vec3& light, const Rgb& diffuse = Rgb::Zero()) {
  return MaterialMapFunction(std::make_shared<PhongMaterial>(Rgb::Ones(), n, diffuse), {{light, Rgb::Ones()}},
                             Vec3::UnitZ());
}

// The rim circle is the single direction -z. Documented: forward maps -z and anything within
// rounding of it onto the rim circle (never NaN); a lookup there returns the rim texels' value.
TEST(SphereMapRim, MinusZAndItsNeighbourhoodLandOnTheRim) {
  const SphereMap map(128);
  const Image image = bake(map, phong(10, Vec3(0, 0.3, -1).normalized(), Rgb(0.2, 0.2, 0.2)));
  for (const Vec3& r : {Vec3(0, 0, -1), Vec3(1e-12, 0, -1), Vec3(0, 1e-12, -1), Vec3(-1e-12, -1e-12, -1),
                        Vec3(3e-13, 1e-13, -1), Vec3(0, 0, -1e300)}) {
    const MapAddress a = map.getAddressFor(r);
    ASSERT_TRUE(a.pixel.allFinite()) << r.transpose();
    EXPECT_NEAR((a.pixel - Vec2(64, 64)).norm(), 64.0, 1e-6) << r.transpose();
    EXPECT_TRUE(allFinite(sampleBilinear(image, map, r))) << r.transpose();
  }
}

TEST(SphereMapRim, TexelsOutsideTheDiscHoldTheNearestRimValue) {
  // A light behind the viewer (near -z): outside corners carry the rim value on (zero coverage),
  // so bilinear lookups near the rim are not darkened by empty texels.
  const SphereMap map(64);
  const Vec3 light = Vec3(0.05, 0, -1).normalized();
  const Image image = bake(map, phong(4, light));
  const double rimValue = std::pow(Vec3(0, 0, -1).dot(light), 4);
  EXPECT_NEAR(image.at(0, 0)[0], rimValue, 1e-3);
  EXPECT_EQ(image.at(0, 0)[3], 0.0);
  // Documented failure: a texel at the rim of an N^2 map spans up to ~4/sqrt(N) rad of directions
  // (anisotropy 1/cos^2(theta/2) diverges), so a lookup near -z returns the footprint mean over
  // that range: here between cos^4(0.5) and the peak, not the point value.
  const double nearRim = sampleBilinear(image, map, Vec3(0.02, 0.01, -1))[0];
  EXPECT_LT(nearRim, rimValue);
  EXPECT_GT(nearRim, std::pow(std::cos(4.0 / std::sqrt(64.0)), 4));
}

TEST(Resolution, OneTexelMapsAreValid) {
  // Maps of one texel per side. A lobe narrower than the sample spacing is deposited with its
  // exact energy, so the map's integral (texel value x exact texel solid angle, summed) is
  // ∫ max(0, r.l)^n dω = 2 pi / (n + 1), as Exponent.KeepsTheLobesEnergyAndStaysFinite checks at
  // 64 texels: n = 1000 in every map, n = 20 in all but the cube (16 samples on a 1-texel face
  // are 21 degrees apart, less than the lobe's 29 degree width, so it is sampled there; below).
  const Vec3 light = Vec3(1, 2, 3).normalized();
  for (auto kind : {ParameterizationKind::Sphere, ParameterizationKind::Paraboloid, ParameterizationKind::Cube,
                    ParameterizationKind::LatLong}) {
    const auto map = makeParameterization(kind, 1);
    for (double n : {20.0, 1000.0}) {
      const auto [image, summary] = bakeMap(*map, phong(n, light));
      double integral = 0.0;
      for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) {
          EXPECT_TRUE(allFinite(image.at(x, y))) << toString(kind);
          integral += image.at(x, y)[0] * map->texelSolidAngle(x, y);
        }
      EXPECT_TRUE(allFinite(sampleBilinear(image, *map, Vec3(0, 0, 1))));
      if (kind == ParameterizationKind::Cube && n == 20.0) {
        EXPECT_EQ(summary.deltaLobes, 0);
        continue;
      }
      EXPECT_EQ(summary.deltaLobes, 1) << toString(kind) << " n " << n;
      EXPECT_NEAR(integral, kTwoPi / (n + 1.0), 1e-5 * kTwoPi / (n + 1.0)) << toString(kind) << " n " << n;
    }
  }
  // The sampled case: each face texel of a one-texel cube holds the mean of the lobe over its
  // footprint in texture space (baker.hpp), here with 64 x 64 samples against a 256 x 256 midpoint
  // sum in the test. (Not the solid-angle mean: a face's centre covers 5.2 times the solid angle of
  // its corners, so at one texel per face this map's integral is 10 % above the lobe's energy.)
  const auto cube = makeParameterization(ParameterizationKind::Cube, 1);
  BakeOptions dense;
  dense.samplesPerTexel = 4096;
  const Image image = bake(*cube, phong(20.0, light), dense);
  int faces = 0;
  double peak = 0.0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      if (cube->texelCoverage(x, y) < 1.0) continue;
      ++faces;
      double sum = 0.0;
      for (int j = 0; j < 256; ++j)
        for (int i = 0; i < 256; ++i) {
          const Vec3 d = *cube->getDirectionFor(Vec2(x + (i + 0.5) / 256, y + (j + 0.5) / 256));
          sum += std::pow(std::max(0.0, d.normalized().dot(light)), 20.0);
        }
      const double expected = sum / (256.0 * 256.0);
      peak = std::max(peak, expected);
      // 1e-6: the tolerance of the baker's lobe table, relative to the lobe's peak of 1.
      EXPECT_NEAR(image.at(x, y)[0], expected, 1e-3 * expected + 1e-6) << "cube texel " << x << "," << y;
    }
  EXPECT_EQ(faces, 6);
  EXPECT_GT(peak, 0.1);
}

TEST(Resolution, HugeMapsAreRefusedWithAMemoryMessageUnlessAllowed) {
  const SphereMap map(16384);
  try {
    bake(map, phong(5, Vec3::UnitZ()));
    FAIL() << "expected Error(Resource)";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::Resource);
    const std::string message = e.what();
    EXPECT_NE(message.find("16384 x 16384"), std::string::npos) << message;
    EXPECT_NE(message.find("4 GiB"), std::string::npos) << message;
    EXPECT_NE(message.find("--allow-large"), std::string::npos) << message;
  }
  // Allowed, the texel limit no longer applies; the memory budget still does (checked without baking 4 GiB).
  const test::EnvironmentVariable budget("BRDFBAKE_MEMORY_LIMIT", "64G");
  EXPECT_NO_THROW(Context({.allowLarge = true}).requireImageSize(map.width(), map.height()));
  const test::EnvironmentVariable small("BRDFBAKE_MEMORY_LIMIT", "1G");
  EXPECT_THROW(Context({.allowLarge = true}).requireImageSize(map.width(), map.height()), Error);
}

}  // namespace
}  // namespace brdfbake
