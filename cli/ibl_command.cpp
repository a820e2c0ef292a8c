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

struct IblArgs {
  CommonFlags flags;
  IblFiles files;
  std::string dfgForm = "single", shFormat = "brdfbake", format = "ktx2";
  std::optional<std::string> texelFormat, from;
};

int runIblCommand(IblArgs args) {
  IblFiles& files = args.files;
  const IblReport result = namingFields({{"environment", "ENV"}}, [&] {
    files.request.dfgForm = parseFlag("--dfg-form", args.dfgForm, parseDfgForm);
    files.outputs.format = args.format;
    files.outputs.shCmgen = args.shFormat == "cmgen";
    if (args.texelFormat) files.outputs.texelFormat = parseFlag("--texel-format", *args.texelFormat, parseTexelFormat);
    if (args.from) files.from = parseFlag("--from", *args.from, parseParameterizationKind);
    return withProgress(args.flags, files, runIbl);
  });
  return printResult(result, args.flags);
}

}  // namespace

Command addIblCommand(CLI::App& app) {
  auto args = std::make_shared<IblArgs>();
  IblRequest& r = args->files.request;
  IblOutputs& o = args->files.outputs;
  o.stem.clear();  // the environment's, unless --stem
  auto* command = app.add_subcommand("ibl", "Engine-ready IBL: GGX chain, irradiance (cube, SH), DFG table, skybox");
  command->footer(kFooter);
  command->add_option("environment", args->files.environment, "Environment image (EXR, HDR, ...)")->required();
  command->add_option("--out-dir", o.folder, "Folder for every file (created if missing)")->required();
  command
      ->add_option("--format", args->format,
                   "The files' container: ktx2 (.ktx2) | ktx (.ktx) | dds (.dds) | exr (.exr)")
      ->default_val("ktx2")
      ->check(CLI::IsMember({"ktx2", "ktx", "dds", "exr"}));
  addTexelFormatOption(command, args->texelFormat);
  command->add_option("--stem", o.stem, "File names' stem (default: the environment's)");
  command->add_option("--resolution", r.resolution, "GGX chain: level-0 face size, a power of two")->default_val(256);
  command->add_option("--levels", r.levels, "GGX chain levels (default and only: down to 1 texel)");
  command->add_option("--irradiance-resolution", r.irradianceResolution, "Irradiance cube faces")->default_val(32);
  command->add_option("--skybox-resolution", r.skyboxResolution, "Skybox cube faces")->default_val(512);
  command->add_option("--dfg-size", r.dfgSize, "DFG table texels per side")->default_val(128);
  command->add_option("--dfg-form", args->dfgForm, "single (f0 DFG1 + f90 DFG2) | multiscatter (Filament's)")
      ->default_val("single");
  addMaxErrorOption(command, r.maxError, "The bound each prefiltered level is made to (relative RMS)");
  addEnvironmentFromOption(command, args->from);
  command->add_option("--sh-format", args->shFormat, "brdfbake (JSON) | cmgen (also STEM_sh.txt, cmgen's lines)")
      ->default_val("brdfbake")
      ->check(CLI::IsMember({"brdfbake", "cmgen"}));
  addComputeFlags(command, args->flags, /*makesMaps=*/true);
  addOutputFlags(command, args->flags, "every file with its role, and each map's entry as bake --json prints it");
  return [args] { return runIblCommand(*args); };
}

}  // namespace brdfbake::cli
