#pragma once
/// @file
/// Prefiltering an environment (docs/prefilter.md) in three steps, each usable alone:
///
///   PrefilterRequest request{.environment = sky, .lobe = PrefilterLobe::ggx(0.3),
///                            .parameterization = ParameterizationKind::Cube, .resolution = 64};
///   PrefilterResult made = prefilterEnvironment(request, context);   // in memory: made.map.levels
///   writePrefiltered(made, {.files = {"sky_ggx.ktx2"}});
///
/// and runPrefilter, what `brdfbake prefilter ENV --lobe L --to KIND -o OUT` does: the files read,
/// checked and written in one call. A spec's environment map is made by the same
/// prefilterEnvironment and writePrefiltered (run/spec_runner.hpp).

#include <brdfbake/brdf/fresnel.hpp>
#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/core/context.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/env/prefilter_stack.hpp>
#include <brdfbake/env/sh_irradiance.hpp>
#include <brdfbake/maps/sh.hpp>
#include <brdfbake/run/map_outputs.hpp>
#include <brdfbake/run/spec_runner.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace brdfbake {

/// One prefiltered map (or chain, stack, Fresnel decomposition), in memory. Fields are named in
/// messages as the spec keys and Python keywords are (snake_case).
struct PrefilterRequest {
  std::shared_ptr<const Environment> environment;  ///< radiance (loadEnvironment or makeEnvironment)
  /// The lobe: mirror, irradiance, phong:N, blinn:N, ggx:R (PrefilterLobe::parse). Ignored when a
  /// fitted model or a chain is given.
  PrefilterLobe lobe = PrefilterLobe::mirror();
  /// Fitted lobes (a fit.json's model, docs/fitting.md) in place of `lobe`: one map when the model is
  /// constant, a stack of `elevations` maps over view elevation when it varies with it.
  std::shared_ptr<const LobeModel> lobeModel;
  /// A gloss chain in place of `lobe`: level k of the map's mip chain holds its own lobe.
  std::optional<GlossChain> glossChain;
  /// How the map's metadata names the lobe ("" : the lobe's, the chain's, or "lobes").
  std::string lobeName;
  ParameterizationKind parameterization = ParameterizationKind::Sphere;  ///< the map's ("--to")
  int resolution = 256;                            ///< texels per side, hemisphere, face or rows, in [1, 65536]
  PrefilterMethod method = PrefilterMethod::Auto;  ///< auto | reference | sh | importance | direct
  double maxError = 0.01;                          ///< the bound each map is made to, in (0, 0.5]
  bool mips = false;                               ///< also the solid-angle mip chain
  Vec3 view = Vec3::UnitZ(), up = Vec3::UnitY();   ///< sphere maps: the eye's frame in the environment's
  int samplesPerTexel = 16;                        ///< the mirror lobe's footprint samples, in [1, 4096]
  int elevations = 8;                              ///< a varying model's stack, in [2, 64]
  /// A Fresnel decomposition (a specular lobe only): the specular map, the irradiance map and the
  /// Fresnel table F(cos theta), combined as `combine` says.
  std::optional<FresnelTerm> fresnel;
  FresnelCombine combine = FresnelCombine::Add;
  bool sh = false;  ///< irradiance only: also its 9 spherical-harmonic coefficients (E/pi)

  /// Throws Error::invalidField naming the field: "environment", "lobe" (a fitted model and a chain,
  /// irradiance with fresnel, ...), "parameterization", "resolution", "method", "max_error", "mips",
  /// "view", "up", "samples_per_texel", "elevations", "fresnel", "combine", "gloss_chain", "sh".
  void validate() const;
  /// The options prefilter() and its kin take.
  PrefilterOptions options() const;
  /// The name the map's metadata and report give the lobe.
  std::string describedLobe() const;
};

struct PrefilterResult {
  PrefilteredMap map;  ///< the map or chain; for a stack or a decomposition, its summary and first map
  std::optional<PrefilteredStack> stack;              ///< a varying model's maps over elevation
  std::optional<FresnelDecomposition> decomposition;  ///< specular, irradiance and Fresnel table
  std::optional<ShExpansion> sh;                      ///< irradiance as spherical harmonics (E/pi)
  std::optional<GlossChain> glossChain;               ///< the chain asked for, for reports
  std::string lobe;                                   ///< PrefilterRequest::describedLobe()
  /// What the map was made from, recorded in its report and SH file: the environment's file name
  /// (no folder), parameterization, resolution and how it was detected.
  nlohmann::json environment;

  std::string briefReport() const { return map.summary.briefReport(); }
  /// What `prefilter --json` prints of a map, but its files: parameterization, resolution, width,
  /// height, bake_path, bake_seconds, prefilter (the summary), environment, and elevations,
  /// fresnel (combine, irradiance_prefilter) or gloss_chain.
  nlohmann::json toJson() const;
};

/// The lobe of a request as the tool's flags (and Python's keywords) name it: --lobe, --chain,
/// --gloss-scale, --gloss-bias, --mip-count, --no-edge-fixup.
struct LobeArguments {
  /// mirror | irradiance | phong:N | blinn:N | ggx:R | lobes:FIT.json (parseLobeArgument), or phong |
  /// blinn with glossScale (cmft's gloss chain).
  std::string lobe;
  std::optional<std::string> chain;  ///< "ggx": cmgen's GGX chain
  std::optional<double> glossScale, glossBias;
  std::optional<int> mipCount;
  bool edgeFixup = true;

  /// Sets the request's lobe, lobeModel, lobeName and glossChain (a FIT.json relative to
  /// `baseDirectory`). Throws Error::invalidField: "lobe" (none, unknown, beside a chain), "chain",
  /// "gloss_chain" (a chain's settings without a chain, or a GGX chain's with scale or bias).
  void apply(PrefilterRequest& request, const std::filesystem::path& baseDirectory = ".") const;
};

/// Makes the map in memory: validate(), then prefilter, prefilterGlossChain, prefilterLobeModel,
/// prefilterLobeModelStack or prefilterFresnelDecomposition on `context`, and irradianceSh when
/// asked. Throws what validate() and they throw.
PrefilterResult prefilterEnvironment(const PrefilterRequest& request, const Context& context = {});

/// Every file writePrefiltered writes for `request` to `outputs` (and `sh`), with their roles, for
/// checks before any work.
std::vector<FilePlan::Entry> plannedFiles(const PrefilterRequest& request, const MapOutputs& outputs,
                                          const std::optional<ShOutput>& sh = std::nullopt);

/// Writes the result to every file of `outputs` (each level, slice and map of it), and the SH
/// coefficients to `sh`. `spec` is what the metadata records as the spec the map was made from (a
/// spec's map object; null: the request's description). Throws Error(Io) for a file that cannot
/// be written.
MapWriteReport writePrefiltered(const PrefilterResult& result, const MapOutputs& outputs,
                                const std::optional<ShOutput>& sh = std::nullopt, nlohmann::json spec = nullptr);

/// What `brdfbake prefilter ENV -o OUT` takes.
struct PrefilterFiles {
  std::filesystem::path environment;         ///< EXR, HDR, ... (loadEnvironment)
  std::optional<ParameterizationKind> from;  ///< the environment's parameterization if plain
  PrefilterRequest request;                  ///< the environment is filled in
  MapOutputs outputs;
  std::optional<ShOutput> sh;
};

/// Checks every file before any work, reads the environment, prefilters and writes. Returns the
/// map's entry as `bake --json` prints a map's. Errors name the file or the request's field.
MapResult runPrefilter(const PrefilterFiles& files, const Context& context = {});

}  // namespace brdfbake
