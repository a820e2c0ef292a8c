#pragma once
/// @file
/// Latitude-longitude (equirectangular) parameterization, the usual form of HDR environments.

#include <brdfbake/maps/parameterization.hpp>

namespace brdfbake {

/// Lat-long map of 2N x N texels in its own frame, y up. Column u = px / 2N gives the azimuth
/// phi = 2 pi (u - 1/2) measured from -z towards +x; row v = py / N gives the polar angle
/// theta = pi v from +y. Direction: (sin theta sin phi, cos theta, -sin theta cos phi), so the
/// image centre looks down -z (forward in a right-handed y-up world) and +x is right of centre.
/// Singular sets: the poles (rows 0 and N, any phi) and the seam phi = +-pi (u = 0 and 1).
class LatLongMap final : public Parameterization {
 public:
  explicit LatLongMap(int resolution) : Parameterization(resolution) {}
  ParameterizationKind kind() const override { return ParameterizationKind::LatLong; }
  int width() const override { return 2 * resolution(); }
  int height() const override { return resolution(); }
  MapAddress getAddressFor(const Vec3& direction) const override;
  /// getAddressFor's pixel for a direction the caller guarantees to be unit length (no check, no
  /// virtual call: for inner loops).
  Vec2 pixelForUnit(const Vec3& unit) const;
  std::optional<Vec3> getDirectionFor(const Vec2& pixel) const override;
  bool wrapsHorizontally() const override { return true; }
  double texelCoverage(int, int) const override { return 1.0; }
  double texelSolidAngle(int x, int y) const override;
};

}  // namespace brdfbake
