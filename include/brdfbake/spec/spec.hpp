#pragma once
/// @file
/// Bake specs: the JSON files `brdfbake bake` reads. See docs/spec.md for the format.

#include <brdfbake/bake/auto_config.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/bake/map_function.hpp>
#include <brdfbake/env/camera.hpp>
#include <brdfbake/env/material_under_environment.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/env/prefilter_stack.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/maps/parameterization.hpp>
#include <brdfbake/spec/material_spec.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace brdfbake {

/// "environment": {...} in place of "material" and "lights": a prefiltered environment map
/// (docs/prefilter.md): the map's parameterization, resolution, samples_per_texel (mirror lobe)
/// and layout apply as for any map.
struct EnvironmentMapSpec {
  std::filesystem::path file;  ///< "file", resolved against the spec's folder
  std::string lobeName;        ///< "lobe" as written: "phong:100", "lobes:FIT.json", ...
  /// The lobe, parsed: an analytic lobe (PrefilterLobe::parse) or the fitted model read from
  /// "lobes:FIT.json".
  std::variant<PrefilterLobe, std::shared_ptr<const LobeModel>> lobe = PrefilterLobe::mirror();
  PrefilterMethod method = PrefilterMethod::Auto;  ///< "method" (default "auto")
  double maxError = 0.01;                          ///< "max_error" (default 0.01)
  bool mips = false;                               ///< "mips": also write STEM_mipK.EXT
  /// "mip_layout": "files" (default: STEM_mipK.EXT) | "tiled" (the chain inside OUTPUT, one tiled
  /// MIP-mapped OpenEXR; needs "mips", a .exr output and a power-of-two resolution).
  MipLayout mipLayout = MipLayout::Files;
  std::optional<ParameterizationKind> from;       ///< "from": parameterization of a plain image
  Vec3 view = Vec3::UnitZ(), up = Vec3::UnitY();  ///< "view", "up": sphere maps only
  /// "elevations" (varying lobe models only, in [2, 64], default 8): maps in the stack over view
  /// elevation, written as STEM_elev0.EXT ... (prefilter_stack.hpp).
  int elevations = 8;
  /// "fresnel" (a specular lobe only): the Fresnel term as the fresnel material's "fresnel" object;
  /// then OUTPUT is the specular map, STEM_irradiance.EXT the irradiance map and STEM_fresnel.EXT
  /// the 1-D Fresnel table of `resolution` texels (prefilterFresnelDecomposition).
  std::optional<FresnelTerm> fresnel;
  FresnelCombine combine = FresnelCombine::Add;  ///< "combine": "add" (default) | "mix"; needs "fresnel"
  /// "gloss_chain": {"scale": S, "bias": B (default 1), "levels": M (default: down to 1 texel, at most 16),
  /// "edge_fixup": true} with "lobe": "phong" or "blinn" (no exponent): a gloss mip chain as cmft makes
  /// it, level k at resolution N >> k filtered with the exponent 2^(S g_k + B), g_k = 1 - k/(M - 1)
  /// (glossLevelExponents); with "lobe": "ggx" ({"levels", "edge_fixup"} only): cmgen's GGX chain, level k
  /// holding ggx:R_k, R_k = k / (M - 1) (ggxChainRoughness; level 0 the mirror). Written as the map's mip
  /// levels STEM_mipK.EXT, or with "mip_layout": "tiled" (M must then reach 1 texel) as one file's levels,
  /// each level's roughness or exponent in the metadata's "level_values". `chainLobes` holds level k's lobe;
  /// "edge_fixup": false keeps cube texels unaveraged (cmft's --edgeFixup none).
  std::optional<GlossChain> glossChain;
  std::vector<PrefilterLobe> chainLobes;
  /// "sh_output": FILE.json, with "lobe": "irradiance": also the irradiance as 3 bands of spherical
  /// harmonics (env/sh_irradiance.hpp), resolved (and placed under an output folder) like "output".
  std::optional<std::filesystem::path> shOutput;
  /// "sh_format": "brdfbake" (default: the JSON of irradianceShToJson, FILE.json) or "cmgen" (the 9 RGB
  /// lines cmgen --sh-shader prints, irradianceShCmgenText, FILE.txt).
  bool shCmgen = false;

  /// The analytic lobe, or null for a fitted model.
  const PrefilterLobe* analyticLobe() const { return std::get_if<PrefilterLobe>(&lobe); }
  /// The fitted model, or null for an analytic lobe.
  const LobeModel* lobeModel() const {
    const auto* model = std::get_if<std::shared_ptr<const LobeModel>>(&lobe);
    return model ? model->get() : nullptr;
  }
};

/// "environment": {"file", "from", "method", "max_error", "max_relative_error"} beside "material" (in place of
/// "lights"), and the map's "camera": the material lit by an environment (docs/matcap.md), made by
/// bakeUnderEnvironment.
struct EnvironmentLighting {
  std::filesystem::path file;                                    ///< "file", resolved against the spec's folder
  std::optional<ParameterizationKind> from;                      ///< "from": parameterization of a plain image
  UnderEnvironmentMethod method = UnderEnvironmentMethod::Auto;  ///< "method": "auto" | "sampled" | "reference"
  double maxError = 0.01;                                        ///< "max_error", in (0, 0.5]
  std::optional<double> maxRelativeError;  ///< "max_relative_error", in (0, 10] (default 3 x max_error)
  /// The map's "camera": {"forward": [x, y, z], "up": [x, y, z]} (orthonormal) or {"yaw": degrees,
  /// "pitch": degrees}; default the environment's axes (viewer on +z, up +y).
  CameraFrame camera;
};

/// "material" and "lights" (or "environment"): a map baked from a material model (docs/materials.md),
/// with the extra files some models write beside it.
struct MaterialMapSpec {
  /// The material; null while `deferredFit` is pending (MapSpec::prepare() makes it).
  std::shared_ptr<const Material> material;
  /// A "measured" material's fit, parsed but not run yet (see MapSpec::prepare()).
  std::optional<DeferredFit> deferredFit;
  std::vector<DirectionalLight> lights;
  bool lightAtEye = false;  ///< a light was given as "direction": "eye"
  /// Set when the material is lit by an environment instead of lights (no "lights", "mips" or
  /// "fresnel_table_output" then): bakeUnderEnvironment makes the map, makeFunction() refuses it.
  std::optional<EnvironmentLighting> environment;
  /// "mips": true (silhouette sphere maps only): also write the hand-made mip levels 1.. as
  /// STEM_mip1.EXT, STEM_mip2.EXT, ... beside the output (docs/materials.md).
  bool mips = false;
  /// "mip_layout" beside "mips": "files" (default) | "tiled" (the whole chain in the map's output,
  /// one tiled MIP-mapped OpenEXR: writeTiledMap).
  MipLayout mipLayout = MipLayout::Files;
  /// "fresnel_table_output" (fresnel model only; "profile_output", its former name, is still
  /// read): also write the 1-D Fresnel table F(cos theta), `resolution` x 1 texels, to this path; a
  /// relative path is taken relative to the folder of the map's output.
  std::optional<std::filesystem::path> fresnelTableOutput;

  /// The material model's name ("measured" while its fit is pending).
  std::string modelName() const;
};

/// What a map holds: a material baked, or an environment prefiltered.
using MapContent = std::variant<MaterialMapSpec, EnvironmentMapSpec>;

/// One lambda per kind, for std::visit over MapContent:
///   std::visit(Overloaded{[](const MaterialMapSpec& m) {...}, [](const EnvironmentMapSpec& e) {...}}, map.content)
template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

/// One entry of "maps", validated: what every map has (output, parameterization, resolution, view,
/// files), and its content, one of its kinds (std::visit it, or ask materialMap() / environmentMap()).
struct MapSpec {
  std::string jsonPath;          ///< "maps[0]", for messages
  std::filesystem::path output;  ///< resolved against the spec's folder; the first of "outputs"
  /// "outputs": [FILE, ...] in place of "output" (docs/spec.md): the map is made once and written to
  /// each file, its format chosen by the extension. These are the files after the first (`output`),
  /// resolved the same way; empty when the map gives "output".
  std::vector<std::filesystem::path> moreOutputs;
  bool outputList = false;  ///< the map gave "outputs" (a list), not "output"
  /// "texel_format": how the map's .ktx2, .ktx and .dds outputs store texels (toString(TexelFormat)
  /// names: "rgba16f" (the default), "rgba32f", "rgb16f", "rgb32f", "rgb9e5", "rg11b10f"); the
  /// other formats ignore it, but at least one output must be a texture container.
  std::optional<TexelFormat> texelFormat;
  ParameterizationKind parameterization = ParameterizationKind::Sphere;
  /// "parameterization": "profile": a 1-D radial profile (bake/radial_profile.hpp) instead of a
  /// 2-D map, for materials radially symmetric about one axis; eye space as for sphere maps
  /// (`parameterization` stays Sphere for the view rules). Material maps only.
  bool radialProfile = false;
  int resolution = 256;
  int samplesPerTexel = 16;
  Vec3 view = Vec3::UnitZ();  ///< view vector in the map frame (+z for sphere maps)
  bool viewGiven = false;     ///< the spec fixed the view ("view": [x, y, z])
  CubeLayout cubeLayout = CubeLayout::Cross;
  nlohmann::json raw;     ///< the map's JSON as written, stored in the map's metadata
  std::string specLabel;  ///< the spec's file name (parseBakeSpec's label), for messages
  /// The material map ("material", "lights") or the prefiltered environment map ("environment").
  MapContent content;

  /// The content if it is a material map, else null.
  const MaterialMapSpec* materialMap() const { return std::get_if<MaterialMapSpec>(&content); }
  MaterialMapSpec* materialMap() { return std::get_if<MaterialMapSpec>(&content); }
  /// The content if it is a prefiltered environment map, else null.
  const EnvironmentMapSpec* environmentMap() const { return std::get_if<EnvironmentMapSpec>(&content); }

  /// "auto" values: the tool picks the cheapest configuration meeting `maxError`.
  struct AutoSelection {
    bool parameterization = false, resolution = false, samplesPerTexel = false;
    double maxError = 0.0;  ///< "max_error": RMS lookup error relative to the peak
  } autoSelect;
  /// "view": "fixed" (one view, +z: a sphere map suffices) or "free" (the viewer moves: only
  /// maps indexed by reflected direction, of view-independent materials).
  enum class ViewNeed { Unspecified, Fixed, Free } viewNeed = ViewNeed::Unspecified;

  /// The files this map reads (environment, fit.json, measured table) with the JSON paths that
  /// name them; filled by parsing.
  std::vector<FilePlan::Entry> inputs;
  /// Notes about the inputs found while parsing (e.g. negative measured values clamped to 0),
  /// printed and reported with the map.
  std::vector<std::string> notes;
  /// Every file the map is written to: `output`, then `moreOutputs`; none for a map made in memory.
  std::vector<std::filesystem::path> outputs() const;
  /// The map names no output (parseBakeSpec with `inMemory`): it is made in memory only.
  bool inMemory() const { return output.empty(); }
  /// How progress and reports name the map: its output's file name, or "in memory".
  std::string outputName() const { return inMemory() ? "in memory" : output.filename().string(); }
  /// The JSON path naming outputs()[i]: "maps[0].output", or "maps[0].outputs[i]".
  std::string outputJsonPath(std::size_t i) const;
  /// The write options for outputs()[i]: `readFiles` (never overwritten), and `texelFormat` for a texture container.
  WriteOptions writeOptionsFor(std::size_t i, std::vector<std::filesystem::path> readFiles) const;
  /// Why outputs()[i] cannot hold this map ("" if it can): containerProblem with the map's shape
  /// (parameterization, resolution, a whole mip chain in the file, texel format).
  std::string outputProblem(std::size_t i) const;

  /// Every file making this map writes or replaces: the output or its cube faces, mip levels,
  /// elevation slices, Fresnel maps, "fresnel_table_output", and the metadata sidecar FILE.json beside
  /// each, with roles such as "maps[0].output (mip level 2)".
  std::vector<FilePlan::Entry> plannedOutputs() const;

  bool anyAuto() const { return autoSelect.parameterization || autoSelect.resolution || autoSelect.samplesPerTexel; }
  /// The candidates and target for chooseConfiguration (fixed values become one-element lists).
  AutoOptions autoOptions() const;

  /// Makes what parsing deferred (a material map's "measured" fit, on `context`) and checks the rules that need the
  /// made material (lights, view, profile symmetry, sampling), throwing Error(InvalidInput) that names the spec and
  /// JSON path. Does nothing when nothing is pending. Call it before makeFunction().
  void prepare(const Context& context = {});
  /// The material model's name (MaterialMapSpec::modelName; empty for environment maps).
  std::string modelName() const;

  /// The prefilter options an environment map asks for (parameterization, resolution, mips,
  /// method, max_error, view, up, mirror samples, elevations). Throws Error(InvalidArgument) for material maps.
  PrefilterOptions prefilterOptions() const;

  /// The function the baker integrates. Throws Error(InvalidArgument) for environment maps, for
  /// materials lit by an environment (bakeUnderEnvironment makes those) and while a fit is pending
  /// (call prepare() first).
  std::shared_ptr<const MapFunction> makeFunction() const;

  /// The environment lighting of a material map lit by one, else null.
  const EnvironmentLighting* environmentLighting() const;
  /// The options a material lit by an environment asks for (parameterization, resolution, view,
  /// camera, samples_per_texel, method, max_error). Throws Error(InvalidArgument) for other maps.
  UnderEnvironmentOptions underEnvironmentOptions() const;
};

struct BakeSpec {
  std::filesystem::path file;  ///< where it was read from (empty for in-memory specs)
  std::vector<MapSpec> maps;
};

/// A prefilter lobe as the tool and specs name it: "mirror", "irradiance", "phong:N", "blinn:N",
/// "ggx:R" (PrefilterLobe::parse) or "lobes:FIT.json" (the fitted model of `brdfbake fit`, FIT relative
/// to `baseDirectory`).
struct LobeArgument {
  std::variant<PrefilterLobe, std::shared_ptr<const LobeModel>> lobe = PrefilterLobe::mirror();
  std::filesystem::path fitFile;  ///< the fit.json read, or empty
};
/// Throws Error(InvalidArgument) naming the accepted forms, and what readFitFile throws.
LobeArgument parseLobeArgument(const std::string& text, const std::filesystem::path& baseDirectory);

/// Parses and validates a spec. `baseDirectory` resolves relative paths. With `inMemory` a map may
/// leave out "output" and "outputs" (then it is made in memory only, MapSpec::inMemory, and may not ask
/// for files of its own: "mips" beside it, "fresnel_table_output", "sh_output", Fresnel maps, an
/// elevation stack); without it, "output" is required. Throws Error(InvalidInput) whose message starts
/// with `label` (usually the file name) and names the JSON path.
BakeSpec parseBakeSpec(const nlohmann::json& document, const std::filesystem::path& baseDirectory,
                       const std::string& label = "spec", bool inMemory = false);

/// The environment a map reads ("environment": {"file", "from"}: prefiltered, or lighting a material),
/// read and checked by loadEnvironment; its errors name the spec and the JSON path of
/// "environment.file" (missing, unreadable, not an image, a size no parameterization has). Throws
/// Error(InvalidArgument) for a map without an environment. For checks before any work.
Environment loadMapEnvironment(const MapSpec& map);

/// Makes a material map lit by an environment (MapSpec::environmentLighting; prepare() first):
/// shadeUnderEnvironment with the map's options, on `context`. Write it with
/// writeUnderEnvironmentMap(result, map.output, map.raw, map.cubeLayout, ...). Throws
/// Error(InvalidArgument) for other maps or a pending fit, and shadeUnderEnvironment's errors.
MaterialUnderEnvironment bakeUnderEnvironment(const MapSpec& map, const Environment& environment,
                                              const Context& context = {});

/// Writes the extra files a map asks for besides its image ("mips", "fresnel_table_output"; see MapSpec),
/// each written with writeImage/writeMap semantics. `bakeOptions` is used for baking mip levels, on
/// `context`. Returns the files written and notes (nothing if the map asks for no extras).
MapWriteReport writeMapExtras(const MapSpec& map, const BakeOptions& bakeOptions, const WriteOptions& writeOptions = {},
                              const Context& context = {});

/// The files baking `spec` reads and writes, for FilePlan::check(): `specFile` (none when empty),
/// every map's inputs and planned outputs, with `outputFolder` (when given) as the folder outputs
/// must stay in.
FilePlan planSpecFiles(const BakeSpec& spec, const std::filesystem::path& specFile,
                       const std::optional<std::filesystem::path>& outputFolder);

/// Reads a spec file. Throws Error(Io) if unreadable, Error(InvalidInput) with file, line and
/// column for JSON syntax errors, and the errors of parseBakeSpec.
BakeSpec loadBakeSpec(const std::filesystem::path& file, bool inMemory = false);

}  // namespace brdfbake
