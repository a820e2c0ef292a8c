// The preview's meshes against their analytic surfaces, and a preview of a general map from a
// general view against the map's function at the analytic reflected direction.
#include <gtest/gtest.h>
#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/output/preview.hpp>

#include <cmath>

namespace brdfbake {
namespace {

TEST(PreviewMeshes, SphereAndTorusNormalsAreTheAnalyticSurfaceNormals) {
  // The unit sphere: every vertex on it, its normal the position.
  const Mesh sphere = makeSphereMesh(12);
  ASSERT_EQ(sphere.positions.size(), sphere.normals.size());
  ASSERT_EQ(sphere.triangles.size(), 2u * 12 * 24);
  for (std::size_t i = 0; i < sphere.positions.size(); ++i) {
    EXPECT_NEAR(sphere.positions[i].norm(), 1.0, 1e-12);
    EXPECT_LT((sphere.normals[i] - sphere.positions[i]).norm(), 1e-12);
  }
  // The torus of radii R = 0.65 and r = 0.35 about the y axis tilted 60 degrees towards +z, so
  // about a = (0, cos 60, sin 60): the nearest point of the centre circle to p is
  // c = R (p - (p.a) a) / |p - (p.a) a|; p lies at distance r from it, with normal (p - c) / r.
  const Vec3 a(0.0, std::cos(kPi / 3), std::sin(kPi / 3));
  for (int segments : {8, 33}) {
    const Mesh torus = makeTorusMesh(segments);
    ASSERT_EQ(torus.triangles.size(), 2u * segments * 2 * segments);
    for (std::size_t i = 0; i < torus.positions.size(); ++i) {
      const Vec3& p = torus.positions[i];
      const Vec3 radial = p - p.dot(a) * a, c = 0.65 * radial.normalized();
      EXPECT_NEAR((p - c).norm(), 0.35, 1e-12) << i;
      EXPECT_LT((torus.normals[i] - (p - c) / 0.35).norm(), 1e-12) << i;
    }
  }
  // makePreviewMesh gives the same objects.
  EXPECT_EQ(makePreviewMesh(PreviewObject::Torus, 8).positions, makeTorusMesh(8).positions);
}

// The largest angle (degrees) between a vertex normal and the normal of a triangle through it,
// over the triangles of positive area; `consistent` says whether every vertex normal lies on the
// same side of its triangles (as their winding orients them).
double worstNormalAgainstFaces(const Mesh& mesh, bool& consistent) {
  double worst = 0.0;
  int positive = 0, negative = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 face = (mesh.positions[t[1]] - mesh.positions[t[0]]).cross(mesh.positions[t[2]] - mesh.positions[t[0]]);
    if (face.norm() < 1e-12) continue;
    for (int v : t) {
      const double c = face.normalized().dot(mesh.normals[v]);
      (c > 0 ? positive : negative)++;
      worst = std::max(worst, std::acos(std::min(1.0, std::abs(c))) * 180.0 / kPi);
    }
  }
  consistent = positive == 0 || negative == 0;
  return worst;
}

TEST(PreviewMeshes, TeapotNormalsAreThoseOfTheSurfaceItsTrianglesMake) {
  // The teapot's surfaces are splines, so its normals are checked against the triangles: each
  // vertex normal is a unit vector on the same side of every triangle through it, and departs
  // from the triangles' planes by an angle that halves as the tessellation doubles (the tangent
  // plane's first-order error), with every vertex inside the unit sphere it was fitted into.
  double previous = 0.0;
  for (int segments : {16, 32, 64}) {
    const Mesh teapot = makeTeapotMesh(segments);
    double radius = 0.0;
    for (std::size_t i = 0; i < teapot.positions.size(); ++i) {
      EXPECT_NEAR(teapot.normals[i].norm(), 1.0, 1e-12);
      radius = std::max(radius, teapot.positions[i].norm());
    }
    EXPECT_LE(radius, 1.0 + 1e-12);
    EXPECT_GT(radius, 0.9);  // fitted, not shrunk
    bool consistent = false;
    const double worst = worstNormalAgainstFaces(teapot, consistent);
    EXPECT_TRUE(consistent) << segments;
    if (previous > 0.0) {
      EXPECT_LT(worst, 0.6 * previous) << segments << ": " << worst << " degrees after " << previous;
    }
    previous = worst;
  }
}

TEST(Preview, APixelShowsTheMapAtTheReflectionOfTheAnalyticNormal) {
  // A cube map of f(d) = 0.5 + 0.5 d (d the texel's direction), previewed on the sphere from the
  // view v = normalize(1, 0.5, 0.3). The renderer's screen (output/preview.cpp): right =
  // normalize(y x v), up = v x right, half-width 1.08 object units, orthographic. At screen point
  // (x, y) the unit sphere's normal is x right + y up + sqrt(1 - x^2 - y^2) v, the reflected
  // direction r = 2 (n.v) n - v, and the pixel must show f(r): within 5e-3, the bilinear
  // interpolation of f between texel centres (64 per face: 1e-3) plus the normal's error between
  // the mesh's vertices (96 segments: below 1e-3 rad).
  const CubeMap map(64);
  Image image(map.width(), map.height(), Rgba::Zero());
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x)
      if (const auto d = map.getDirectionFor(Vec2(x + 0.5, y + 0.5))) {
        const Vec3 u = d->normalized();
        image.set(x, y, Rgba(0.5 + 0.5 * u.x(), 0.5 + 0.5 * u.y(), 0.5 + 0.5 * u.z(), 1.0));
      }
  PreviewOptions options;
  options.resolution = 96;
  options.segments = 96;
  options.view = Vec3(1.0, 0.5, 0.3).normalized();
  const Image preview = renderPreview(image, map, options);
  const Vec3 v = options.view, right = Vec3::UnitY().cross(v).normalized(), up = v.cross(right);
  int checked = 0;
  for (int py = 0; py < 96; py += 2) {
    for (int px = 0; px < 96; px += 2) {
      const double sx = ((px + 0.5) / 48.0 - 1.0) * 1.08, sy = (1.0 - (py + 0.5) / 48.0) * 1.08;
      if (sx * sx + sy * sy > 0.8) continue;  // away from the tessellated silhouette
      const Vec3 n = sx * right + sy * up + std::sqrt(1.0 - sx * sx - sy * sy) * v;
      const Vec3 r = 2.0 * n.dot(v) * n - v;
      const Eigen::Array3d expected = 0.5 + 0.5 * r.array();
      EXPECT_EQ(preview.at(px, py)[3], 1.0f);
      EXPECT_LT((preview.at(px, py).head<3>().cast<double>() - expected).abs().maxCoeff(), 5e-3)
          << "pixel (" << px << ", " << py << ")";
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
  // Outside the object: the background, alpha 0.
  EXPECT_EQ(preview.at(0, 0)[3], 0.0f);
  EXPECT_LT((preview.at(0, 0).head<3>() - options.background).abs().maxCoeff(), 1e-6);
}

}  // namespace
}  // namespace brdfbake
