#include <brdfbake/core/error.hpp>
#include <brdfbake/core/named_values.hpp>
#include <brdfbake/maps/sphere_map.hpp>
#include <brdfbake/output/baked_output.hpp>
#include <brdfbake/output/preview.hpp>

#include <tbb/parallel_for.h>

#include <limits>

namespace brdfbake {

std::string_view toString(PreviewObject object) {
  switch (object) {
    case PreviewObject::Sphere:
      return "sphere";
    case PreviewObject::Torus:
      return "torus";
    case PreviewObject::Teapot:
      return "teapot";
  }
  return "sphere";
}

PreviewObject parsePreviewObject(std::string_view name) {
  return parseByName(name, std::array{PreviewObject::Sphere, PreviewObject::Torus, PreviewObject::Teapot},
                     "the preview object");
}
namespace {

// Grid of (rows + 1) x (columns + 1) vertices into two triangles per cell.
void addGrid(Mesh& mesh, int rows, int columns, const std::function<std::pair<Vec3, Vec3>(double, double)>& surface) {
  const int base = static_cast<int>(mesh.positions.size());
  for (int i = 0; i <= rows; ++i) {
    for (int j = 0; j <= columns; ++j) {
      const auto [p, n] = surface(static_cast<double>(i) / rows, static_cast<double>(j) / columns);
      mesh.positions.push_back(p);
      mesh.normals.push_back(n.normalized());
    }
  }
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < columns; ++j) {
      const int a = base + i * (columns + 1) + j, b = a + 1, c = a + columns + 1, d = c + 1;
      mesh.triangles.push_back({a, c, b});
      mesh.triangles.push_back({b, c, d});
    }
  }
}

Vec3 bezier(const std::array<Vec3, 4>& p, double t) {
  const double s = 1 - t;
  return s * s * s * p[0] + 3 * s * s * t * p[1] + 3 * s * t * t * p[2] + t * t * t * p[3];
}
Vec3 bezierTangent(const std::array<Vec3, 4>& p, double t) {
  const double s = 1 - t;
  return 3 * s * s * (p[1] - p[0]) + 6 * s * t * (p[2] - p[1]) + 3 * t * t * (p[3] - p[2]);
}

// A tube of varying radius along a cubic Bezier curve in the z = 0 plane.
void addTube(Mesh& mesh, const std::array<Vec3, 4>& curve, double r0, double r1, int segments) {
  addGrid(mesh, segments, segments, [&](double u, double v) {
    const Vec3 centre = bezier(curve, u), tangent = bezierTangent(curve, u).normalized();
    const Vec3 side = Vec3::UnitZ(), normalInPlane = side.cross(tangent).normalized();
    const double angle = v * kTwoPi;
    const Vec3 n = std::cos(angle) * normalInPlane + std::sin(angle) * side;
    return std::pair{Vec3(centre + (r0 + (r1 - r0) * u) * n), n};
  });
}

// Catmull-Rom through a profile (radius, height) for a body of revolution.
Vec2 profileAt(const std::vector<Vec2>& points, double t, Vec2* derivative) {
  const int segments = static_cast<int>(points.size()) - 1;
  const double f = std::clamp(t, 0.0, 1.0) * segments;
  const int i = std::min(static_cast<int>(f), segments - 1);
  const double u = f - i;
  const Vec2& p0 = points[std::max(i - 1, 0)];
  const Vec2& p1 = points[i];
  const Vec2& p2 = points[i + 1];
  const Vec2& p3 = points[std::min(i + 2, segments)];
  const Vec2 a = 2 * p1, b = p2 - p0, c = 2 * p0 - 5 * p1 + 4 * p2 - p3, d = -p0 + 3 * p1 - 3 * p2 + p3;
  if (derivative) *derivative = 0.5 * (b + 2 * c * u + 3 * d * u * u);
  return 0.5 * (a + b * u + c * u * u + d * u * u * u);
}

constexpr double kMajorRadius = 0.65, kMinorRadius = 0.35;  // torus

}  // namespace

Mesh makeSphereMesh(int segments) {
  Mesh mesh;
  addGrid(mesh, segments, 2 * segments, [](double u, double v) {
    const double theta = u * kPi, phi = v * kTwoPi;
    const Vec3 p(std::sin(theta) * std::sin(phi), std::cos(theta), std::sin(theta) * std::cos(phi));
    return std::pair{p, p};
  });
  return mesh;
}

Mesh makeTorusMesh(int segments) {
  Mesh mesh;
  // Axis tilted 60 degrees from y towards +z, so a viewer on +z sees through the hole.
  const Mat3 tilt = Eigen::AngleAxisd(radians(60.0), Vec3::UnitX()).toRotationMatrix();
  addGrid(mesh, segments, 2 * segments, [&](double u, double v) {
    const double a = u * kTwoPi, b = v * kTwoPi;
    const Vec3 ring(std::sin(b), 0, std::cos(b));
    const Vec3 n = std::cos(a) * ring + std::sin(a) * Vec3::UnitY();
    return std::pair{Vec3(tilt * (kMajorRadius * ring + kMinorRadius * n)), Vec3(tilt * n)};
  });
  return mesh;
}

Mesh makeTeapotMesh(int segments) {
  Mesh mesh;
  // Body and lid profile (radius, height), bottom centre to knob top.
  const std::vector<Vec2> profile{{0.0, 0.0},   {0.85, 0.0}, {1.2, 0.3},   {1.38, 0.75}, {1.3, 1.25}, {1.05, 1.55},
                                  {0.95, 1.63}, {0.45, 1.8}, {0.12, 1.86}, {0.2, 1.98},  {0.0, 2.06}};
  addGrid(mesh, 3 * segments, 2 * segments, [&](double u, double v) {
    Vec2 d;
    const Vec2 p = profileAt(profile, u, &d);
    const double phi = v * kTwoPi;
    const Vec3 radial(std::sin(phi), 0, std::cos(phi));
    // Outward normal of the profile curve, rotated about y.
    const Vec3 n = (d.y() * radial - d.x() * Vec3::UnitY());
    return std::pair{Vec3(p.x() * radial + Vec3(0, p.y(), 0)), n.norm() > 0 ? n : Vec3(radial)};
  });
  addTube(mesh, {Vec3(1.15, 0.6, 0), Vec3(1.95, 0.65, 0), Vec3(1.8, 1.4, 0), Vec3(2.4, 1.7, 0)}, 0.28, 0.1, segments);
  addTube(mesh, {Vec3(-1.2, 1.4, 0), Vec3(-2.3, 1.55, 0), Vec3(-2.15, 0.3, 0), Vec3(-1.3, 0.55, 0)}, 0.11, 0.11,
          segments);
  // Centre and fit into the unit sphere.
  Vec3 lo = mesh.positions[0], hi = lo;
  for (const Vec3& p : mesh.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Vec3 centre = 0.5 * (lo + hi);
  double radius = 0.0;
  for (const Vec3& p : mesh.positions) radius = std::max(radius, (p - centre).norm());
  for (Vec3& p : mesh.positions) p = (p - centre) / radius;
  return mesh;
}

Mesh makePreviewMesh(PreviewObject object, int segments) {
  switch (object) {
    case PreviewObject::Sphere:
      return makeSphereMesh(segments);
    case PreviewObject::Torus:
      return makeTorusMesh(segments);
    case PreviewObject::Teapot:
      return makeTeapotMesh(segments / 2 + 2);
  }
  return makeSphereMesh(segments);
}

void PreviewOptions::validate() const {
  require(resolution >= 8 && resolution <= 8192,
          "preview resolution must be in [8, 8192] pixels, got " + std::to_string(resolution));
  require(tessellation() >= 3 && tessellation() <= 1024,
          "segments must be in [3, 1024], got " + std::to_string(tessellation()));
  require(view.allFinite() && view.norm() > 0.0, "view must be a finite non-zero vector");
  require(std::isfinite(exposure), "exposure must be finite");
}

namespace {

// The object seen along -view: each covered pixel's triangle and barycentric weights, shaded by
// `shade(triangle, weights)` in parallel. Checks the options and, for eye-space maps, the view.
Image rasterise(const Mesh& mesh, const Vec3& view, const PreviewOptions& options,
                const std::function<Rgba(const std::array<int, 3>&, const Vec3&)>& shade) {
  // Screen basis: right, up, and the view vector towards the viewer.
  const Vec3 upHint = std::abs(view.y()) < 0.99 ? Vec3::UnitY() : Vec3(0, 0, view.y() > 0 ? -1 : 1);
  const Vec3 right = upHint.cross(view).normalized(), up = view.cross(right);
  const int n = options.resolution;
  const double extent = 1.08;  // screen half-width in object units
  auto toScreen = [&](const Vec3& p) {
    return Vec3((p.dot(right) / extent + 1) * 0.5 * n, (1 - p.dot(up) / extent) * 0.5 * n, p.dot(view));
  };
  std::vector<Vec3> screen(mesh.positions.size());
  for (std::size_t i = 0; i < screen.size(); ++i) screen[i] = toScreen(mesh.positions[i]);

  std::vector<double> depth(static_cast<std::size_t>(n) * n, -std::numeric_limits<double>::infinity());
  std::vector<int> triangleAt(depth.size(), -1);
  std::vector<Vec3> weightsAt(depth.size());
  // Rasterise (serially: the z-buffer is shared); shade afterwards in parallel.
  for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 &a = screen[tri[0]], &b = screen[tri[1]], &c = screen[tri[2]];
    const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    if (std::abs(area) < 1e-12) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
    const int x1 = std::min(n - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
    const int y1 = std::min(n - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double w0 = ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) / area;
        const double w1 = ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) / area;
        const double w2 = 1.0 - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        const double z = w0 * a.z() + w1 * b.z() + w2 * c.z();
        const std::size_t index = static_cast<std::size_t>(y) * n + x;
        if (z <= depth[index]) continue;
        depth[index] = z;
        triangleAt[index] = t;
        weightsAt[index] = Vec3(w0, w1, w2);
      }
    }
  }

  Image out(n, n, Rgba(options.background[0], options.background[1], options.background[2], 0.0));
  const double scale = std::exp2(options.exposure);
  tbb::parallel_for(0, n, [&](int y) {
    for (int x = 0; x < n; ++x) {
      const std::size_t index = static_cast<std::size_t>(y) * n + x;
      if (triangleAt[index] < 0) continue;
      const Rgba value = shade(mesh.triangles[triangleAt[index]], weightsAt[index]);
      out.set(x, y, Rgba(value[0] * scale, value[1] * scale, value[2] * scale, 1.0));
    }
  });
  return out;
}

// The options' view, checked: eye-space maps (sphere maps, profiles) hold one view, +z.
Vec3 checkedView(const PreviewOptions& options, bool eyeSpace) {
  options.validate();
  const Vec3 view = options.view.normalized();
  if (eyeSpace && (view - Vec3::UnitZ()).norm() > 1e-9) {
    throw Error(Error::Kind::InvalidArgument,
                "a sphere map (or a profile about the view) is valid only for the view it was "
                "made for: +z (eye space)");
  }
  return view;
}

Vec3 interpolatedNormal(const Mesh& mesh, const std::array<int, 3>& tri, const Vec3& w) {
  return (w[0] * mesh.normals[tri[0]] + w[1] * mesh.normals[tri[1]] + w[2] * mesh.normals[tri[2]]).normalized();
}

}  // namespace

Image renderPreview(const Image& map, const Parameterization& parameterization, const PreviewOptions& options) {
  const bool sphere = parameterization.kind() == ParameterizationKind::Sphere;
  const Vec3 view = checkedView(options, sphere);
  const Mesh mesh = makePreviewMesh(options.object, options.tessellation());
  // Per-vertex attributes for the fixed-function mode: sphere-map pixel coordinates, or r.
  std::vector<Vec3> vertexReflection(mesh.positions.size());
  std::vector<Vec2> vertexTexel(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    vertexReflection[i] = reflect(view, mesh.normals[i]);
    if (sphere) vertexTexel[i] = parameterization.getAddressFor(vertexReflection[i]).pixel;
  }
  return rasterise(mesh, view, options, [&](const std::array<int, 3>& tri, const Vec3& w) {
    if (options.perVertex && sphere) {
      const Vec2 texel = w[0] * vertexTexel[tri[0]] + w[1] * vertexTexel[tri[1]] + w[2] * vertexTexel[tri[2]];
      return sampleBilinear(map, texel, parameterization.region(0), false);
    }
    if (options.perVertex) {
      const Vec3 r =
          w[0] * vertexReflection[tri[0]] + w[1] * vertexReflection[tri[1]] + w[2] * vertexReflection[tri[2]];
      return sampleBilinear(map, parameterization, r.norm() > 0 ? r : Vec3(view));
    }
    return sampleBilinear(map, parameterization, reflect(view, interpolatedNormal(mesh, tri, w)));
  });
}

Image renderPreview(const BakedOutput& output, const PreviewOptions& options) {
  const MapFile* map = output.map();
  if (map && !output.indexedByNormal()) return renderPreview(map->image, *map->parameterization, options);
  if (options.perVertex) {
    throw Error(Error::Kind::InvalidArgument,
                std::string("per-vertex texture coordinates are for 2-D maps looked up at the "
                            "reflected direction; a ") +
                    std::string(toString(output.kind())) + (map ? " indexed by the normal" : "") +
                    " is shaded per pixel");
  }
  const Vec3 view = checkedView(options, output.eyeSpace());
  const Mesh mesh = makePreviewMesh(options.object, options.tessellation());
  return rasterise(mesh, view, options, [&](const std::array<int, 3>& tri, const Vec3& w) {
    return output.shade(interpolatedNormal(mesh, tri, w), view);
  });
}

}  // namespace brdfbake
