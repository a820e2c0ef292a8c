#pragma once
/// @file
/// Cube maps with the OpenGL face-selection table (Zimmons 1999 Fig. 33), stored as a horizontal cross.

#include <brdfbake/maps/parameterization.hpp>

#include <array>

namespace brdfbake {

/// Cube map with N x N faces laid out as a 4N x 3N horizontal cross:
///
///            +Y
///       -X   +Z   +X   -Z
///            -Y
///
/// Face order (region index) is the OpenGL one: +X, -X, +Y, -Y, +Z, -Z. Within a face the OpenGL
/// table gives (sc, tc, ma), s = (sc/|ma| + 1)/2, t = (tc/|ma| + 1)/2, and pixel
/// (face origin) + (s N, t N): OpenGL's t already runs downwards on the side faces, so each face
/// looks like a photograph with +y up, as cube-map tools write them, and the cross is seamless.
/// Cells of the cross that hold no face have coverage 0 and no direction.
class CubeMap final : public Parameterization {
 public:
  enum Face { PosX = 0, NegX, PosY, NegY, PosZ, NegZ };

  explicit CubeMap(int resolution) : Parameterization(resolution) {}
  ParameterizationKind kind() const override { return ParameterizationKind::Cube; }
  int width() const override { return 4 * resolution(); }
  int height() const override { return 3 * resolution(); }
  MapAddress getAddressFor(const Vec3& direction) const override;
  std::optional<Vec3> getDirectionFor(const Vec2& pixel) const override;
  int regionCount() const override { return 6; }
  TexelRect region(int index) const override;
  double texelCoverage(int x, int y) const override;
  double texelSolidAngle(int x, int y) const override;

  /// Face and (s, t) in [0,1]^2 for a unit direction (OpenGL table; ties go to x, then y).
  static std::pair<Face, Vec2> faceCoordinates(const Vec3& unitDirection);
  /// Unit direction for a face and (s, t).
  static Vec3 faceDirection(Face face, const Vec2& st);
  /// Cross cell (column, row) of each face.
  static std::array<int, 2> faceCell(Face face);
  /// "+X", "-X", ...
  static std::string_view faceName(Face face);
};

}  // namespace brdfbake
