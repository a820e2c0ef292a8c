// Where parameterizations and the baker fail: the sphere-map rim, resolutions 1 and 16384.
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/bake/sphere_map.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/core/error.hpp>
#include <gtest/gtest.h>

namespace brdfbake {
namespace {

MaterialMapFunction phong(double n, const Vec3& light, const Rgb& diffuse = Rgb::Zero()) {
  return MaterialMapFunction(std::make_shared<PhongMaterial>(Rgb::Ones(), n, diffuse), {{light, Rgb::Ones()}}, Vec3::UnitZ());
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
  for (auto kind : {ParameterizationKind::Sphere, ParameterizationKind::Paraboloid, ParameterizationKind::Cube,
                    ParameterizationKind::LatLong}) {
    const auto map = makeParameterization(kind, 1);
    const Image image = bake(*map, phong(20, Vec3(1, 2, 3).normalized()));
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) EXPECT_TRUE(allFinite(image.at(x, y))) << toString(kind);
    EXPECT_TRUE(allFinite(sampleBilinear(image, *map, Vec3(0, 0, 1))));
  }
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
  // Allowed, the limit no longer applies (checked without baking 4 GiB: a smaller limit).
  BakeOptions options;
  options.maxTexels = 100;
  EXPECT_THROW(bake(SphereMap(11), phong(5, Vec3::UnitZ()), options), Error);
  options.allowLarge = true;
  EXPECT_NO_THROW(bake(SphereMap(11), phong(5, Vec3::UnitZ()), options));
}

}  // namespace
}  // namespace brdfbake
