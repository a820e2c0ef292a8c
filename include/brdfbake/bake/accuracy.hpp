#pragma once
/// @file
/// How close a baked map is to the function it stands for, as a renderer sees it.

#include <brdfbake/bake/image.hpp>
#include <brdfbake/bake/map_function.hpp>

#include <functional>

namespace brdfbake {

struct ErrorOptions {
  int samples = 20000;    ///< lookup directions
  unsigned seed = 1;      ///< for the random directions (results are reproducible)
  /// Sphere maps: also measure over the directions a renderer looks up for a visible sphere
  /// (reflected vectors of normals uniform over the sphere's screen disc, i.e. uniform over the
  /// map's disc, since the map is equal-area).
  bool visibleSphere = true;
};

/// Errors of bilinear lookups against the exact function, relative to the largest exact value
/// met (so 0.01 is 1 % of the peak), over all channels.
struct ErrorStats {
  double rms = 0.0;         ///< RMS over directions uniform on the sphere (solid-angle weighted)
  double max = 0.0;         ///< largest absolute error over those directions
  double visibleRms = 0.0;  ///< sphere maps: RMS over the directions of a visible sphere (else = rms)
  double peak = 0.0;        ///< largest |exact value| met, the normaliser
};

/// Errors of any lookup against the exact function: RMS and max over `options.samples` directions
/// uniform on the sphere and, with `visibleSphere`, RMS over a visible sphere's lookups (reflected
/// vectors of normals uniform over the sphere-map disc, view +z). Directions r with -r.z >
/// `rimCos` are skipped (the sphere-map rim; pass a value > 1 to keep every direction).
ErrorStats measureLookupError(const std::function<Rgb(const Vec3&)>& lookup, const MapFunction& exact,
                              const ErrorOptions& options, double rimCos, bool visibleSphere);

/// Measures a baked map. Sphere maps skip directions within 2 texels' worth of angle of -z (the
/// rim, their singular set; see docs/conventions.md).
ErrorStats measureMapError(const Image& image, const Parameterization& map, const MapFunction& exact,
                           const ErrorOptions& options = {});

}  // namespace brdfbake
