#pragma once
/// @file
/// How close a baked map is to the function it stands for, as a renderer sees it. The measures
/// and why there are three: docs/accuracy.md.

#include <brdfbake/bake/map_function.hpp>
#include <brdfbake/core/context.hpp>
#include <brdfbake/maps/image.hpp>

#include <functional>
#include <vector>

namespace brdfbake {

struct ErrorOptions {
  int samples = 20000;  ///< lookup directions per set (uniform, visible sphere, highlight); >= 1
  unsigned seed = 1;    ///< for the random directions (results are reproducible)
  /// Sphere maps: also measure over the directions a renderer looks up for a visible sphere
  /// (reflected vectors of normals uniform over the sphere's screen disc, i.e. uniform over the
  /// map's disc, since the map is equal-area).
  bool visibleSphere = true;
  /// The highlight set is drawn in proportion to the exact value, located by evaluating the
  /// function on a cube grid of this many cells per face side (cell centres and corners), once
  /// per function. 192 resolves lobes down to about 0.3 degrees (Phong exponents to ~30 000);
  /// a fraction of the set stays uniform, so narrower lobes are still seen, with more noise. >= 8.
  int highlightGrid = 192;

  /// Throws Error(InvalidArgument) for values outside the documented ranges.
  void validate() const;
};

/// Errors of bilinear lookups against the exact function, relative to the largest exact value
/// met (so 0.01 is 1 % of the peak), over all channels (RMS over channels per direction).
struct ErrorStats {
  double rms = 0.0;         ///< RMS over directions uniform on the sphere (solid-angle weighted)
  double max = 0.0;         ///< largest absolute error over those directions
  double visibleRms = 0.0;  ///< sphere maps: RMS over the directions of a visible sphere (else = rms)
  /// Value-weighted RMS: sqrt(integral v e^2 dw / integral v dw), v the exact value's largest
  /// channel, e the error. The RMS over lookups drawn in proportion to the map's own value: it
  /// sees a narrow highlight that the uniform RMS averages away (docs/accuracy.md).
  double highlightRms = 0.0;
  double highlightMax = 0.0;  ///< largest error among the highlight set's lookups
  double peak = 0.0;          ///< largest |exact value| met at the lookups measured, the normaliser

  /// The measure `max_error` bounds (auto, chart): the larger of highlightRms and the RMS over
  /// the lookups a renderer makes (visibleRms when `visibleLookups`, else rms).
  double bound(bool visibleLookups) const;
};

/// The lookup directions of ErrorStats' three sets, with the exact values there: built once per
/// function, then any number of maps of it are measured against them (auto tries many).
class ErrorProbes {
 public:
  /// Draws the sets (options.samples each; the visible set only with options.visibleSphere) and
  /// evaluates `exact` on them (in parallel). Throws Error(InvalidArgument) for bad options.
  ErrorProbes(const MapFunction& exact, const ErrorOptions& options = {});

  /// Errors of `lookup` at the probes. Directions r with -r.z > `rimCos` are left out of every set
  /// (the sphere-map rim; pass a value > 1 to keep them all); `visibleSphere` = false leaves the
  /// visible set out (visibleRms = rms).
  ErrorStats measure(const std::function<Rgb(const Vec3&)>& lookup, double rimCos, bool visibleSphere) const;

  /// Every direction measure() may look up (the visible set only with `visibleSphere`), rim
  /// directions included.
  std::vector<Vec3> directions(bool visibleSphere) const;
  /// measure() of lookups already made: `looked[i]` the value at directions(visibleSphere)[i].
  /// Throws Error(InvalidArgument) for a size mismatch.
  ErrorStats measureValues(const std::vector<Rgb>& looked, double rimCos, bool visibleSphere) const;

 private:
  struct Probe {
    Vec3 direction;
    Rgb exact;
    double weight = 1.0;  ///< self-normalised importance weight (highlight set), else 1
  };
  // measure(), with lookup(index into directions(visibleSphere), direction).
  ErrorStats measureAt(const std::function<Rgb(std::size_t, const Vec3&)>& lookup, double rimCos,
                       bool visibleSphere) const;

  std::vector<Probe> uniform_, visible_, highlight_;
};

/// The texels one lookup blends: `count` (up to 4) texel indices and their weights.
struct TexelTaps {
  int count = 0;
  long long index[4] = {0, 0, 0, 0};
  double weight[4] = {0.0, 0.0, 0.0, 0.0};
};

/// ErrorProbes::measure of a lookup that blends texels of a map never stored whole: `taps` names
/// the texels (indices in [0, texelCount)) a lookup at a direction reads, `texel` computes one
/// (called once for each texel any probe reads, in parallel on the context's threads). So a
/// map's error costs model evaluations for the texels the probes read (at most 4 per probe),
/// whatever its resolution.
ErrorStats measureSparseLookups(const ErrorProbes& probes, long long texelCount,
                                const std::function<void(const Vec3&, TexelTaps&)>& taps,
                                const std::function<Rgb(long long)>& texel, double rimCos, bool visibleSphere,
                                const Context& context = {});

/// Errors of any lookup against the exact function (builds ErrorProbes; see there).
ErrorStats measureLookupError(const std::function<Rgb(const Vec3&)>& lookup, const MapFunction& exact,
                              const ErrorOptions& options, double rimCos, bool visibleSphere);

/// The rim band measureMapError leaves out of a sphere map of `resolution`: cos of the angle two
/// rim texels span, 4 sqrt(2/N), about -z (docs/conventions.md); 2 (nothing left out) for other
/// parameterizations and for sphere maps under 4 texels across, where the band would be the sphere.
double mapRimCos(ParameterizationKind kind, int resolution);

/// Measures a baked map. Sphere maps skip directions within 2 texels' worth of angle of -z (the
/// rim, their singular set; see docs/conventions.md).
ErrorStats measureMapError(const Image& image, const Parameterization& map, const MapFunction& exact,
                           const ErrorOptions& options = {});
/// The same against probes already drawn for the function.
ErrorStats measureMapError(const Image& image, const Parameterization& map, const ErrorProbes& probes,
                           bool visibleSphere = true);

/// What measureMapError reports for the map bakeMap's general path makes of `function` with
/// `samplesPerTexel` samples (texels by bakeTexel, rounded to float as an Image stores them),
/// without baking it: only the texels the probes' lookups read are computed
/// (measureSparseLookups), so the cost is bounded by the probes, not the resolution, and no
/// image is allocated. bakeMap's tabulated paths give slightly different texels (bakeTexel).
ErrorStats estimateMapError(const Parameterization& map, const MapFunction& function, int samplesPerTexel,
                            const ErrorProbes& probes, bool visibleSphere = true, const Context& context = {});

}  // namespace brdfbake
