#pragma once
/// @file
/// Dual-paraboloid parameterization (Heidrich & Seidel; Heidrich 2000 section 2.3).

#include <brdfbake/maps/parameterization.hpp>

namespace brdfbake {

/// Dual-paraboloid map: one image of 2N x N texels, front hemisphere (rz >= 0) on the left,
/// back (rz < 0) on the right, in the map's own frame.
///
/// Front: (x, y) = (rx, ry) / (1 + rz); back: (x, y) = (rx, ry) / (1 - rz); s = (x + 1)/2,
/// t = (y + 1)/2 within each half; pixels: px = (s + half) N, py = (1 - t) N.
/// The mapping is the stereographic projection, so it is conformal (anisotropy 1) and the solid
/// angle per unit area is 4 / (1 + x^2 + y^2)^2: centre texels cover 4x the solid angle of rim
/// texels. Each half covers its whole square: outside the unit circle the inverse continues into
/// the other hemisphere (Heidrich 2000 Fig. 6), which filtering needs; alpha (texelCoverage) is the
/// part of the texel inside the circle.
class ParaboloidMap final : public Parameterization {
 public:
  enum Hemisphere { Front = 0, Back = 1 };

  explicit ParaboloidMap(int resolution) : Parameterization(resolution) {}
  ParameterizationKind kind() const override { return ParameterizationKind::Paraboloid; }
  int width() const override { return 2 * resolution(); }
  int height() const override { return resolution(); }
  MapAddress getAddressFor(const Vec3& direction) const override;
  std::optional<Vec3> getDirectionFor(const Vec2& pixel) const override;
  void getDirectionsForRow(double py, const double* px, int count, double* x, double* y, double* z,
                           unsigned char* valid) const override;
  int regionCount() const override { return 2; }
  TexelRect region(int index) const override;
  double texelCoverage(int x, int y) const override;
  double texelSolidAngle(int x, int y) const override;

  /// The 4x4 texture matrix of Heidrich 2000 Eq. 9-12 for one hemisphere: applied to the homogeneous
  /// eye-space reflection vector (rx, ry, rz, 1), followed by the perspective divide, it gives
  /// (s, t, 1, 1) in that hemisphere's own [0,1]^2 texture. `eyeToMap` is the linear part of the
  /// eye-to-map rotation (M_l^-1 in Heidrich 2000). With `atlas` the matrix targets this class's
  /// 2N x N image instead (s scaled into the left or right half; t still upwards as in OpenGL, so
  /// a renderer that uploads row 0 first flips t).
  static Mat4 textureMatrix(Hemisphere hemisphere, const Mat3& eyeToMap = Mat3::Identity(), bool atlas = false);
};

}  // namespace brdfbake
