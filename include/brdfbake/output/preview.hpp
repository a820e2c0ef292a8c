#pragma once
/// @file
/// Rendering an object shaded by a map, to see what a renderer would show (`brdfbake preview`).

#include <brdfbake/maps/image.hpp>

#include <array>
#include <optional>
#include <string_view>
#include <vector>

namespace brdfbake {

/// A triangle mesh with per-vertex unit normals, in the map's frame.
struct Mesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;
  std::vector<std::array<int, 3>> triangles;
};

enum class PreviewObject { Sphere, Torus, Teapot };
/// "sphere", "torus", "teapot".
std::string_view toString(PreviewObject object);
/// Inverse of toString; throws Error(InvalidArgument) listing the names.
PreviewObject parsePreviewObject(std::string_view name);

/// Unit sphere tessellated into `segments` x 2 `segments` quads.
Mesh makeSphereMesh(int segments);
/// Torus of radii 0.65 and 0.35 about the y axis tilted 60 degrees towards +z.
Mesh makeTorusMesh(int segments);
/// A procedural teapot (body and lid of revolution about y, spout towards +x, handle towards -x),
/// fitted into the unit sphere. Drawn for brdfbake, not Newell's patch data.
Mesh makeTeapotMesh(int segments);
Mesh makePreviewMesh(PreviewObject object, int segments);

struct PreviewOptions {
  PreviewObject object = PreviewObject::Sphere;
  int resolution = 512;       ///< output is resolution x resolution pixels
  Vec3 view = Vec3::UnitZ();  ///< towards the viewer, in the map frame (sphere maps: +z only)
  /// Per-vertex mode: texture coordinates (sphere maps) or reflected vectors (other maps) are
  /// computed at the vertices and interpolated linearly across each triangle, as fixed-function
  /// hardware did; otherwise the normal is interpolated and the map looked up exactly per pixel.
  bool perVertex = false;
  /// Tessellation (per-vertex artefacts grow as it drops), in [3, 1024]; default 64, or 16 in
  /// per-vertex mode (coarse enough to show its artefacts): tessellation() says which.
  std::optional<int> segments;
  double exposure = 0.0;  ///< values are scaled by 2^exposure
  Rgb background = Rgb(0.18, 0.18, 0.2);

  void validate() const;
  int tessellation() const { return segments.value_or(perVertex ? 16 : 64); }
};

/// Orthographic view of the object: every pixel sees it along -view, so the reflected direction
/// is r = 2 (n.v) n - v with the interpolated normal n; the value is the map's bilinear lookup at
/// r. Alpha is 1 on the object and 0 on the background.
Image renderPreview(const Image& map, const Parameterization& parameterization, const PreviewOptions& options);

class BakedOutput;
/// The same for any output of bake or prefilter (baked_output.hpp), shaded per pixel as a renderer
/// shades it (BakedOutput::shade): a profile at r, a stack at r and n.v, a Fresnel table at n.v,
/// irradiance (maps indexed by the normal, SH) at n. 2-D maps looked up at r take the call above
/// (per-vertex mode included); for the other kinds perVertex is Error(InvalidArgument).
Image renderPreview(const BakedOutput& output, const PreviewOptions& options);

}  // namespace brdfbake
