#pragma once
/// @file
/// A material under an environment (Kautz, Vázquez, Heidrich & Seidel 2000, "A Unified Approach to
/// Prefiltered Environment Maps"; Cabral, Olano & Nemec 1999): each texel holds the radiance the
/// material reflects towards the viewer,
///
///   L_o(n, v) = ∫ f_r(l, v; n) L(l) max(0, n.l) dω(l) = k ∫ shade(g, l) L(l) dω(l),
///
/// k = Material::lightColorPerIrradiance() (docs/conventions.md, "Radiometric units": an environment
/// texel is radiance, so a texel of radiance L and solid angle dω is a light of colour k L dω), n the
/// normal a texel stands for (n = normalize(r + v), r its map direction; geometryForReflection) and v
/// the map's view. A sphere map (view +z) is the matcap: an orthographic picture of a sphere of the
/// material, looked up by the view-space normal (docs/matcap.md).
///
/// Frames: the map lives in eye space (x right, y up, +z towards the viewer) and the environment is
/// seen through the camera (camera.hpp): environment direction = camera.eyeToEnvironment() x eye
/// direction. Sphere maps view along +z; paraboloid, cube and lat-long maps are indexed by the
/// reflected direction r in eye space and fix `view` (default +z). Texels hold the mean of L_o over
/// their footprint (stratified samples, as baked material maps: bake/baker.hpp); alpha is coverage.
///
/// Method (docs/matcap.md): the environment's bright texels (luminance above 16 x its mean, at most
/// 1024: a sun) are explicit lights summed exactly at every evaluation; the rest, clipped there, is
/// integrated by filtered importance sampling of the BRDF's reflection lobes (Křivánek & Colbert
/// 2008: directions drawn from the lobes' mixture, each reading the rest's solid-angle mip chain at
/// the level of its own solid angle; multi-sample balance heuristic, Veach 1997). L_o is evaluated on
/// a polar grid of normals about the view, 4 or 8 points per lobe width, and interpolated bicubically
/// into the texels' footprint samples, or at every footprint sample when that is cheaper.
///
/// Error (docs/accuracy.md's measures, relative to the peak): bilinear lookups of the finished map
/// against the reference at probe directions: the RMS over directions uniform on the sphere (for a
/// sphere map, uniform over the visible disc), and the value-weighted RMS (drawn in proportion to
/// the map's value: where the highlight is); the estimate is the larger. The reference is a sum over
/// the environment's texels (underEnvironmentReferenceAt). Sphere maps leave out the rim band
/// (mapRimCos), as measureMapError does. Besides, the largest relative error of the evaluation's
/// values at the probes whose reference is above 1 % of the median: the error where the picture is
/// dim, bounded by maxRelativeError.

#include <brdfbake/brdf/material.hpp>
#include <brdfbake/core/context.hpp>
#include <brdfbake/env/camera.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/maps/image.hpp>

#include <nlohmann/json.hpp>

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace brdfbake {

enum class UnderEnvironmentMethod {
  Auto,       ///< the cheapest sampled configuration whose estimated error is within 0.8 maxError
  Sampled,    ///< bright lights plus filtered importance sampling, fixed or searched settings
  Reference,  ///< the reference sum at every footprint sample (slow: for checks)
};
/// "auto", "sampled", "reference".
std::string_view toString(UnderEnvironmentMethod method);
/// Inverse of toString; throws Error(InvalidArgument) naming the accepted values.
UnderEnvironmentMethod parseUnderEnvironmentMethod(std::string_view name);

struct UnderEnvironmentOptions {
  ParameterizationKind parameterization = ParameterizationKind::Sphere;
  int resolution = 256;
  /// Towards the viewer in eye space: +z for sphere maps (anything else is an error); paraboloid,
  /// cube and lat-long maps may fix another.
  Vec3 view = Vec3::UnitZ();
  CameraFrame camera;
  /// Stratified footprint samples per texel (as BakeOptions::samplesPerTexel), in [1, 4096].
  int samplesPerTexel = 16;
  UnderEnvironmentMethod method = UnderEnvironmentMethod::Auto;
  /// The bound on the estimated error (larger of the lookup RMS and the value-weighted RMS,
  /// relative to the peak), in (0, 1). Default 1 %.
  double maxError = 0.01;
  /// The bound on the largest relative error of a texel, |value - reference| / reference, over the
  /// texels whose reference is above 1 % of the median (where the picture is dim as well as at a
  /// highlight), in (0, 10]. Default (nullopt): 3 x maxError.
  std::optional<double> maxRelativeError;
  double relativeBound() const { return maxRelativeError.value_or(3.0 * maxError); }
  /// Fixed settings (0 = searched by maxError; Sampled only): importance samples per evaluation
  /// (>= 8), and grid points per lobe width (>= 2; -1 = every footprint sample, no grid).
  int importanceSamples = 0;
  int gridPerWidth = 0;
  /// Estimate the error (auto always does). Probes (half uniform, half value-weighted; >= 16).
  bool estimateError = true;
  int probes = 512;
  unsigned seed = 1;
  /// Bright texels: luminance above `brightFactor` x the environment's mean (> 1), at most
  /// `maxBrightTexels` (>= 0; the threshold rises to keep the count).
  double brightFactor = 16.0;
  int maxBrightTexels = 1024;

  /// Throws Error(InvalidArgument) for out-of-range values, a sphere map's view other than +z, a
  /// fixed setting with another method, or a camera frame that is not orthonormal.
  void validate() const;
};

/// One configuration tried (auto) or used.
struct UnderEnvironmentCandidate {
  std::string detail;              ///< e.g. "256 samples, grid 39 x 156 (4 per width)"
  double predictedSeconds = 0.0;   ///< from the cost model, for ordering
  double seconds = 0.0;            ///< spent evaluating it (grid or probes)
  double errorEstimate = -1.0;     ///< the bound on the probes, from its own values (-1: not estimated)
  double errorEstimateMax = -1.0;  ///< the largest probe error, relative to the peak
  double relativeError = -1.0;     ///< the largest relative error at probes above 1 % of the median
  bool chosen = false;
};

struct UnderEnvironmentSummary {
  UnderEnvironmentMethod method = UnderEnvironmentMethod::Auto;  ///< Sampled or Reference
  std::string detail;
  std::string material;  ///< the material's model name
  double maxError = 0.0, maxRelativeError = 0.0;
  /// The finished map's lookups against the reference (0 when not estimated): the larger of
  /// lookupRms and highlightRms (errorEstimate), each relative to the peak (the largest reference
  /// value met), and the largest error.
  double errorEstimate = 0.0;
  double lookupRms = 0.0;
  double highlightRms = 0.0;
  double errorMax = 0.0;
  double peak = 0.0;
  /// The largest relative error of the chosen evaluation's values (a texel's own value, before
  /// bilinear lookups) at the probes whose reference is above relativeFloor (1 % of the median of the
  /// uniform probes' references).
  double relativeError = 0.0, relativeFloor = 0.0;
  int probes = 0;
  bool errorEstimated = false;
  /// Why not, when errorEstimated is false: "estimation off", or "the lobe is narrower than the
  /// environment's texels" (auto then reflects the environment as a mirror: see the notes).
  std::string unestimated = "estimation off";
  bool exact = false;     ///< the reference method (no estimate)
  bool metBound = false;  ///< exact, or estimated within maxError and maxRelativeError
  /// The split: bright texels (explicit lights), the luminance threshold, their share of ∫ Y dω.
  int brightTexels = 0;
  double brightThreshold = 0.0;
  double brightShare = 0.0;
  double seconds = 0.0;          ///< everything
  double setupSeconds = 0.0;     ///< split, mip chain
  double estimateSeconds = 0.0;  ///< probes, their reference, candidates' values there
  double outputSeconds = 0.0;    ///< evaluating and baking the map
  std::vector<UnderEnvironmentCandidate> candidates;
  std::vector<std::string> notes;

  std::string briefReport() const;
  nlohmann::json toJson() const;
};

/// A map of a material under an environment: level 0 of `map`.
struct MaterialUnderEnvironment {
  Image image;
  std::shared_ptr<const Parameterization> map;
  UnderEnvironmentSummary summary;
};

/// Throws Error(InvalidArgument) naming the model and why when `material` has no BRDF to light
/// with an environment (Material::reflectionLobes is nullopt): hand-designed maps (colorgram,
/// gooch, silhouette, hatching, fresnel), mirror-direction tables, reflectance and prefiltered modes.
void requireBrdf(const Material& material);

/// Makes the map (see @file). Throws Error(InvalidArgument) for bad options or a material with no
/// BRDF, Error(Resource) above maxTexels, Error(Numerical) if a value comes out non-finite.
MaterialUnderEnvironment shadeUnderEnvironment(const Environment& environment, const Material& material,
                                               const UnderEnvironmentOptions& options = {},
                                               const Context& context = {});

/// The reference L_o at explicit eye-space normals for the view `view` (eye space) and `camera`:
/// k times the sum over the environment's texels of shade(g, l) L Ω, the bright texels (as split by
/// `options`) one by one and the rest over a quadtree of its solid-angle mip chain refined to an
/// eighth of the integrand's local scale (docs/matcap.md). Only the options' camera and split settings
/// are read.
std::vector<Rgb> underEnvironmentReferenceAt(const Environment& environment, const Material& material,
                                             const std::vector<Vec3>& normals, const Vec3& view,
                                             const UnderEnvironmentOptions& options = {}, const Context& context = {});

/// The metadata writeUnderEnvironmentMap writes with the map (see there).
MapInfo underEnvironmentMapInfo(const MaterialUnderEnvironment& map, nlohmann::json spec);

/// Writes the map (writeMap) with MapInfo::spec = `spec` plus "under_environment": {material,
/// method, detail, max_error, error_metric, error_estimate, max_relative_error, relative_error, exact}.
MapWriteReport writeUnderEnvironmentMap(const MaterialUnderEnvironment& map, const std::filesystem::path& path,
                                        nlohmann::json spec, CubeLayout layout = CubeLayout::Cross,
                                        const WriteOptions& options = {});

}  // namespace brdfbake
