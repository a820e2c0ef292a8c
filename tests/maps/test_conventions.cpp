// Pins the conventions of docs/conventions.md: frames, image orientation, texel centres, layouts.
#include <gtest/gtest.h>
#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/maps/image.hpp>
#include <brdfbake/maps/latlong_map.hpp>
#include <brdfbake/maps/paraboloid_map.hpp>
#include <brdfbake/maps/sphere_map.hpp>

namespace brdfbake {
namespace {

TEST(Conventions, SphereMapCentreIsTheViewerAndUpIsTheTopRow) {
  const SphereMap map(256);
  // +z (towards the viewer) is the image centre.
  EXPECT_NEAR((map.getAddressFor(Vec3::UnitZ()).pixel - Vec2(128, 128)).norm(), 0.0, 1e-12);
  // +y (up) lands in the upper half (smaller row), +x in the right half: a photograph of a mirror ball.
  EXPECT_LT(map.getAddressFor(Vec3::UnitY()).pixel.y(), 128);
  EXPECT_GT(map.getAddressFor(Vec3::UnitX()).pixel.x(), 128);
  // Texel centres are at (i + 0.5): texel (0, 0)'s centre is the top-left of the disc's square.
  const Vec3 topLeft = *map.getDirectionFor(Vec2(0.5, 0.5));
  EXPECT_NEAR((topLeft - Vec3(0, 0, -1)).norm(), 0.0, 1e-7);  // outside the disc: the rim direction
  // ... pulled just inside the rim at its own azimuth: up-left of the centre.
  EXPECT_LT(topLeft.x(), 0.0);
  EXPECT_GT(topLeft.y(), 0.0);
  const Vec3 nearTop = *map.getDirectionFor(Vec2(128, 0.5));
  EXPECT_GT(nearTop.y(), 0.0);
}

TEST(Conventions, ParaboloidFrontIsLeftAndUpIsTop) {
  const ParaboloidMap map(100);
  EXPECT_NEAR((map.getAddressFor(Vec3::UnitZ()).pixel - Vec2(50, 50)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((map.getAddressFor(-Vec3::UnitZ()).pixel - Vec2(150, 50)).norm(), 0.0, 1e-12);
  EXPECT_LT(map.getAddressFor(Vec3(0, 1, 0.5)).pixel.y(), 50);
  EXPECT_GT(map.getAddressFor(Vec3(1, 0, 0.5)).pixel.x(), 50);
}

TEST(Conventions, CubeCrossLayoutAndFaceOrientation) {
  const CubeMap map(10);
  // Face centres in the cross: +Y top, -X +Z +X -Z middle row, -Y bottom.
  EXPECT_NEAR((map.getAddressFor(Vec3::UnitY()).pixel - Vec2(15, 5)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((map.getAddressFor(-Vec3::UnitX()).pixel - Vec2(5, 15)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((map.getAddressFor(Vec3::UnitZ()).pixel - Vec2(15, 15)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((map.getAddressFor(Vec3::UnitX()).pixel - Vec2(25, 15)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((map.getAddressFor(-Vec3::UnitZ()).pixel - Vec2(35, 15)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((map.getAddressFor(-Vec3::UnitY()).pixel - Vec2(15, 25)).norm(), 0.0, 1e-12);
  // Side faces have +y up (towards row 0).
  EXPECT_LT(map.getAddressFor(Vec3(0, 0.5, 1)).pixel.y(), 15);
  EXPECT_LT(map.getAddressFor(Vec3(1, 0.5, 0)).pixel.y(), 15);
}

TEST(Conventions, LatLongCentreLooksDownMinusZWithYUp) {
  const LatLongMap map(100);
  EXPECT_NEAR((map.getAddressFor(-Vec3::UnitZ()).pixel - Vec2(100, 50)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(map.getAddressFor(Vec3::UnitY()).pixel.y(), 0.0, 1e-12);
  EXPECT_NEAR(map.getAddressFor(-Vec3::UnitY()).pixel.y(), 100.0, 1e-12);
  EXPECT_NEAR(map.getAddressFor(Vec3::UnitX()).pixel.x(), 150.0, 1e-12);  // +x right of centre
}

TEST(Conventions, BilinearLookupHitsTexelCentresExactly) {
  Image image(4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) image.set(x, y, Rgba(x, y, 10 * x + y, 1));
  const TexelRect all{0, 0, 4, 4};
  EXPECT_NEAR(sampleBilinear(image, Vec2(2.5, 1.5), all, false)[2], 21.0, 1e-6);
  EXPECT_NEAR(sampleBilinear(image, Vec2(2.0, 1.5), all, false)[0], 1.5, 1e-6);  // between columns 1 and 2
  EXPECT_NEAR(sampleBilinear(image, Vec2(0.1, 1.5), all, false)[0], 0.0, 1e-6);  // clamped at the edge
  EXPECT_NEAR(sampleBilinear(image, Vec2(0.0, 1.5), all, true)[0], 1.5, 1e-6);   // wrapped: columns 3 and 0
}

// An N-texel 1-D texture holds texel i at s = (i + 0.5) / N (the Fresnel table's coordinate): a
// ramp v_i = i reads i at the texel centres, i + 1/4 a quarter texel further, and its end values
// beyond the first and last centres.
TEST(Conventions, LinearLookupIn1dHitsTexelCentres) {
  std::vector<Rgb> ramp;
  for (int i = 0; i < 8; ++i) ramp.push_back(Rgb::Constant(i));
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(sampleLinear1d(ramp, (i + 0.5) / 8)[0], i, 1e-12) << i;
  for (int i = 0; i < 7; ++i) EXPECT_NEAR(sampleLinear1d(ramp, (i + 0.75) / 8)[0], i + 0.25, 1e-12) << i;
  EXPECT_EQ(sampleLinear1d(ramp, 0.0)[0], 0.0);
  EXPECT_EQ(sampleLinear1d(ramp, 1.0)[0], 7.0);
}

}  // namespace
}  // namespace brdfbake
