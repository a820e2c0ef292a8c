// brdfbake prefilter ENV --lobe L --to KIND -o OUT: one prefiltered environment map (prefilterEnvironment).
#include <brdfbake/run/prefilter_job.hpp>
#include <brdfbake/spec/spec.hpp>

#include "commands.hpp"
#include "flags.hpp"

namespace brdfbake::cli {

namespace {

constexpr const char* kFooter =
    R"(ENV is an environment image (EXR, HDR, ...): radiance in its own frame, y up, a lat-long image's
centre looking down -z. Its parameterization comes from its brdfbake metadata, else --from, else its
shape (2:1 lat-long, 4:3 cube cross). A cube may be six files STEM_posx.EXT ...: pass STEM.EXT.

Lobes (a texel holds the integral of the lobe times the environment about its axis):
  mirror          the environment itself, resampled over each texel's footprint
  irradiance      ∫ L max(0, n.l) dω at the normal n (a constant L = 1 gives pi)
  phong:N         (N+1)/(2pi) max(0, r.l)^N, normalised (a constant L = 1 gives 1)
  blinn:N         Blinn-Phong exponent N as phong:N/4
  ggx:R           GGX split-sum lobe with n = v = r (as Filament), perceptual roughness R
  lobes:FIT.json  fitted mirror lobes of `brdfbake fit` (varying ones make a stack of --elevations maps)

Methods: reference (the exact sum), sh, importance, direct; auto (default) picks the cheapest that
meets --max-error by its own estimate against the reference. --mips writes solid-angle-weighted mip
levels STEM_mipK.EXT (--tiled: inside OUT, one tiled MIP-mapped OpenEXR). --fresnel-ior ETA also
writes STEM_irradiance.EXT and the Fresnel table STEM_fresnel.EXT (Heidrich 2000 section 3.1.1).
--gloss-scale S with --lobe phong|blinn makes cmft's gloss chain: level k filtered with exponent
2^(S g_k + B), g_k = 1 - k/(M - 1). --chain ggx makes cmgen's GGX chain: level k of M (--mip-count,
default down to 1 texel) holds ggx:R_k, R_k = k/(M - 1), level 0 the mirror; with --tiled and a .ktx2,
.ktx or .dds output one texture whose levels an engine reads at lod = R (M - 1), the roughness of each
level in the metadata's "level_values". --sh-output FILE.json with --lobe irradiance also writes 9 SH
coefficients (E/pi, as cmgen). Every option is a key of a spec's "environment" map (docs/spec.md);
details and figures: docs/prefilter.md.

Examples:
  brdfbake prefilter data_samples/environments/sky_latlong.exr --lobe phong:100 --to paraboloid \
      --resolution 128 --mips -o out/sky_phong100.exr
  brdfbake prefilter data_samples/environments/sky_latlong.exr --lobe irradiance --to cube --resolution 32 \
      --sh-output out/sky_sh.json -o out/sky_irr_cube.exr
  brdfbake prefilter sky.hdr --lobe ggx:0.4 --to cube --faces --json -o out/sky_ggx.exr
  brdfbake prefilter sky.hdr --chain ggx --to cube --resolution 256 --tiled -o out/sky_ggx.ktx2)";

// The request's fields whose flags are not their names.
const FieldFlags kFieldFlags = {{"parameterization", "--to"}, {"outputs", "-o"},
                                {"mip_layout", "--tiled"},    {"fresnel", "--fresnel-ior"},
                                {"sh", "--sh-output"},        {"gloss_chain", "--gloss-scale or --chain"},
                                {"environment", "ENV"}};

struct PrefilterArgs {
  CommonFlags flags;
  PrefilterFiles files;
  LobeArguments lobe;
  std::filesystem::path shOutput;
  bool shCmgen = false;
};

void addFilterFlags(CLI::App* command, PrefilterArgs& a) {
  PrefilterRequest& r = a.files.request;
  command->add_option("--lobe", a.lobe.lobe,
                      "mirror | irradiance | phong:N | blinn:N | ggx:ROUGHNESS | lobes:FIT.json");
  command->add_option("--chain", a.lobe.chain, "ggx: cmgen's GGX chain, level k of L holding roughness k/(L-1)")
      ->check(CLI::IsMember({"ggx"}));
  addToOption(command, r.parameterization);
  addMapResolutionOption(command, r.resolution);
  addParsed(command, "--method", r.method, parsePrefilterMethod, "auto | reference | sh | importance | direct")
      ->default_str("auto");
  addMaxErrorOption(command, r.maxError, "The bound each map is made to (relative RMS, 0.01 = 1 %)");
  addSamplesPerTexelOption(command, r.samplesPerTexel, "Mirror lobe: footprint samples per texel", true);
  addParsed(command, "--view", r.view, parseVec3, "Sphere maps: direction towards the viewer X,Y,Z (default 0,0,1)");
  addParsed(command, "--up", r.up, parseVec3, "Sphere maps: up vector X,Y,Z (default 0,1,0)");
  command->add_option("--elevations", r.elevations, "Varying lobe models: maps in the stack (default 8)");
  addParsed(
      command, "--fresnel-ior", r.fresnel,
      [](const std::string& text) { return FresnelTerm::dielectric(Rgb::Constant(parseFiniteNumber(text))); },
      "Fresnel decomposition of a dielectric of this index");
  addParsed(command, "--combine", r.combine, parseFresnelCombine,
            "Fresnel decomposition: add (F L_m + k_d E/pi) | mix");
  command->add_option("--gloss-scale", a.lobe.glossScale, "A gloss chain (--lobe phong|blinn): exponent 2^(S g + B)");
  command->add_option("--gloss-bias", a.lobe.glossBias, "Gloss chain: B above (default 1)");
  command->add_option("--mip-count", a.lobe.mipCount, "Gloss chain: levels (default: down to 1 texel, at most 16)");
  command->add_flag("--no-edge-fixup{false}", a.lobe.edgeFixup,
                    "Gloss chain: keep cube texels unaveraged across edges");
}

void addOutputFileFlags(CLI::App* command, PrefilterArgs& a) {
  MapOutputs& outputs = a.files.outputs;
  addMapOutputOptions(command, outputs);
  command->add_flag("--mips", a.files.request.mips, "Also write the solid-angle-weighted mip levels STEM_mipK.EXT");
  command->add_flag_callback(
      "--tiled", [&outputs] { outputs.mipLayout = MipLayout::Tiled; },
      "With --mips: the chain inside OUT, one tiled MIP-mapped OpenEXR");
  command->add_option("--sh-output", a.shOutput, "With --lobe irradiance: also 9 SH coefficients per channel (JSON)");
  addParsed(
      command, "--sh-format", a.shCmgen, [](const std::string& text) { return parseShFormat(text) == ShFormat::Cmgen; },
      "brdfbake (JSON, default) | cmgen (the lines cmgen prints, .txt)");
}

int runPrefilterCommand(PrefilterArgs a) {
  const MapResult result = namingFields(kFieldFlags, [&] {
    a.lobe.apply(a.files.request);
    if (!a.shOutput.empty()) a.files.sh = ShOutput{a.shOutput, a.shCmgen};
    return withProgress(a.flags, a.files, runPrefilter);
  });
  return printResult(result, a.flags);
}

}  // namespace

Command addPrefilterCommand(CLI::App& app) {
  auto args = std::make_shared<PrefilterArgs>();
  auto* command =
      app.add_subcommand("prefilter", "Prefilter an environment with a lobe (mirror, irradiance, Phong, GGX)");
  command->footer(kFooter);
  addEnvironmentOptions(command, args->files.environment, args->files.from);
  addFilterFlags(command, *args);
  addOutputFileFlags(command, *args);
  addCommonFlags(command, args->flags, Computes::Maps,
                 "the map's entry, as bake --json prints it: files, method, error estimate");
  return [args] { return runPrefilterCommand(*args); };
}

}  // namespace brdfbake::cli
