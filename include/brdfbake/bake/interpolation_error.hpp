#pragma once
/// @file
/// How wrong per-vertex environment lookups are (Zimmons & Bastos 1999 section 3.4.2, Zimmons 1999 Figs. 16, 34-36).
///
/// Fixed-function sphere mapping computes texture coordinates per vertex and interpolates them
/// linearly across a triangle; hardware cube mapping interpolates the reflected vector. Both are
/// compared with the exact per-pixel lookup: the reflected vector of the interpolated normal.
/// Errors are angles (degrees) between the direction each scheme looks up and the exact one.

#include <brdfbake/core/math.hpp>

#include <vector>

namespace brdfbake {

enum class InterpolationScheme {
  SphereMapCoordinates,  ///< per-vertex GL_SPHERE_MAP (s, t), interpolated linearly
  ReflectedVector,       ///< per-vertex reflected vectors, interpolated linearly (cube maps)
};

/// Largest angular error (degrees) over a triangle of unit normals in eye space (orthographic
/// view +z), sampled at `steps` x `steps` barycentric points.
double triangleInterpolationError(InterpolationScheme scheme, const std::array<Vec3, 3>& normals, int steps = 24);

/// One point of the sweep: a triangle whose normals are `size` degrees apart (equilateral about
/// its centre normal), centred `place` degrees from the view axis (its reflected vector lands at
/// radius sin(place) of the sphere map; 90 degrees is the rim), worst over its orientation.
struct InterpolationPoint {
  double sizeDegrees = 0.0, placeDegrees = 0.0;
  double sphereMapError = 0.0, reflectedVectorError = 0.0;  ///< degrees
};
std::vector<InterpolationPoint> interpolationSweep(const std::vector<double>& sizesDegrees,
                                                   const std::vector<double>& placesDegrees);

/// Zimmons 1999's experiment: a planar surface along the x axis from -10 to +10 (normal +y), a
/// viewer at `viewer` (a perspective eye: v = normalize(viewer - p)), vertices every `segment`
/// units; the reflected vectors computed at the vertices are interpolated linearly along each
/// segment and compared with the per-point ones.
struct LineExperiment {
  std::vector<double> x, errorDegrees;
  double maxError = 0.0, maxAt = 0.0;
};
struct LineExperimentOptions {
  Vec3 viewer = Vec3(-8.3, 1, 0);  ///< the eye, above the surface: y in [1e-6, 1e6], |x|, |z| <= 1e6
  double segment = 20.0;           ///< vertex spacing, in (0, 20] (20: one segment, the whole surface)
  int samples = 4001;              ///< points along the surface, in [2, 1e7]
  /// Throws Error(InvalidArgument) naming the value outside its range: a viewer on or below the
  /// surface sees it edge-on or from behind (no reflection to interpolate), and beyond 1e6 the
  /// view directions lose the precision the error is measured in.
  void validate() const;
};
LineExperiment planarLineExperiment(const LineExperimentOptions& options);
LineExperiment planarLineExperiment(const Vec3& viewer = Vec3(-8.3, 1, 0), double segment = 20.0, int samples = 4001);

}  // namespace brdfbake
