#pragma once
/// @file
/// Engine-ready image-based lighting from one environment (docs/engines.md): what `brdfbake ibl ENV
/// --out-dir OUT` does, as one call. It writes, in one container format:
///
/// | role | file | holds |
/// |---|---|---|
/// | specular | STEM_ggx.EXT | a cube texture whose level k of L holds ggx:R_k, R_k = k / (L - 1) (cmgen's GGX chain;
/// level 0 the mirror), the roughness per level in "level_values" | | irradiance | STEM_irradiance.EXT | a small cube
/// of E/pi at the normal | | irradiance_sh | STEM_sh.json (and STEM_sh.txt with cmgen's format) | 9 RGB SH coefficients
/// of E/pi | | dfg | STEM_dfg.EXT | the split-sum DFG table over (n.v, R) (dfg_table.hpp) | | skybox | STEM_skybox.EXT
/// | the environment resampled into a cube |
///
/// The three cube maps are one spec of three "environment" maps (iblSpec) run by runSpec, so the whole
/// request, the DFG table's file included, is validated and every file checked before anything is
/// computed; then the maps are made and the table last.

#include <brdfbake/env/dfg_table.hpp>
#include <brdfbake/run/spec_runner.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake {

/// What `brdfbake ibl` takes: the environment, the folder and the sizes of each file.
struct IblOptions : JobOptions {
  std::filesystem::path environment;  ///< EXR, HDR, ... (as prefilter reads it)
  std::filesystem::path outDir;       ///< where every file goes (created if missing)
  std::string stem;                   ///< file names' stem; default the environment's
  std::string format = "ktx2";        ///< ktx2 | ktx | dds | exr (the files' container)
  int resolution = 256;               ///< the GGX chain's level-0 face size (a power of two)
  std::optional<int> levels;          ///< chain levels; only the whole chain (down to 1 texel) is accepted
  int irradianceResolution = 32;      ///< faces of the irradiance cube (a power of two)
  int skyboxResolution = 512;         ///< faces of the skybox cube (a power of two)
  int dfgSize = 128;                  ///< DFG table texels per side
  DfgForm dfgForm = DfgForm::SingleScattering;
  double maxError = 0.01;           ///< the bound of every prefiltered level (RMS relative)
  std::optional<std::string> from;  ///< parameterization of a plain environment image
  bool shCmgen = false;             ///< also STEM_sh.txt, the 9 lines cmgen prints
  /// How the textures store texels (default rgba16f; every map and the DFG table); not with "exr".
  std::optional<TexelFormat> texelFormat;

  /// Throws Error(InvalidArgument) naming the field (by its flag): no environment or out_dir, an
  /// unknown format, sizes out of range, a resolution that is not a power of two, levels other than
  /// the whole chain, a stem holding a folder; and JobOptions' rules.
  void validate() const;
};

/// One file the job wrote, with its role (see @file).
struct IblFile {
  std::string role;
  std::filesystem::path file;
  std::string description;
  nlohmann::json details;  ///< e.g. the chain's levels, the table's axes
};

struct IblResult {
  std::filesystem::path environment;
  std::vector<IblFile> outputs;
  SpecRunResult maps;  ///< the three cube maps as runSpec made them
  std::vector<std::filesystem::path> files;
  std::vector<std::string> notes;

  std::string briefReport() const;
  /// {"environment", "format", "files": [{"role", "file", "description", ...details}], "maps": [...]}.
  nlohmann::json toJson() const;
};

/// The spec of the three cube maps (see @file), outputs relative to options.outDir.
nlohmann::json iblSpec(const IblOptions& options);

/// Validates, plans every file (the spec's, the DFG table's, the SH text's) and only then creates
/// the folder and makes the maps and the table. Throws what planSpec and runSpec throw (errors name
/// the spec keys: "ibl: maps[0].resolution"; the tool renames them to its flags), the first map's
/// error when one fails (after removing every file the job wrote: no partial output), and
/// Error(Io) when a file cannot be written.
IblResult makeIbl(const IblOptions& options);

}  // namespace brdfbake
