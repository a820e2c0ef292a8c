#pragma once
/// @file
/// The OpenGL GL_SPHERE_MAP parameterization (Zimmons & Bastos 1999 Eq. 2).

#include <brdfbake/maps/parameterization.hpp>

namespace brdfbake {

/// Sphere map of N x N texels, in eye space (view vector +z, y up).
///
/// Forward: m = 2 sqrt(rx^2 + ry^2 + (rz + 1)^2), s = rx/m + 1/2, t = ry/m + 1/2.
/// Inverse: x = 2s - 1, y = 2t - 1, n = (x, y, sqrt(1 - x^2 - y^2)), r = 2 n_z n - (0, 0, 1).
/// Pixels: s = px / N, t = 1 - py / N (row 0 is t = 1, so the image looks like a photograph of a
/// mirror ball with up at the top).
///
/// Singular set: the rim circle x^2 + y^2 = 1, which is the single direction -z. Forward maps -z
/// (and directions within rounding of it) to the rim point (s, t) = (1, 1/2), never NaN. The
/// inverse pulls points at or outside the rim to radius 1 - 1e-15 at the same azimuth: a direction
/// within 1e-7 of -z whose normal (x, y, ~0) still tells the rim points apart, so the part of a
/// texel's footprint outside the disc takes the value at its nearest rim point and lookups near
/// the rim stay continuous, also for terms that depend on the normal.
/// The map is equal-area: 16 / N^2 sr per texel inside the disc; its anisotropy is
/// 1 / cos^2(theta / 2) at angle theta from +z.
class SphereMap final : public Parameterization {
 public:
  explicit SphereMap(int resolution) : Parameterization(resolution) {}
  ParameterizationKind kind() const override { return ParameterizationKind::Sphere; }
  int width() const override { return resolution(); }
  int height() const override { return resolution(); }
  MapAddress getAddressFor(const Vec3& direction) const override;
  std::optional<Vec3> getDirectionFor(const Vec2& pixel) const override;
  void getDirectionsForRow(double py, const double* px, int count, double* x, double* y, double* z,
                           unsigned char* valid) const override;
  double texelCoverage(int x, int y) const override;
  void texelCoverageRow(int y, double* coverage) const override;
  double texelSolidAngle(int x, int y) const override;

  /// GL_SPHERE_MAP texture coordinates of a unit reflected direction (total, never NaN).
  static Vec2 textureCoordinates(const Vec3& unitDirection);
  /// Reflected direction for texture coordinates (pulled just inside the rim outside the disc).
  static Vec3 direction(const Vec2& st);
};

}  // namespace brdfbake
