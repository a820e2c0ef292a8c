#pragma once
/// @file
/// Prefiltered environment maps (Heidrich 2000 section 3.2): each texel of the output holds
///   L_o(a) = ∫ w(a . l) L(l) dω(l)
/// for the lobe w (prefilter_lobe.hpp) about the texel's axis a: its map direction (the reflected
/// direction r), or the normal n for irradiance. Paraboloid, cube and lat-long outputs live in the
/// environment's frame; a sphere map lives in eye space for one view (PrefilterOptions::view), and
/// irradiance in a sphere map is indexed, as the hardware indexes it, by the reflected direction,
/// so texel r holds L_o(n) with n = normalize(r + v).
///
/// Texels hold L_o at their centre direction (the lobe band-limits it); the mirror lobe has no
/// integral and resamples the environment with footprint supersampling instead.
///
/// Methods (docs/prefilter.md):
/// - reference: the exact solid-angle-weighted sum over every input texel (texelSolidAngle),
///   in double; texels wider than an eighth of the lobe's width are split into s x s sub-samples
///   (s <= 8, at most 2^22 samples in all) that share the texel's exact solid angle.
///   The sum is taken in ratio form, Σ w_i Ω_i L_i / Σ w_i Ω_i times the lobe's mass, so a
///   constant environment is reproduced exactly whatever the quadrature of the lobe.
/// - sh: spherical harmonics to order L, convolved with the lobe's Funk-Hecke coefficients.
/// - importance: filtered importance sampling (Křivánek & Colbert 2008): K samples of the lobe,
///   each reading the environment's solid-angle mip chain at the level of its own solid angle.
/// - direct: the reference sum restricted to the lobe's support (all but a stated fraction of its
///   mass) on the coarsest mip level whose texels are finer than width/q.
/// Fast methods may evaluate a coarser lat-long grid (8 points per lobe width) and interpolate it
/// bicubically when that is cheaper than the output's own texels.
///
/// Error metric: per-texel relative error e = |a - r| / max(|r|, delta) (|.| the RGB norm, delta
/// = 1e-3 of the lobe's mass times the environment's mean |L|), as an RMS over the sphere weighted
/// by solid angle (prefilterError). Fast methods estimate it before they run from probes: up to 512
/// directions, half uniform, half drawn towards the bright parts of the filtered environment,
/// against the reference on the probes (the direct sum on the finest needed level, texels split
/// into sub-samples no wider than width/8, all but 1e-7 of the lobe's mass), weighted to an
/// unbiased solid-angle RMS. The probes are read in four batches; an estimate stops once it lies
/// more than two standard errors above the bound, or below it after at least half the probes.

#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/core/context.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter_lobe.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/maps/image.hpp>

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace brdfbake {

enum class PrefilterMethod { Auto, Reference, SphericalHarmonics, Importance, Direct, Resample };

/// "auto", "reference", "sh", "importance", "direct", "resample".
std::string_view toString(PrefilterMethod method);
/// Inverse of toString (not "resample", which only the mirror lobe uses); throws
/// Error(InvalidArgument) naming the accepted values.
PrefilterMethod parsePrefilterMethod(std::string_view name);

struct PrefilterOptions {
  /// Output parameterization and resolution (per side, per hemisphere, per face, rows).
  ParameterizationKind parameterization = ParameterizationKind::Sphere;
  int resolution = 256;
  /// Sphere maps only: the direction towards the viewer and the up vector, in the environment's
  /// frame; the map's eye space has +z = view and +y = up made orthogonal to it.
  Vec3 view = Vec3::UnitZ();
  Vec3 up = Vec3::UnitY();
  /// Also make the solid-angle mip chain (env_mips.hpp).
  bool mips = false;
  /// Cube maps: each edge texel and the texel facing it across the edge become their mean at every
  /// level (fixCubeEdges, env_mips.hpp), so clamp-to-face lookups meet at the seams. Off keeps every
  /// texel's own prefiltered value (cmft's --edgeFixup none), e.g. to compare texels with a reference;
  /// the solid-angle mip chain (mips) always fixes edges, so off requires mips off.
  bool cubeEdgeFixup = true;
  /// Auto picks the cheapest candidate whose estimated error is within 0.8 maxError (a margin
  /// for the estimate's own spread); a named fast method picks its cheapest such setting; when
  /// no fast candidate qualifies, auto falls back to reference and a named method uses its most
  /// accurate setting (noted).
  PrefilterMethod method = PrefilterMethod::Auto;
  /// RMS relative error the map is built to, in (0, 1). Default 1 %.
  double maxError = 0.01;
  /// Fixed method settings for benchmarks (0 = choose by maxError): SH order, importance
  /// samples, direct texels per lobe width q. Setting one requires the matching method.
  int shOrder = 0;
  int importanceSamples = 0;
  double directTexelsPerWidth = 0.0;
  /// Allow fast methods to evaluate a coarser grid and interpolate (default on).
  bool interpolate = true;
  /// Estimate the error from probes (fast methods; auto always does). Turning it off for a named
  /// method with fixed settings times the method alone.
  bool estimateError = true;
  /// Probe directions for the estimate (>= 16), and the seed of their random rotation.
  int probes = 512;
  unsigned seed = 1;
  /// Footprint samples per texel for the mirror lobe (as BakeOptions::samplesPerTexel).
  int mirrorSamples = 16;
  /// Varying lobe models only (prefilterLobeModelStack, prefilter_stack.hpp): the number of maps
  /// in the stack over view elevation, in [2, 64].
  int elevations = 8;

  /// Throws Error(InvalidArgument) for out-of-range values or settings that contradict the method.
  void validate() const;
};

/// One configuration tried (auto) or used.
struct PrefilterCandidate {
  PrefilterMethod method = PrefilterMethod::Auto;
  std::string detail;             ///< e.g. "order 24", "256 samples", "level 2 (q = 4), tail 1e-05, grid 64"
  double predictedSeconds = 0.0;  ///< from the cost model, for ordering
  double seconds = 0.0;           ///< setup (and grid) time actually spent
  /// The error on the probes (-1: not estimated): the larger of errorEstimateRms and
  /// errorEstimateHighlight.
  double errorEstimate = -1.0;
  double errorEstimateMax = -1.0;        ///< largest probe error
  double errorEstimateRms = -1.0;        ///< solid-angle RMS of the relative error
  double errorEstimateHighlight = -1.0;  ///< value-weighted RMS of the relative error (near the highlights)
  int probes = 0;                        ///< probes the estimate read (it stops once clearly above or below the bound)
  bool chosen = false;
};

struct PrefilterSummary {
  PrefilterMethod method = PrefilterMethod::Auto;  ///< the method that made the map
  std::string detail;
  std::string lobe;       ///< canonical lobe name
  double maxError = 0.0;  ///< the bound it was built to
  /// The estimated error of the texels (0 when not estimated): the larger of the chosen method's
  /// solid-angle RMS of the relative error on the probes and its RMS where the signal is (the larger
  /// of the value-weighted RMS and the RMS within 5 degrees of the bright sources: a sun).
  double errorEstimate = 0.0;
  double errorEstimateMax = 0.0;        ///< largest probe error
  double errorEstimateRms = 0.0;        ///< the solid-angle RMS
  double errorEstimateHighlight = 0.0;  ///< the RMS where the signal is
  /// The finished map's bilinear lookups at the probes, as a renderer reads it (the same three RMS,
  /// each with two standard errors to spare, the largest): the texels' error plus their interpolation,
  /// which only the resolution lowers. -1: not measured (exact methods, estimation off).
  double lookupErrorEstimate = -1.0;
  double lookupErrorMax = -1.0;  ///< the largest lookup error at the probes
  bool errorEstimated = false;   ///< an estimate was made (never for reference and mirror, nor with estimation off)
  bool exact = false;            ///< every part was made by the reference sum or mirror resampling
  /// Known to meet the bound: exact, or estimated within maxError. False when the error is unknown
  /// (a fast method with estimation off): neither exact nor errorEstimated.
  bool metBound = false;
  int levels = 1;
  double seconds = 0.0;          ///< everything: setup, selection, probes, output, mips
  double estimateSeconds = 0.0;  ///< probes and their reference
  double outputSeconds = 0.0;    ///< evaluating the output texels with the chosen method
  double mipSeconds = 0.0;
  std::vector<PrefilterCandidate> candidates;
  std::vector<std::string> notes;

  std::string briefReport() const;
  nlohmann::json toJson() const;
};

/// Folds the summary of one part of a request made of several prefilter() runs (a fitted model's
/// Phong terms, an elevation stack's slices, a Fresnel decomposition's maps) into `into`, its
/// candidates and notes labelled "label: ". `first`: `part` is the first part (into takes its
/// error flags as they are; later parts can only lower exact and metBound). The error estimate
/// is the largest part's.
void mergePrefilterSummary(PrefilterSummary& into, const PrefilterSummary& part, const std::string& label, bool first);

/// A prefiltered map: level 0 (and the mip levels, if asked) of `map`.
struct PrefilteredMap {
  std::vector<Image> levels;
  std::shared_ptr<const Parameterization> map;  ///< level 0
  PrefilterSummary summary;
  /// A chain whose levels hold different lobes (prefilterGlossChain): one JSON object per level
  /// ({"lobe", "roughness" or "exponent", "method", "error_estimate"}), written as the
  /// metadata's "level_values" (levelValues, map_file.hpp); empty for a plain mip chain.
  std::vector<nlohmann::json> levelValues;
};

/// Prefilters `environment` with `lobe`. Throws Error(InvalidArgument) for bad options,
/// Error(Resource) above maxTexels, Error(Numerical) if a value comes out non-finite.
PrefilteredMap prefilter(const Environment& environment, const PrefilterLobe& lobe,
                         const PrefilterOptions& options = {}, const Context& context = {});

/// Prefilters with a fitted lobe model (brdf/lobes.hpp, `brdfbake fit`) in its prefiltered form
/// (Kautz & McCool; LobeMaterialMode::Prefiltered): per channel c,
///   L_o,c(r) = Σ_k C_kc (n_kc + 2)/(2 pi) ∫ max(0, r.l)^n_kc L(l) dω
///            = Σ_k C_kc (n_kc + 2)/(n_kc + 1) phong:n_kc[L](r),
/// channels taken to linear sRGB by LobeModel::rgbWeights and multiplied component-wise with the
/// environment's RGB (identity for R, G, B models). No diffuse term and no cosine: the renderer adds
/// k_d x irradiance and multiplies by n.r as Heidrich 2000 Eq. 19 does. One prefilter() run per distinct
/// exponent, each to `options` (its method and bound); the sum's relative error is at most the
/// largest run's, which the summary reports. Only constant models make one map: varying models
/// (lobes that change with elevation) throw Error(InvalidArgument); prefilterLobeModelStack
/// (prefilter_stack.hpp) makes their stack of maps over elevation. `name` is what metadata records.
PrefilteredMap prefilterLobeModel(const Environment& environment, const LobeModel& model, const std::string& name,
                                  const PrefilterOptions& options = {}, const Context& context = {});

/// The axis (environment frame) whose prefiltered value a texel of map direction `mapDirection`
/// holds, for the options' output (view rotation of sphere maps; normals for irradiance there).
Vec3 prefilterAxis(const Vec3& mapDirection, const PrefilterLobe& lobe, const PrefilterOptions& options);

/// The reference method at explicit axes (environment frame): ratio-form exact sum over every
/// texel of the environment, sub-sampled as described above.
std::vector<Rgb> prefilterReferenceAt(const Environment& environment, const PrefilterLobe& lobe,
                                      const std::vector<Vec3>& axes, const Context& context = {});

/// delta of the error metric: 1e-3 x lobe mass x the solid-angle mean of |L| over the environment.
double prefilterErrorFloor(const Environment& environment, const PrefilterLobe& lobe);

struct PrefilterError {
  double rms = 0.0;  ///< solid-angle-weighted RMS of the per-texel relative error
  double max = 0.0;  ///< largest per-texel relative error
};
/// Error of `result` against `reference` (both level-0 images of `map`) over the texels of
/// non-zero solid angle, weighted by texelSolidAngle.
PrefilterError prefilterError(const Image& result, const Image& reference, const Parameterization& map, double floor);

/// The metadata level `level` of `map` is written with (writePrefilteredMap): MapInfo::spec is `spec`
/// plus "prefilter" (see there) and the chain's "level_values".
MapInfo prefilteredMapInfo(const PrefilteredMap& map, nlohmann::json spec, int level);

/// Writes every level: level 0 at `path`, level k at mipLevelPath(path, k), each a map
/// (writeMap) whose MapInfo::spec is `spec` plus "prefilter": {lobe, method, detail, max_error,
/// error_estimate, error_metric, mip_level, mip_levels} (irradiance adds "irradiance_quantity": "E/pi"),
/// and map.levelValues as "level_values"; with MipLayout::Tiled the whole chain in
/// one tiled MIP-mapped OpenEXR at `path` (writeTiledMap; needs mip levels, a .exr path and a
/// power-of-two resolution, else Error(InvalidArgument)). Keys of an object `spec["prefilter"]`
/// are kept (prefilter_stack.hpp adds "elevation" and "fresnel" there).
MapWriteReport writePrefilteredMap(const PrefilteredMap& map, const std::filesystem::path& path, nlohmann::json spec,
                                   CubeLayout layout = CubeLayout::Cross, const WriteOptions& options = {},
                                   MipLayout mipLayout = MipLayout::Files);

}  // namespace brdfbake
