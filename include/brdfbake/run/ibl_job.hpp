#pragma once
/// @file
/// Engine-ready image-based lighting from one environment (docs/engines.md), in three steps:
///
///   IblResult ibl = makeIbl({.environment = sky, .resolution = 256}, context);   // in memory
///   writeIbl(ibl, {.folder = "out", .stem = "sky", .format = "ktx2"});
///
/// and runIbl, what `brdfbake ibl ENV --out-dir OUT` does (files checked, read, made and written in
/// one call). The files, in one container format:
///
/// | role | file | holds |
/// |---|---|---|
/// | specular | STEM_ggx.EXT | a cube texture whose level k of L holds ggx:R_k, R_k = k / (L - 1) (cmgen's GGX chain;
/// level 0 the mirror), the roughness per level in "level_values" | | irradiance | STEM_irradiance.EXT | a small cube
/// of E/pi at the normal | | irradiance_sh | STEM_sh.json (and STEM_sh.txt with cmgen's format) | 9 RGB SH coefficients
/// of E/pi | | dfg | STEM_dfg.EXT | the split-sum DFG table over (n.v, R) (dfg_table.hpp) | | skybox | STEM_skybox.EXT
/// | the environment resampled into a cube |
///
/// The files are written as one set: each to a hidden temporary first, and all renamed into place
/// only once every one is complete (OutputBatch), so a failure leaves the previous set whole.

#include <brdfbake/env/dfg_table.hpp>
#include <brdfbake/run/prefilter_job.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake {

/// What to make; fields are named in messages as the tool's flags (--irradiance-resolution) and the
/// Python keywords (irradiance_resolution) are.
struct IblRequest {
  std::shared_ptr<const Environment> environment;
  int resolution = 256;           ///< the GGX chain's level-0 face size, a power of two in [1, 8192]
  std::optional<int> levels;      ///< chain levels; only the whole chain (down to 1 texel) is accepted
  int irradianceResolution = 32;  ///< faces of the irradiance cube, a power of two in [1, 1024]
  int skyboxResolution = 512;     ///< faces of the skybox cube, a power of two in [1, 8192]
  int dfgSize = 128;              ///< DFG table texels per side, in [1, 4096]
  DfgForm dfgForm = DfgForm::SingleScattering;
  double maxError = 0.01;  ///< the bound of every prefiltered level, in (0, 0.5]

  /// Throws Error::invalidField naming the field ("resolution", "levels", "irradiance_resolution",
  /// "skybox_resolution", "dfg_size", "max_error", "environment").
  void validate() const;
};

struct IblResult {
  PrefilterResult specular;    ///< the GGX chain: specular.map.levels[k], a cube cross of N >> k
  PrefilterResult irradiance;  ///< the irradiance cube, with irradiance.sh (E/pi)
  PrefilterResult skybox;      ///< the environment resampled into a cube
  Image dfg;                   ///< the DFG table: n.v along x, roughness along y (metadata "dfg_table")

  std::string briefReport() const;
  nlohmann::json toJson() const;
};

/// Makes every part in memory on `context` (progress per part; cancellation). Throws what
/// validate() and prefilterEnvironment throw.
IblResult makeIbl(const IblRequest& request, const Context& context = {});

/// Where the files go: FOLDER/STEM_ggx.EXT and the rest (see @file).
struct IblOutputs {
  std::filesystem::path folder;               ///< created if missing
  std::string stem = "ibl";                   ///< the files' stem: a name, not a path
  std::string format = "ktx2";                ///< ktx2 | ktx | dds | exr
  std::optional<TexelFormat> texelFormat;     ///< ktx2, ktx, dds only (default rgba16f)
  bool shCmgen = false;                       ///< also STEM_sh.txt, the 9 lines cmgen prints
  std::vector<std::filesystem::path> inputs;  ///< never overwritten

  /// Throws Error::invalidField ("out_dir", "stem", "format", "texel_format").
  void validate() const;
  std::filesystem::path file(const std::string& suffix, const std::string& extension) const;
  /// The container's extension: ".ktx2", ".ktx", ".dds" or ".exr".
  std::string extension() const;
};

/// One file written, with its role (see @file).
struct IblFile {
  std::string role;
  std::filesystem::path file;
  std::string description;
  nlohmann::json details;  ///< e.g. the chain's levels, the table's axes
};

/// What writeIbl and runIbl report.
struct IblReport {
  std::filesystem::path environment;  ///< its file name
  std::vector<IblFile> outputs;
  std::vector<MapResult> maps;  ///< the three cube maps' entries, as `bake --json` prints maps
  std::vector<std::filesystem::path> files;
  std::vector<std::string> notes;

  std::string briefReport() const;
  /// {"environment", "files": [{"role", "file", "description", ...details}], "maps": [...], "notes"}.
  nlohmann::json toJson() const;
};

/// Every file writeIbl writes, with its role, for checks before any work.
std::vector<FilePlan::Entry> plannedFiles(const IblOutputs& outputs);

/// Writes every file as one set (see @file). Throws Error(Io) when one cannot be written: then none
/// is replaced.
IblReport writeIbl(const IblResult& result, const IblOutputs& outputs);

/// What `brdfbake ibl ENV --out-dir OUT` takes.
struct IblFiles {
  std::filesystem::path environment;
  std::optional<ParameterizationKind> from;
  IblRequest request;  ///< the environment is filled in
  IblOutputs outputs;  ///< the stem defaults to the environment's
};

/// Validates, checks every file, reads the environment, makes and writes the set; nothing is written
/// or replaced on failure or cancellation.
IblReport runIbl(const IblFiles& files, const Context& context = {});

}  // namespace brdfbake
