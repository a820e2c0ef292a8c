// brdfbake prefilter ENV --lobe L --to KIND -o OUT: one prefiltered environment map (prefilterEnvironment).
#include <brdfbake/run/prefilter_job.hpp>

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

// The spec keys a request sets, named by their flags in messages.
const FlagNames kFlagNames = {
    {"prefilter: maps[0].environment.gloss_chain.scale", "--gloss-scale"},
    {"prefilter: maps[0].environment.gloss_chain.bias", "--gloss-bias"},
    {"prefilter: maps[0].environment.gloss_chain.levels", "--mip-count"},
    {"prefilter: maps[0].environment.gloss_chain", "--gloss-scale or --chain"},
    {"prefilter: maps[0].environment.file", "ENV"},
    {"prefilter: maps[0].environment.lobe", "--lobe"},
    {"prefilter: maps[0].environment.method", "--method"},
    {"prefilter: maps[0].environment.from", "--from"},
    {"prefilter: maps[0].environment.view", "--view"},
    {"prefilter: maps[0].environment.up", "--up"},
    {"prefilter: maps[0].environment.elevations", "--elevations"},
    {"prefilter: maps[0].environment.fresnel", "--fresnel-ior"},
    {"prefilter: maps[0].environment.combine", "--combine"},
    {"prefilter: maps[0].environment.sh_output", "--sh-output"},
    {"prefilter: maps[0].environment.sh_format", "--sh-format"},
    {"prefilter: maps[0].environment.mip_layout", "--tiled"},
    {"prefilter: maps[0].environment.mips", "--mips"},
    {"prefilter: maps[0].environment", "prefilter"},
    {"prefilter: maps[0].resolution", "--resolution"},
    {"prefilter: maps[0].parameterization", "--to"},
    {"prefilter: maps[0]", "prefilter"},
    {"\"mips\"", "--mips"},
    {"\"fresnel\"", "--fresnel-ior"},
    {"\"lobe\": \"irradiance\"", "--lobe irradiance"},
};

struct PrefilterArgs {
  CommonFlags flags;
  PrefilterRequest request;
  OutputFiles outputs;
  std::string environment, view, up, shOutput;
};

void addFilterFlags(CLI::App* command, PrefilterArgs& a) {
  PrefilterRequest& r = a.request;
  command->add_option("--lobe", r.lobe, "mirror | irradiance | phong:N | blinn:N | ggx:ROUGHNESS | lobes:FIT.json");
  command->add_option("--chain", r.chain, "ggx: cmgen's GGX chain, level k of L holding roughness k/(L-1)")
      ->check(CLI::IsMember({"ggx"}));
  addToOption(command, r.to);
  addMapResolutionOption(command, r.resolution);
  command->add_option("--method", r.method, "auto | reference | sh | importance | direct")->default_val("auto");
  addMaxErrorOption(command, r.maxError, "The bound each map is made to (relative RMS, 0.01 = 1 %)");
  addSamplesPerTexelOption(command, r.samplesPerTexel, "Mirror lobe: footprint samples per texel", true);
  addEnvironmentFromOption(command, r.from);
  command->add_option("--view", a.view, "Sphere maps: direction towards the viewer X,Y,Z (default 0,0,1)");
  command->add_option("--up", a.up, "Sphere maps: up vector X,Y,Z (default 0,1,0)");
  command->add_option("--elevations", r.elevations, "Varying lobe models: maps in the stack (default 8)");
}

void addOutputFileFlags(CLI::App* command, PrefilterArgs& a) {
  PrefilterRequest& r = a.request;
  addOutputFileOption(command, a.outputs, "Output map");
  addTexelFormatOption(command, r.texelFormat);
  command->add_flag("--mips", r.mips, "Also write the solid-angle-weighted mip levels STEM_mipK.EXT");
  command->add_flag("--tiled", r.tiled, "With --mips: the chain inside OUT, one tiled MIP-mapped OpenEXR");
  command->add_flag("--faces", r.faces, "Write a cube map as six files STEM_posx.EXT ... instead of a cross");
  command->add_option("--sh-output", a.shOutput, "With --lobe irradiance: also 9 SH coefficients per channel (JSON)");
  command->add_option("--sh-format", r.shFormat, "brdfbake (JSON, default) | cmgen (the lines cmgen prints, .txt)")
      ->check(CLI::IsMember({"brdfbake", "cmgen"}));
  command->add_option("--fresnel-ior", r.fresnelIor, "Fresnel decomposition of a dielectric of this index");
  command->add_option("--combine", r.combine, "Fresnel decomposition: add (F L_m + k_d E/pi) | mix");
  command->add_option("--gloss-scale", r.glossScale, "A gloss chain (--lobe phong|blinn): exponent 2^(S g + B)");
  command->add_option("--gloss-bias", r.glossBias, "Gloss chain: B above (default 1)");
  command->add_option("--mip-count", r.mipCount, "Gloss chain: levels (default: down to 1 texel, at most 16)");
  command->add_flag("--no-edge-fixup{false}", r.edgeFixup, "Gloss chain: keep cube texels unaveraged across edges");
}

int runPrefilter(PrefilterArgs args) {
  PrefilterRequest& request = args.request;
  if (request.lobe.empty() && !request.chain) {
    throw Error(Error::Kind::InvalidArgument, "prefilter needs --lobe (or --chain ggx)");
  }
  request.environment = args.environment;
  request.output = args.outputs.first();
  request.moreOutputs = args.outputs.rest();
  if (!args.view.empty()) request.view = parseVector(args.view, "--view");
  if (!args.up.empty()) request.up = parseVector(args.up, "--up");
  if (!args.shOutput.empty()) request.shOutput = args.shOutput;
  FlagNames names = outputFlagNames("prefilter");
  names.insert(names.end(), kFlagNames.begin(), kFlagNames.end());
  const MapResult result = namingFlags(names, [&] {
    return withProgress(args.flags, [&](const JobOptions& options) { return prefilterEnvironment(request, options); });
  });
  return printResult(result, args.flags);
}

}  // namespace

Command addPrefilterCommand(CLI::App& app) {
  auto args = std::make_shared<PrefilterArgs>();
  auto* command =
      app.add_subcommand("prefilter", "Prefilter an environment with a lobe (mirror, irradiance, Phong, GGX)");
  command->footer(kFooter);
  command->add_option("environment", args->environment, "Environment image (EXR, HDR, ...)")->required();
  addFilterFlags(command, *args);
  addOutputFileFlags(command, *args);
  addComputeFlags(command, args->flags, /*makesMaps=*/true);
  addOutputFlags(command, args->flags, "the map's entry, as bake --json prints it: files, method, error estimate");
  return [args] { return runPrefilter(*args); };
}

}  // namespace brdfbake::cli
