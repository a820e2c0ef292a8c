#pragma once
/// @file
/// How close a prefiltered environment map is to the reference prefilter, measured at a few
/// chosen points instead of every texel (the reference costs output texels x input samples lobe
/// evaluations: minutes to hours for a whole map). Used by `brdfbake chart` (environment maps) and
/// bench/prefilter_bench.
///
/// Two kinds of point sets:
/// - a random subset of output texels (prefilterTexelSubset): the map's value at the texel against
///   the reference at the texel's axis, weighted by the texel's solid angle. Its RMS estimates
///   prefilterError over the whole map (docs/prefilter.md's metric), which is what the fast
///   methods' own error estimates predict;
/// - random lookup directions (prefilterLookupSet), uniform on the sphere: a bilinear lookup of the
///   map (sampleBilinear, as a renderer filters) against the reference at the direction's axis,
///   so it also sees the interpolation between texels, which falls with the map's resolution.
/// Errors are the per-point relative error |a - r| / max(|r|, floor) (prefilterErrorFloor) as a
/// weighted RMS and a maximum.

#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/env/prefilter_lobe.hpp>
#include <brdfbake/maps/image.hpp>
#include <brdfbake/maps/parameterization.hpp>

#include <array>
#include <utility>
#include <vector>

namespace brdfbake {

/// Points a prefiltered map is compared with the reference on.
struct PrefilterCheckPoints {
  /// Texel subsets: the (x, y) texel of each point, read with Image::at. Empty for lookup sets,
  /// which read the map by sampleBilinear at `directions`.
  std::vector<std::array<int, 2>> texels;
  std::vector<Vec3> directions;  ///< map directions (texel centres, or lookup directions)
  std::vector<Vec3> axes;        ///< the axis each holds (prefilterAxis), in the environment's frame
  std::vector<double> weights;   ///< texelSolidAngle for texels, 1 for uniform lookups

  std::size_t size() const { return axes.size(); }
};

/// `count` texels of `map` drawn uniformly with replacement (seeded std::mt19937) among those of
/// non-zero solid angle, with their axes for `lobe` and `options` (sphere-map view, irradiance
/// normals). When `count` is at least the number of such texels, every one of them once (the
/// measure is then exact). Throws Error(InvalidArgument) if count < 1.
PrefilterCheckPoints prefilterTexelSubset(const Parameterization& map, const PrefilterLobe& lobe,
                                          const PrefilterOptions& options, int count, unsigned seed);

/// `count` directions uniform on the sphere (seeded), except, for sphere maps, those within the
/// angle two rim texels span of -z (the map's singular set, as measureMapError skips it).
PrefilterCheckPoints prefilterLookupSet(const Parameterization& map, const PrefilterLobe& lobe,
                                        const PrefilterOptions& options, int count, unsigned seed);

/// The map's RGB at the points: the texels, or bilinear lookups at the directions.
std::vector<Rgb> prefilterValuesAt(const Image& level0, const Parameterization& map,
                                   const PrefilterCheckPoints& points);

/// Weighted RMS and maximum of the relative error of `values` against `reference` (same length as
/// `weights`): |v - r| / max(|r|, floor), |.| the RGB norm.
PrefilterError prefilterPointsError(const std::vector<Rgb>& values, const std::vector<Rgb>& reference,
                                    const std::vector<double>& weights, double floor);

/// The RGB weight of each distinct exponent n of a constant fitted lobe model in its prefiltered
/// form (prefilterLobeModel): Σ over channels c and lobes k with n_kc = n of C_kc (n + 2)/(n + 1)
/// times channel c's column of LobeModel::rgbWeights. Lobes of zero weight are left out.
std::vector<std::pair<double, Rgb>> prefilterLobeModelTerms(const LobeModel& model);

/// The reference of prefilterLobeModel at explicit axes: Σ_n weight_n x prefilterReferenceAt(phong:n),
/// component-wise with the environment's RGB. Throws Error(InvalidArgument) for models that vary
/// with elevation or have no lobe of non-zero weight.
std::vector<Rgb> prefilterLobeModelReferenceAt(const Environment& environment, const LobeModel& model,
                                               const std::vector<Vec3>& axes, const Context& context = {});

/// The error floor (prefilterErrorFloor's delta) for a lobe model: 1e-3 x the environment's mean |L|
/// x Σ_n |weight_n| (the model's mass on a white environment, as an RGB norm).
double prefilterLobeModelErrorFloor(const Environment& environment, const LobeModel& model);

}  // namespace brdfbake
