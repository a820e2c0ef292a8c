// brdfbake prefilter ENV: prefiltered environment maps (docs/prefilter.md).
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/env/prefilter_stack.hpp>
#include <brdfbake/env/sh_irradiance.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/maps/map_mips.hpp>

#include <chrono>
#include <iostream>

#include "commands.hpp"
#include "terminal.hpp"

namespace brdfbake::cli {
namespace fs = std::filesystem;

namespace {

constexpr const char* kFooter =
    R"(ENV is an environment image (EXR, HDR, or anything OpenImageIO reads): incoming radiance
in its own frame, y up, a lat-long image's centre looking down -z. Its parameterization comes
from its brdfbake metadata if it has any, else from --from, else from its shape: 2:1 is read
as lat-long and 4:3 as a horizontal cube cross (sphere and paraboloid images need --from). A
cube may also be six files STEM_posx.EXT ... STEM_negz.EXT: pass STEM.EXT.

Lobes (each texel holds the integral of the lobe times the environment about its axis):
  mirror         the environment itself, resampled over each texel's footprint
  irradiance     ∫ L max(0, n.l) dω, indexed by the normal (a constant L = 1 gives pi)
  phong:N        (N+1)/(2pi) max(0, r.l)^N, normalised (a constant L = 1 gives 1)
  blinn:N        Blinn-Phong exponent N as phong:N/4 (the classic N' = 4n conversion)
  ggx:R          GGX split-sum lobe with n = v = r (as Filament), perceptual roughness R
  lobes:FIT.json the fitted lobes of `brdfbake fit`, prefiltered as Kautz & McCool's sum of
                 C_k (n_k+2)/(2pi) max(0, r.l)^n_k per channel (no diffuse term, no cosine)

Fitted lobes that vary with the view elevation make a stack of --elevations K maps (default 8),
STEM_elev0.EXT ... STEM_elev{K-1}.EXT (nothing at OUT itself): slice j holds the model frozen at
t = j/(K-1), t = ln(cos / min_cos) / ln(max_cos / min_cos) the model's own elevation coordinate
(0 at the most grazing fitted view). A renderer clamps t to [0, 1] and interpolates linearly in t
between neighbouring slices; each slice's metadata records its elevation.

--fresnel-ior ETA makes the Fresnel decomposition (Heidrich 2000 section 3.1.1) from a specular lobe:
OUT is the specular map L_m, STEM_irradiance.EXT the irradiance map E, STEM_fresnel.EXT the 1-D
texture F(cos theta) of a dielectric of index ETA (--resolution texels, texel i at cos theta =
(i + 0.5)/N). A renderer computes L = F L_m + k_d E / pi (--combine add, the default) or
F L_m + (1 - F) k_d E / pi (--combine mix), F = F(n.v); the maps' metadata says which.

Methods: reference is the exact sum over every input texel (slow: the ground truth); sh
(spherical harmonics), importance (filtered importance sampling from the environment's mips)
and direct (the reference sum over the lobe's support on a coarser mip level) are fast and
estimate their own error beforehand from 512 probe directions against the reference. auto
picks the cheapest setting of any of them whose estimated RMS relative error is within
--max-error, and falls back to reference when none is.

--mips also writes the solid-angle-weighted mip levels STEM_mip1.EXT, STEM_mip2.EXT, ... down
to 1 texel, each a map of its own (cube faces edge-fixed, paraboloid borders kept). With --tiled
the whole chain goes into OUT itself: one tiled (64 x 64), MIP-mapped OpenEXR as OpenImageIO's
make_texture and maketx write it, read by any OIIO TextureSystem (with --faces, six such files).
It needs a power-of-two --resolution; OpenEXR halves to 1 x 1, so a cube cross (4 x 3 at 1 texel
per face) or a 2 x 1 paraboloid or lat-long level is followed by levels holding the map's mean.
The output's metadata records the lobe, the method, the error bound and estimate, and the
environment.

--gloss-scale S [--gloss-bias B] [--mip-count M] with --lobe phong (or blinn) makes a gloss mip
chain as cmft (--glossScale, --glossBias, --mipCount) and CubeMapGen do: level k (resolution N >> k,
written as STEM_mipK.EXT) is the environment filtered with its own exponent 2^(S g_k + B),
g_k = 1 - k/(M - 1); S = 10, B = 1, M = 8 give 2048 at level 0 falling to 2 at level 7. Each level
is made to --max-error; --no-edge-fixup keeps cube texels unaveraged (cmft's --edgeFixup none).

--sh-output FILE.json (with --lobe irradiance) also writes the irradiance as 3 bands of
spherical harmonics, 9 RGB coefficients, as cmgen does. Convention (stated in the file):
E(n)/pi = sum_i c_i Y_i(n), radiance-equivalent (a constant environment L gives L); the
coefficients include the cosine-lobe convolution (pi, 2pi/3, pi/4) and the 1/pi; Y_i are the
orthonormal real harmonics with the Condon-Shortley phase, in the environment's frame, pole +z:
Y00 = 0.282095, Y1-1 = -0.488603 y, Y10 = 0.488603 z, Y11 = -0.488603 x, Y2-2 = 1.092548 xy,
Y2-1 = -1.092548 yz, Y20 = 0.315392 (3z^2 - 1), Y21 = -1.092548 xz, Y22 = 0.546274 (x^2 - y^2).
brdfbake sample, info, convert and preview read the file (looked up at the normal).

Examples:
  brdfbake prefilter data_samples/environments/sky_latlong.exr --lobe phong:100 --to paraboloid \
      --resolution 128 --mips -o out/sky_phong100.exr
  brdfbake prefilter data_samples/environments/sky_latlong.exr --lobe irradiance --to sphere -o out/sky_irr.exr
  brdfbake prefilter data_samples/environments/sky_latlong.exr --lobe irradiance --to cube --resolution 32 \
      --sh-output out/sky_sh.json -o out/sky_irr_cube.exr
  brdfbake prefilter data_samples/environments/sky_latlong.exr --lobe ggx:0.3 --to latlong --resolution 256 \
      --mips --tiled -o out/sky_ggx_tex.exr
  brdfbake prefilter sky.hdr --lobe ggx:0.4 --to cube --faces --json -o out/sky_ggx.exr
  brdfbake prefilter data_samples/environments/sky_latlong.exr --lobe lobes:data_samples/fits/synthetic_varying.json \
      --to paraboloid --resolution 64 --elevations 8 -o out/sky_varying.exr
  brdfbake prefilter data_samples/environments/sky_latlong.exr --lobe mirror --fresnel-ior 1.5 --combine mix \
      --to sphere -o out/sky_coat.exr)";

struct PrefilterArgs {
  std::string environment, lobe, to, from, method = "auto", output, view, up, combine, shOutput;
  int resolution = 256, threads = 0, samples = 16, elevations = 0;  // elevations 0: not given (8)
  double maxError = 0.01, fresnelIor = 0.0;                         // fresnelIor 0: no decomposition
  std::optional<double> glossScale;                                 // a gloss chain (cmft's mapping)
  double glossBias = 1.0;
  int mipCount = 0;  // 0: down to 1 texel
  bool mips = false, tiled = false, json = false, quiet = false, faces = false, allowLarge = false, noEdgeFixup = false;
};

int runPrefilter(const PrefilterArgs& args) {
  // Everything that can be checked before reading the environment.
  imageFormatFor(args.output);
  // A fitted lobe model (lobes:FIT.json) or one lobe.
  std::optional<PrefilterLobe> lobe;
  std::optional<LobeModel> model;
  std::string lobeName = args.lobe;
  std::vector<fs::path> inputs{fs::path(args.environment)};
  if (args.lobe.rfind("lobes:", 0) == 0) {
    const fs::path file = args.lobe.substr(6);
    if (file.empty())
      throw Error(Error::Kind::InvalidArgument, "--lobe lobes:FILE needs the fit.json written by brdfbake fit");
    model = readFitFile(file).fit.model;
    inputs.push_back(file);
  } else if (!args.glossScale) {
    lobe = PrefilterLobe::parse(args.lobe, fs::current_path());
    lobeName = lobe->name();
  }
  // A gloss chain: --lobe phong or blinn without an exponent, one exponent per level.
  std::vector<PrefilterLobe> chainLobes;
  if (args.glossScale) {
    if (args.lobe != "phong" && args.lobe != "blinn") {
      throw Error(Error::Kind::InvalidArgument,
                  "--gloss-scale: makes a chain of Phong or Blinn-Phong levels: use --lobe phong or "
                  "--lobe blinn (no exponent; each level gets its own), got --lobe " +
                      args.lobe);
    }
    if (args.mips || args.tiled || args.fresnelIor != 0.0 || !args.shOutput.empty()) {
      throw Error(Error::Kind::InvalidArgument,
                  "--gloss-scale: the chain is its own mip levels (written as STEM_mipK.EXT); it "
                  "does not combine with --mips, --tiled, --fresnel-ior or --sh-output");
    }
    const int count = args.mipCount > 0 ? args.mipCount : std::min(16, mipLevelCount(args.resolution));
    for (double exponent : glossLevelExponents(count, *args.glossScale, args.glossBias)) {
      chainLobes.push_back(args.lobe == "phong" ? PrefilterLobe::phong(exponent) : PrefilterLobe::blinn(exponent));
    }
    lobeName = chainLobes.front().name() + " ... " + chainLobes.back().name();
  } else if (args.mipCount != 0) {
    throw Error(Error::Kind::InvalidArgument,
                "--mip-count: the number of levels of a gloss chain; needs --gloss-scale");
  }
  const bool stack = model && model->elevation == LobeElevation::Varying;
  if (args.elevations != 0 && !stack) {
    throw Error(Error::Kind::InvalidArgument,
                "--elevations: only lobe models that vary with elevation (--lobe lobes:FIT.json "
                "with a varying model) make a stack of maps over elevation");
  }
  const bool fresnel = args.fresnelIor != 0.0;
  if (fresnel && (!lobe || lobe->indexedByNormal())) {
    throw Error(Error::Kind::InvalidArgument,
                "--fresnel-ior: the Fresnel decomposition needs a specular lobe (mirror, phong:N, "
                "blinn:N, ggx:R) for its specular map; the irradiance map is made with it");
  }
  if (!args.combine.empty() && !fresnel) {
    throw Error(Error::Kind::InvalidArgument,
                "--combine: needs --fresnel-ior (how the Fresnel decomposition is combined)");
  }
  PrefilterOptions options;
  options.parameterization = parseParameterizationKind(args.to);
  options.resolution = args.resolution;
  options.mips = args.mips;
  if (!chainLobes.empty())
    options.cubeEdgeFixup = !args.noEdgeFixup;
  else if (args.noEdgeFixup)
    throw Error(Error::Kind::InvalidArgument, "--no-edge-fixup: only with --gloss-scale");
  options.method = parsePrefilterMethod(args.method);
  options.maxError = args.maxError;
  options.threads = args.threads;
  options.mirrorSamples = args.samples;
  options.allowLarge = args.allowLarge;
  if (args.elevations != 0) options.elevations = args.elevations;
  if (!args.view.empty() || !args.up.empty()) {
    if (options.parameterization != ParameterizationKind::Sphere) {
      throw Error(Error::Kind::InvalidArgument,
                  "--view/--up: only sphere maps have a view (the others live in the environment's frame)");
    }
    if (!args.view.empty()) options.view = parseVector(args.view, "--view");
    if (!args.up.empty()) options.up = parseVector(args.up, "--up");
  }
  options.validate();
  if (args.tiled) {
    if (!args.mips)
      throw Error(Error::Kind::InvalidArgument, "--tiled: needs --mips (the chain it writes into one file)");
    if (const std::string problem = tiledMipProblem(args.output, options.resolution); !problem.empty()) {
      throw Error(Error::Kind::InvalidArgument, "--tiled: " + problem);
    }
  }
  if (!args.shOutput.empty()) {
    if (!lobe || !lobe->indexedByNormal() || fresnel) {
      throw Error(Error::Kind::InvalidArgument,
                  "--sh-output: spherical-harmonic coefficients hold irradiance: use it with "
                  "--lobe irradiance");
    }
    if (fs::path(args.shOutput).extension() != ".json") {
      throw Error(Error::Kind::InvalidArgument,
                  "--sh-output: " + args.shOutput + ": the SH coefficients are written as JSON (.json)");
    }
  }
  const FresnelCombine combine = args.combine.empty() ? FresnelCombine::Add : parseFresnelCombine(args.combine);
  const std::optional<FresnelTerm> fresnelTerm =
      fresnel ? std::optional(FresnelTerm::dielectric(Rgb::Constant(args.fresnelIor))) : std::nullopt;
  FilePlan plan;
  plan.addInput(args.environment, "environment");
  if (model) plan.addInput(args.lobe.substr(6), "--lobe");
  const MipLayout mipLayout = args.tiled ? MipLayout::Tiled : MipLayout::Files;
  PrefilterOutputs outputs{options.parameterization,
                           options.resolution,
                           options.mips,
                           args.faces ? CubeLayout::Faces : CubeLayout::Cross,
                           mipLayout,
                           stack ? options.elevations : 0,
                           fresnel};
  if (!chainLobes.empty()) outputs.mips = true, outputs.mipLevels = static_cast<int>(chainLobes.size());
  for (const auto& output : prefilterOutputFiles(args.output, outputs, "-o")) plan.addOutput(output.file, output.role);
  if (!args.shOutput.empty()) plan.addOutput(args.shOutput, "--sh-output");
  plan.check();

  EnvironmentLoadOptions load;
  if (!args.from.empty()) load.kind = parseParameterizationKind(args.from);
  const Environment environment = loadEnvironment(args.environment, load);

  ProgressBar bar("prefilter " + lobeName, !args.quiet && !args.json);
  options.progress = bar.callback();
  // One map, a stack over elevation, or a Fresnel decomposition.
  std::optional<PrefilteredStack> slices;
  std::optional<FresnelDecomposition> decomposition;
  PrefilteredMap map;
  if (stack) {
    slices = prefilterLobeModelStack(environment, *model, lobeName, options);
    map.summary = slices->summary;
    map.map = slices->slices.front().map;
  } else if (fresnel) {
    decomposition =
        prefilterFresnelDecomposition(environment, *lobe, *fresnelTerm, combine, options, options.resolution);
    map.summary = decomposition->specular.summary;
    map.map = decomposition->specular.map;
  } else if (!chainLobes.empty()) {
    map = prefilterGlossChain(environment, chainLobes, options);
  } else {
    map = model ? prefilterLobeModel(environment, *model, lobeName, options) : prefilter(environment, *lobe, options);
  }

  nlohmann::json source = {{"file", args.environment},
                           {"lobe", lobeName},
                           {"parameterization", std::string(toString(environment.kind()))},
                           {"resolution", environment.map->resolution()},
                           {"detected", environment.detection}};
  if (options.parameterization == ParameterizationKind::Sphere) {
    source["view"] = {options.view.x(), options.view.y(), options.view.z()};
  }
  const auto writeStart = std::chrono::steady_clock::now();
  const CubeLayout layout = args.faces ? CubeLayout::Faces : CubeLayout::Cross;
  const nlohmann::json spec = {{"environment", source}};
  MapWriteReport written =
      slices          ? writePrefilteredStack(*slices, args.output, spec, layout, {inputs}, mipLayout)
      : decomposition ? writeFresnelDecomposition(*decomposition, args.output, spec, layout, {inputs}, mipLayout)
                      : writePrefilteredMap(map, args.output, spec, layout, {inputs}, mipLayout);
  if (!args.shOutput.empty()) {
    writeIrradianceSh(irradianceSh(environment), source, args.shOutput, inputs);
    written.files.push_back(args.shOutput);
    written.notes.push_back(args.shOutput +
                            ": irradiance as 9 SH coefficients per channel (3 bands), E(n)/pi = sum c_i Y_i(n): "
                            "cosine convolution and 1/pi included, orthonormal basis (the file states it)");
  }
  const double writeSeconds = secondsSince(writeStart);
  bar.done();
  nlohmann::json extra = nlohmann::json::object();
  if (!chainLobes.empty()) {
    nlohmann::json levels = nlohmann::json::array();
    for (std::size_t k = 0; k < chainLobes.size(); ++k)
      levels.push_back(
          {{"level", k}, {"lobe", chainLobes[k].name()}, {"resolution", std::max(1, options.resolution >> k)}});
    extra["gloss_chain"] = {{"scale", *args.glossScale}, {"bias", args.glossBias}, {"levels", levels}};
  }
  if (slices)
    extra["elevations"] = {
        {"slices", slices->slices.size()}, {"cos_theta", slices->cosines}, {"t", slices->coordinates}};
  if (decomposition) {
    extra["fresnel"] = {{"combine", std::string(toString(combine))},
                        {"ior", args.fresnelIor},
                        {"irradiance", fresnelIrradiancePath(args.output).string()},
                        {"table", fresnelTablePath(args.output).string()},
                        {"irradiance_prefilter", decomposition->irradiance.summary.toJson()}};
  }

  const PrefilterSummary& s = map.summary;
  if (args.json) {
    nlohmann::json report = s.toJson();
    report["environment"] = source;
    report["output"] = args.output;
    report["files"] = nlohmann::json::array();
    for (const auto& f : written.files) report["files"].push_back(f.string());
    report["parameterization"] = std::string(toString(options.parameterization));
    report["resolution"] = options.resolution;
    report["width"] = map.map->width();
    report["height"] = map.map->height();
    report["write_seconds"] = writeSeconds;
    report.update(extra);
    for (const auto& note : written.notes) report["notes"].push_back(note);
    std::cout << report.dump(2) << "\n";
    return 0;
  }
  if (!args.quiet) {
    std::cout << "wrote " << (slices ? elevationSlicePath(args.output, 0).string() + " ..." : args.output) << " ("
              << toString(options.parameterization) << " " << map.map->width() << "x" << map.map->height()
              << "): " << s.briefReport() << "; write " << writeSeconds << " s\n";
    if (written.files.size() > 1) {
      std::cout << "  " << written.files.size() - 1 << " more files (" << (slices ? "elevation slices, " : "")
                << (decomposition ? "irradiance map and Fresnel table, " : "") << "mip levels or cube faces)\n";
    }
    if (decomposition) std::cout << "  irradiance map: " << decomposition->irradiance.summary.briefReport() << "\n";
    for (const auto& note : s.notes) std::cout << "  note: " << note << "\n";
    for (const auto& note : written.notes) std::cout << "  note: " << note << "\n";
  }
  const PrefilterSummary* irradiance = decomposition ? &decomposition->irradiance.summary : nullptr;
  for (const PrefilterSummary* summary : {&s, irradiance}) {
    if (summary && summary->errorEstimated && !summary->metTarget) {
      std::cerr << "brdfbake: warning: the estimated error " << 100.0 * summary->errorEstimate << " % of "
                << summary->lobe << " exceeds --max-error " << 100.0 * summary->maxError << " %\n";
    }
  }
  return 0;
}

}  // namespace

Command addPrefilterCommand(CLI::App& app) {
  auto args = std::make_shared<PrefilterArgs>();
  auto* command = app.add_subcommand(
      "prefilter", "Prefilter an environment with a reflection lobe (mirror, irradiance, Phong, GGX)");
  command->footer(kFooter);
  const std::map<std::string, std::string> kinds{
      {"sphere", "sphere"}, {"paraboloid", "paraboloid"}, {"cube", "cube"}, {"latlong", "latlong"}};
  command->add_option("environment", args->environment, "Environment image (EXR, HDR, ...)")->required();
  command->add_option("--lobe", args->lobe, "mirror | irradiance | phong:N | blinn:N | ggx:ROUGHNESS | lobes:FIT.json")
      ->required();
  command->add_option("--to", args->to, "Output parameterization")->required()->check(CLI::IsMember(kinds));
  command
      ->add_option("--from", args->from,
                   "Parameterization of a plain environment image (default: metadata or aspect ratio)")
      ->check(CLI::IsMember(kinds));
  command
      ->add_option("--resolution", args->resolution,
                   "Texels per side (sphere), hemisphere (paraboloid), face (cube) or rows (latlong)")
      ->default_val(256)
      ->check(CLI::Range(1, 65536));
  command->add_flag("--mips", args->mips, "Also write the solid-angle-weighted mip levels STEM_mipK.EXT");
  command->add_flag(
      "--tiled", args->tiled,
      "With --mips: the whole chain in OUT itself, one tiled MIP-mapped OpenEXR (as maketx writes it), instead of "
      "STEM_mipK.EXT files");
  command->add_option(
      "--sh-output", args->shOutput,
      "With --lobe irradiance: also write the irradiance as 9 spherical-harmonic coefficients per channel (JSON)");
  command->add_option("--method", args->method, "auto | reference | sh | importance | direct")
      ->default_val("auto")
      ->check(CLI::IsMember({"auto", "reference", "sh", "importance", "direct"}));
  addEnvironmentMaxErrorOption(command, args->maxError, "The error the map is built to")->default_val(0.01);
  command->add_option("--view", args->view,
                      "Sphere maps: direction towards the viewer X,Y,Z in the environment's frame (default 0,0,1)");
  command->add_option("--up", args->up, "Sphere maps: up vector X,Y,Z (default 0,1,0)");
  command->add_option("--samples", args->samples, "Mirror lobe: footprint samples per texel")
      ->default_val(16)
      ->check(CLI::Range(1, 4096));
  addThreadsOption(command, args->threads);
  command
      ->add_option("--elevations", args->elevations,
                   "Lobe models varying with elevation: maps in the stack STEM_elev0.EXT ... (default 8)")
      ->check(CLI::Range(2, 64));
  command
      ->add_option("--fresnel-ior", args->fresnelIor,
                   "Fresnel decomposition: also write STEM_irradiance.EXT and the 1-D Fresnel table STEM_fresnel.EXT "
                   "of a dielectric of this index")
      ->check(CLI::PositiveNumber);
  command
      ->add_option("--combine", args->combine,
                   "Fresnel decomposition: add (F L_m + k_d E/pi) | mix (F L_m + (1-F) k_d E/pi)")
      ->check(CLI::IsMember({"add", "mix"}));
  command->add_option("--gloss-scale", args->glossScale,
                      "A gloss mip chain as cmft makes it (with --lobe phong or blinn): level k filtered with exponent "
                      "2^(SCALE g + BIAS), g = 1 - k/(levels - 1), at resolution N >> k");
  command->add_option("--gloss-bias", args->glossBias, "Gloss chain: BIAS above (default 1)");
  command->add_option("--mip-count", args->mipCount, "Gloss chain: number of levels (default: down to 1 texel)")
      ->check(CLI::Range(1, 16));
  command->add_flag(
      "--no-edge-fixup", args->noEdgeFixup,
      "Gloss chain: keep every cube texel's own value (cmft's --edgeFixup none) instead of averaging across edges");
  command->add_flag("--faces", args->faces, "Write a cube map as six files STEM_posx.EXT ... instead of a cross");
  command->add_flag("--allow-large", args->allowLarge, "Allow maps over 8192^2 texels (1 GiB of float RGBA)");
  command->add_option("-o,--output", args->output, "Output map (.exr, .hdr, .tif, .png)")->required();
  addJsonFlag(command, args->json, "method, error estimate, seconds filtering and writing, files");
  addQuietFlag(command, args->quiet);
  return [args] { return runPrefilter(*args); };
}

}  // namespace brdfbake::cli
