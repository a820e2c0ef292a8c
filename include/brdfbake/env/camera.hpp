#pragma once
/// @file
/// Which way a camera looks into an environment and which way is up: the rotation from the eye
/// space of a map (x right, y up, +z towards the viewer; docs/conventions.md) to the environment's
/// frame (y up; a lat-long image's centre looks down -z).

#include <brdfbake/core/math.hpp>

namespace brdfbake {

/// A camera frame in the environment's frame. The default is the frame prefiltered maps use:
/// the environment's axes are the map's, the viewer on +z looking down -z, up +y.
struct CameraFrame {
  Vec3 forward = -Vec3::UnitZ();  ///< the direction the camera looks (unit)
  Vec3 up = Vec3::UnitY();        ///< up in the picture (unit, perpendicular to forward)

  /// The camera turned by `yawDegrees` about +y from -z towards +x (the lat-long image's azimuth:
  /// 90 looks at +x, right of the image centre), then tilted up by `pitchDegrees` (in [-90, 90];
  /// positive looks up), with up tilted along so that it stays perpendicular and +x stays level.
  static CameraFrame fromYawPitch(double yawDegrees, double pitchDegrees);
  /// Throws Error(InvalidArgument) unless forward and up are finite unit vectors (to 1e-3) and
  /// perpendicular (|forward.up| <= 1e-3): a frame that is not orthonormal.
  void validate() const;
  /// The rotation taking eye-space directions to the environment's frame: columns right = forward
  /// x up, up, -forward (up made exactly perpendicular to forward first).
  Mat3 eyeToEnvironment() const;
};

}  // namespace brdfbake
