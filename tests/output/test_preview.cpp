// The preview renderer: geometry, per-pixel lookups against the analytic reflection, and the
// per-vertex mode's interpolation error.
#include <gtest/gtest.h>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/sphere_map.hpp>
#include <brdfbake/output/preview.hpp>

namespace brdfbake {
namespace {

// The meshes' normals against the analytic surfaces: tests/output/test_preview_meshes.cpp.

TEST(Preview, ConstantMapShadesTheObjectUniformly) {
  const SphereMap map(16);
  const Image constant(16, 16, Rgba(0.25, 0.5, 0.75, 1));
  PreviewOptions options;
  options.resolution = 64;
  const Image image = renderPreview(constant, map, options);
  int covered = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      if (image.at(x, y)[3] == 0) continue;
      ++covered;
      EXPECT_NEAR(image.at(x, y)[1], 0.5, 1e-6);
    }
  // The unit sphere seen in a window of half-width 1.08: pi / (4 1.08^2) of the pixels.
  EXPECT_NEAR(covered / 4096.0, kPi / (4 * 1.08 * 1.08), 0.01);
}

TEST(Preview, PerPixelLookupMatchesTheReflectionOfTheSphereNormal) {
  // A Phong eye-light map on the unit sphere: at screen point (x, y) the normal is
  // (x, y, sqrt(1 - x^2 - y^2)), r_z = 2 n_z^2 - 1, and the value is max(0, r_z)^n.
  const SphereMap map(256);
  const Image phong = bake(map, MaterialMapFunction(std::make_shared<PhongMaterial>(Rgb::Ones(), 8.0),
                                                    {{Vec3::UnitZ(), Rgb::Ones()}}, Vec3::UnitZ()));
  PreviewOptions options;
  options.resolution = 128;
  options.segments = 96;
  const Image image = renderPreview(phong, map, options);
  double worst = 0.0;
  for (int y = 0; y < 128; y += 3) {
    for (int x = 0; x < 128; x += 3) {
      const double sx = ((x + 0.5) / 64 - 1) * 1.08, sy = (1 - (y + 0.5) / 64) * 1.08;
      const double rho2 = sx * sx + sy * sy;
      if (rho2 > 0.8) continue;  // away from the tessellated silhouette
      const double nz2 = 1 - rho2;
      worst = std::max(worst, std::abs(image.at(x, y)[0] - std::pow(std::max(0.0, 2 * nz2 - 1), 8)));
    }
  }
  EXPECT_LT(worst, 0.02);
}

TEST(Preview, PerVertexInterpolationErrsMostWhereTheMapIsCoarse) {
  // Fixed-function sphere mapping interpolates (s, t) linearly: with 8 segments the result
  // departs from the exact per-pixel lookup, and more with fewer segments.
  const SphereMap map(128);
  const Image phong = bake(map, MaterialMapFunction(std::make_shared<PhongMaterial>(Rgb::Ones(), 30.0),
                                                    {{Vec3(0.5, 0.5, 1).normalized(), Rgb::Ones()}}, Vec3::UnitZ()));
  auto difference = [&](int segments) {
    PreviewOptions exact, vertex;
    exact.resolution = vertex.resolution = 96;
    exact.segments = 96;
    vertex.segments = segments;
    vertex.perVertex = true;
    const Image a = renderPreview(phong, map, exact), b = renderPreview(phong, map, vertex);
    double sum = 0.0;
    for (int y = 0; y < 96; ++y)
      for (int x = 0; x < 96; ++x)
        if (a.at(x, y)[3] > 0 && b.at(x, y)[3] > 0) sum += std::abs(a.at(x, y)[0] - b.at(x, y)[0]);
    return sum;
  };
  const double coarse = difference(6), fine = difference(48);
  EXPECT_GT(coarse, 3 * fine);
}

TEST(Preview, SphereMapsRefuseAnotherView) {
  const SphereMap map(8);
  PreviewOptions options;
  options.view = Vec3(1, 0, 0);
  EXPECT_THROW(renderPreview(Image(8, 8), map, options), Error);
  options.view = Vec3::UnitZ();
  options.resolution = 2;
  EXPECT_THROW(renderPreview(Image(8, 8), map, options), Error);
}

}  // namespace
}  // namespace brdfbake
