#pragma once
/// @file
/// Prefilter requests that make several maps (docs/prefilter.md):
///
/// - **Elevation stacks** for fitted lobe models whose lobes vary with the view elevation
///   (LobeElevation::Varying, brdf/lobes.hpp) or whose weights follow a colour profile (taken at the
///   lobes' centre, theta_d = theta_v: LobeModel::variesWithView). A varying model's prefiltered form
///   Σ_k C_k(u) (n_k(u) + 2)/(2 pi) max(0, r.l)^n_k(u) depends on r and on u = n.v, so it needs a
///   3-D table: K maps, slice j being the constant-model map (prefilterLobeModel) of the model frozen
///   at u_j (LobeModel::prefilterFormAt). The slices are uniform in the model's own elevation
///   coordinate t = ln(u / minCos) / ln(maxCos / minCos) (LobeModel::elevationCoordinate), in which
///   ln C and ln n are quadratic: t_j = j / (K - 1), u_j = minCos (maxCos / minCos)^t_j, slice 0 at
///   the most grazing fitted view, slice K - 1 at the most normal. A renderer computes t from n.v,
///   clamps it to [0, 1] (the model holds its parameters beyond the fitted range), and interpolates
///   linearly in t between slices floor(t (K - 1)) and the next.
/// - **Fresnel decomposition** (Heidrich 2000 section 3.1.1): the specular map L_m (mirror or a glossy
///   lobe), the irradiance map E and the 1-D Fresnel texture F(cos theta) from one request; a
///   renderer combines them as L = F L_m + k_d E' ("add") or F L_m + (1 - F) k_d E' ("mix"),
///   with F = F(n.v), E' = E/pi the irradiance map's value and k_d its diffuse albedo
///   (combineFresnelDecomposition).

#include <brdfbake/brdf/fresnel.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/io/map_file.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace brdfbake {

/// The view cosines u_j of the `count` slices of a varying model's stack (see @file): u_j =
/// minCos (maxCos / minCos)^(j / (count - 1)), exactly minCos and maxCos at the ends. count >= 2.
std::vector<double> elevationSliceCosines(const LobeModel& model, int count);

/// A varying lobe model prefiltered into a stack of maps over view elevation.
struct PrefilteredStack {
  std::vector<double> cosines;         ///< u_j, the view cosine of each slice
  std::vector<double> coordinates;     ///< t_j = j / (K - 1), the model's elevation coordinate
  std::vector<PrefilteredMap> slices;  ///< slice j: prefilterLobeModel of model.prefilterFormAt(u_j)
  PrefilterSummary summary;            ///< all slices: the largest error estimate, the total seconds
  double minCos = 0.0, maxCos = 1.0;   ///< the model's fitted elevation range
};

/// Prefilters a Varying lobe model into options.elevations slices (see @file), each to `options`
/// (method, bound, mips). Throws Error(InvalidArgument) for a Constant model (one map suffices:
/// prefilterLobeModel) and everything prefilterLobeModel throws.
PrefilteredStack prefilterLobeModelStack(const Environment& environment, const LobeModel& model,
                                         const std::string& name, const PrefilterOptions& options = {},
                                         const Context& context = {});

/// STEM_elevJ.EXT beside `path`: where slice j of a stack is written.
std::filesystem::path elevationSlicePath(const std::filesystem::path& path, int slice);

/// Writes slice j with writePrefilteredMap at elevationSlicePath(path, j) (its mip levels, if any,
/// at STEM_elevJ_mipL.EXT); nothing is written at `path` itself. Each slice's "prefilter" metadata
/// has "elevation": {slice, slices, cos_theta, t, min_cos, max_cos, interpolation}.
MapWriteReport writePrefilteredStack(const PrefilteredStack& stack, const std::filesystem::path& path,
                                     nlohmann::json spec, CubeLayout layout = CubeLayout::Cross,
                                     const WriteOptions& options = {}, MipLayout mipLayout = MipLayout::Files);

/// The three outputs of a Fresnel decomposition (see @file).
struct FresnelDecomposition {
  PrefilteredMap specular;    ///< L_m: the environment filtered with the specular lobe
  PrefilteredMap irradiance;  ///< E(n)/pi = (1/pi) ∫ L max(0, n.l) dω (1 for L = 1), same map and options
  std::vector<Rgb> table;     ///< fresnelTable: entry i holds F at cos theta = (i + 0.5) / size
  FresnelTerm fresnel = FresnelTerm::dielectric(Rgb::Constant(1.5));
  FresnelCombine combine = FresnelCombine::Add;
};

/// Prefilters `environment` with `specular` (mirror, phong, blinn or ggx: not irradiance) and with
/// the irradiance lobe, both to `options`, and tabulates `fresnel` over `tableSize` texels (>= 1).
/// Throws Error(InvalidArgument) for an irradiance specular lobe or a bad size.
FresnelDecomposition prefilterFresnelDecomposition(const Environment& environment, const PrefilterLobe& specular,
                                                   const FresnelTerm& fresnel, FresnelCombine combine,
                                                   const PrefilterOptions& options, int tableSize,
                                                   const Context& context = {});

/// What a renderer computes at a surface point from the three outputs: F = F(n.v) (the table),
/// L_m = the specular map at the reflected direction r, E = the irradiance map at the normal n
/// (a sphere map holds both at r), and its own diffuse albedo k_d:
///   add: F L_m + k_d E',   mix: F L_m + (1 - F) k_d E',   E' = E/pi, what the irradiance map holds.
Rgb combineFresnelDecomposition(FresnelCombine combine, const Rgb& fresnel, const Rgb& specular, const Rgb& irradiance,
                                const Rgb& diffuseAlbedo);

/// cmft's gloss mapping (Manesku's cmft, cubemapfilter.cpp, specularPowerFor): mip level k of
/// `count` gets the Phong exponent 2^(scale g_k + bias), glossiness g_k = max(0, 1 - k / (count - 1))
/// (g = 1 for a single level). Scale 10, bias 1 and 8 levels give 2048, 761, 283, 105, 39, 14.5, 5.4
/// and 2. Throws Error(InvalidArgument) unless count is in [1, 16] and scale and bias are finite
/// with every exponent in [0, 1e6].
std::vector<double> glossLevelExponents(int count, double scale, double bias);

/// The perceptual roughness of level k of a GGX chain of `count` levels: R_k = k / (count - 1)
/// (0 for a single level), the mapping of Filament's cmgen (its level k of log2(N) + 1 holds
/// linear roughness (k / (count - 1))^2, i.e. perceptual roughness k / (count - 1)) and of Khronos'
/// glTF-IBL-Sampler (roughness = level / (levels - 1)): a renderer reads roughness R at
/// lod = R (count - 1). Throws Error(InvalidArgument) unless count is in [1, 16].
std::vector<double> ggxChainRoughness(int count);

/// The lobes of a GGX chain: the mirror lobe at R = 0 (level 0: the environment resampled, which
/// is GGX's limit), ggx:R_k above.
std::vector<PrefilterLobe> ggxChainLobes(int count);

/// A glossy mip chain to make (prefilterGlossChain): cmft's Phong or Blinn-Phong chain
/// (glossLevelExponents) or cmgen's GGX chain (ggxChainLobes).
struct GlossChain {
  enum class Lobe { Phong, Blinn, Ggx };
  Lobe lobe = Lobe::Ggx;
  double scale = 10.0, bias = 1.0;  ///< Phong and Blinn: level k's exponent 2^(scale g_k + bias)
  /// Levels, 0 = down to 1 texel (at most 16).
  int levels = 0;
  /// Cube maps: average each edge texel with its neighbour across the edge (cmft's --edgeFixup).
  bool edgeFixup = true;

  /// "phong", "blinn" or "ggx".
  std::string lobeName() const;
  /// The levels of a chain whose level 0 has `resolution` texels: `levels`, or every level down to
  /// 1 texel (at most 16).
  int levelCount(int resolution) const;
  /// Level k's lobe. Throws Error(InvalidArgument) as glossLevelExponents and ggxChainRoughness do.
  std::vector<PrefilterLobe> lobes(int resolution) const;
};

/// A glossy mip chain (as cmft and CubeMapGen make them, or cmgen's GGX chain): level k is the
/// environment filtered with lobes[k] at resolution max(1, options.resolution >> k), each level a
/// prefilter() run to options' method and bound (options.mips must be off: the levels are the
/// chain), cube edges fixed and paraboloid borders aligned at every level. A mirror lobe (a GGX
/// chain's level 0) resamples the environment (method auto). The summary's error estimate is the
/// largest level's, its seconds the total; `levels` is lobes.size(); `levelValues` holds, per level,
/// {"lobe", "roughness" and "alpha" (GGX, mirror 0) or "exponent" (Phong), "method",
/// "error_estimate" (null if exact or not estimated), "exact"}. Throws Error(InvalidArgument) for
/// no lobes, more levels than the resolution halves into, an irradiance lobe, or options.mips, and
/// everything prefilter() throws.
PrefilteredMap prefilterGlossChain(const Environment& environment, const std::vector<PrefilterLobe>& lobes,
                                   const PrefilterOptions& options = {}, const Context& context = {});

/// What a prefilter run writes, for prefilterOutputFiles.
struct PrefilterOutputs {
  ParameterizationKind parameterization = ParameterizationKind::Sphere;
  int resolution = 256;
  bool mips = false;  ///< every mip level as STEM_mipK.EXT
  CubeLayout layout = CubeLayout::Cross;
  MipLayout mipLayout = MipLayout::Files;  ///< Tiled: the mip levels inside each map's file
  int mipLevels = 0;                       ///< with mips: the levels written (a gloss chain's count), 0 = all
  int elevationSlices = 0;                 ///< a stack over elevation (STEM_elevJ.EXT), or 0
  bool fresnel = false;                    ///< a Fresnel decomposition (irradiance map and Fresnel table too)
};

/// Every file writePrefilteredMap, writePrefilteredStack or writeFresnelDecomposition writes or
/// replaces for `output` (mapOutputFiles of each level, slice and map), with roles built on `role`.
std::vector<FilePlan::Entry> prefilterOutputFiles(const std::filesystem::path& output, const PrefilterOutputs& outputs,
                                                  const std::string& role);

/// STEM_irradiance.EXT and STEM_fresnel.EXT beside `output` (the specular map).
std::filesystem::path fresnelIrradiancePath(const std::filesystem::path& output);
std::filesystem::path fresnelTablePath(const std::filesystem::path& output);

/// Writes the specular map at `output`, the irradiance map at fresnelIrradiancePath(output) (both
/// with writePrefilteredMap, mip levels included) and the Fresnel table, a size x 1 image
/// (fresnelTableImage: "parameterization": "fresnel_table", looked up at n.v), at
/// fresnelTablePath(output). Both maps' "prefilter"
/// metadata has "fresnel": {role, combine, formula, specular, irradiance, table (file names),
/// table_size, table_texels, f0}.
MapWriteReport writeFresnelDecomposition(const FresnelDecomposition& decomposition, const std::filesystem::path& output,
                                         nlohmann::json spec, CubeLayout layout = CubeLayout::Cross,
                                         const WriteOptions& options = {}, MipLayout mipLayout = MipLayout::Files);

}  // namespace brdfbake
