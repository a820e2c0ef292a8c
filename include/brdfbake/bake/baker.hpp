#pragma once
/// @file
/// Integrating a MapFunction over every texel's footprint.

#include <brdfbake/bake/map_function.hpp>
#include <brdfbake/core/context.hpp>
#include <brdfbake/maps/image.hpp>

#include <functional>
#include <string>

namespace brdfbake {

struct BakeOptions {
  /// Stratified samples per texel footprint (a grid a x b with a b = samples, a <= b as close to
  /// square as the count allows), each mapped through the inverse parameterization. >= 1.
  int samplesPerTexel = 16;
  /// Tolerance of tabulated radial profiles, relative to their peak.
  double profileTolerance = 1e-6;

  /// Throws Error(InvalidArgument) for out-of-range values.
  void validate() const;
};

struct BakeSummary {
  /// "general" (model per sample), "radial" (tabulated lobes per sample), "radial-view-axis"
  /// (sphere map of lobes about the view axis: table indexed by map radius, no inverse mapping)
  /// or "microfacet" (Cook-Torrance lobes per light, D tabulated: MapFunction::microfacetLobes).
  /// On a sphere map seen along +z the radial and microfacet paths take each sample's normal from
  /// its disc position instead of the inverse mapping, and the radial path skips runs of texels
  /// a lobe cannot reach; the output is the same to rounding (tests/bake: 2e-6 and 1e-6 of the peak).
  std::string path;
  int lobes = 0;            ///< tabulated lobes (radial paths)
  int largestTable = 0;     ///< entries of the largest table
  double tableError = 0.0;  ///< worst table interpolation error relative to its peak
  long long samples = 0;    ///< footprint samples evaluated
  int deltaLobes = 0;       ///< lobes narrower than the sample spacing, deposited as deltas
  double seconds = 0.0;

  std::string briefReport() const;
};

/// A baked map and how it was made.
struct BakedMap {
  Image image;
  BakeSummary summary;
};

/// Bakes `function` into an image laid out by `map`: each texel holds the mean of the function
/// over its stratified footprint samples (points outside the domain take the value the inverse
/// mapping extends to), alpha holds the texel's coverage of the domain.
///
/// Radial lobes narrower than the sample spacing (twice their half-energy angle below the
/// spacing of samples around their axis), which point samples would miss or alias, are not
/// sampled: their exact integral ∫ f dω is deposited into the texels around the axis (a box as
/// wide as the lobe, split by area, divided by each texel's exact solid angle), so the map keeps
/// the lobe's energy at any resolution.
///
/// Runs on the context's threads and reports each row to it (Context::report). Throws Error(Resource)
/// when the image is over the context's size limit (Context::requireImageSize), Cancelled when cancelled.
BakedMap bakeMap(const Parameterization& map, const MapFunction& function, const BakeOptions& options = {},
                 const Context& context = {});

/// Texel (x, y) as bakeMap's general path computes it: the mean of `function` over the texel's
/// `samplesPerTexel` stratified samples (the same grid), 0 when none lies in the domain. The other
/// paths tabulate the model (to BakeOptions::profileTolerance) and deposit lobes narrower than a
/// sample, so their texels differ slightly. For computing a few texels of a map without baking it.
Rgb bakeTexel(const Parameterization& map, const MapFunction& function, int x, int y, int samplesPerTexel);

/// bakeMap(...).image, for callers that do not report how the map was made.
Image bake(const Parameterization& map, const MapFunction& function, const BakeOptions& options = {},
           const Context& context = {});

}  // namespace brdfbake
