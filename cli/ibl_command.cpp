// brdfbake ibl ENV --out-dir OUT: engine-ready image-based lighting (makeIbl, run/ibl_job.hpp).
#include <brdfbake/run/ibl_job.hpp>

#include "commands.hpp"
#include "flags.hpp"

namespace brdfbake::cli {

namespace {

constexpr const char* kFooter =
    R"(Writes, in OUT, the files an engine loads for image-based lighting (docs/engines.md):
  STEM_ggx.EXT        specular: a cube texture whose level k of L holds GGX of roughness R = k/(L-1)
                      (cmgen's chain; level 0 the mirror); sample it at lod = R (L - 1)
  STEM_irradiance.EXT a small cube of irradiance E/pi at the normal
  STEM_sh.json        9 RGB spherical-harmonic coefficients of E/pi (--sh-format cmgen: also STEM_sh.txt)
  STEM_dfg.EXT        the split-sum DFG table: n.v along x, perceptual roughness along y
  STEM_skybox.EXT     the environment as a cube
EXT is .ktx2 (default), .ktx, .dds or .exr (--format). Every prefiltered level meets --max-error by its
own estimate against the reference sum; --json lists each file with its role.

Example:
  brdfbake ibl data_samples/environments/sky_latlong.exr --out-dir out/ibl --json)";

}  // namespace

Command addIblCommand(CLI::App& app) {
  struct IblArgs {
    CommonFlags flags;
    IblFiles files;
  };
  auto args = std::make_shared<IblArgs>();
  IblRequest& r = args->files.request;
  IblOutputs& o = args->files.outputs;
  o.stem.clear();  // the environment's, unless --stem
  auto* command = app.add_subcommand("ibl", "Engine-ready IBL: GGX chain, irradiance (cube, SH), DFG table, skybox");
  command->footer(kFooter);
  addEnvironmentOptions(command, args->files.environment, args->files.from);
  command->add_option("--out-dir", o.folder, "Folder for every file (created if missing)")->required();
  command->add_option("--format", o.format, "The files' container: ktx2 (.ktx2) | ktx (.ktx) | dds (.dds) | exr (.exr)")
      ->default_val("ktx2")
      ->check(CLI::IsMember({"ktx2", "ktx", "dds", "exr"}));
  addTexelFormatOption(command, o.texelFormat);
  command->add_option("--stem", o.stem, "File names' stem (default: the environment's)");
  command->add_option("--resolution", r.resolution, "GGX chain: level-0 face size, a power of two")->default_val(256);
  command->add_option("--levels", r.levels, "GGX chain levels (default and only: down to 1 texel)");
  command->add_option("--irradiance-resolution", r.irradianceResolution, "Irradiance cube faces")->default_val(32);
  command->add_option("--skybox-resolution", r.skyboxResolution, "Skybox cube faces")->default_val(512);
  command->add_option("--dfg-size", r.dfgSize, "DFG table texels per side")->default_val(128);
  addParsed(command, "--dfg-form", r.dfgForm, parseDfgForm, "single (f0 DFG1 + f90 DFG2) | multiscatter (Filament's)")
      ->default_str("single");
  addMaxErrorOption(command, r.maxError, "The bound each prefiltered level is made to (relative RMS)");
  addParsed(
      command, "--sh-format", o.shCmgen, [](const std::string& text) { return parseShFormat(text) == ShFormat::Cmgen; },
      "brdfbake (JSON) | cmgen (also STEM_sh.txt, cmgen's lines)")
      ->default_str("brdfbake");
  addCommonFlags(command, args->flags, Computes::Maps,
                 "every file with its role, and each map's entry as bake --json prints it");
  return [args] {
    return printResult(
        namingFields({{"environment", "ENV"}}, [&] { return withProgress(args->flags, args->files, runIbl); }),
        args->flags);
  };
}

}  // namespace brdfbake::cli
