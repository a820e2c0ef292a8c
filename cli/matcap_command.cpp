// brdfbake matcap MATERIAL ENVIRONMENT -o OUT: a material shaded under an environment, as a sphere map
// looked up by the view-space normal (makeMatcap).
#include <brdfbake/run/matcap_job.hpp>

#include "commands.hpp"
#include "flags.hpp"

namespace brdfbake::cli {

namespace {

constexpr const char* kFooter =
    R"(MATERIAL is one of:
  a material JSON file   one object {"model": "cook_torrance", ...} as a spec's "material" (docs/materials.md)
  a fit.json             lobes fitted by `brdfbake fit` (lit through their BRDF)
  a measured table       .astm, .brdf, .mat: lobes are fitted to it first (a few seconds)
ENVIRONMENT is an environment image (EXR, HDR, ...) of radiance, as `prefilter` reads it.

Each texel holds the radiance the material reflects towards the viewer,
L_o(n, v) = ∫ f_r(l, v; n) L(l) max(0, n.l) dω(l): an orthographic picture of a sphere of the material
under the environment, viewed along -z with up +y (the environment's axes; turn the camera with
--camera YAW,PITCH in degrees). Up in the environment is up in the picture, as Blender's matcaps
(uv = n.xy / 2 + 1/2). The environment's bright texels (a sun) are summed exactly; the rest is
importance-sampled. The map reports its error estimate: the larger of the RMS of its bilinear lookups
over the visible disc and their value-weighted RMS (where the highlight is), relative to the peak, each
against a brute-force sum over the environment's texels; auto makes the cheapest map within
--max-error. A .png output is 8-bit sRGB (clamped to [0, 1]; --exposure STOPS scales by 2^STOPS
first); .exr keeps linear floats.
Units, orientation and method: docs/matcap.md.

Examples:
  echo '{"model": "cook_torrance", "distribution": "ggx", "roughness": 0.3,
         "fresnel": {"schlick": [1.0, 0.78, 0.34]}, "shadowing": "smith_separable"}' > gold.json
  brdfbake matcap gold.json data_samples/environments/sky_latlong.exr -o out/gold.png
  brdfbake matcap data_samples/fits/synthetic_two_lobes.json data_samples/environments/sky_latlong.exr \
      --resolution 512 --camera 90,10 --json -o out/fit.exr)";

struct MatcapArgs {
  CommonFlags flags;
  MatcapRequest request;
  OutputFiles outputs;
  std::string material, environment, camera;
};

// "YAW,PITCH" in degrees.
void parseCamera(const std::string& text, MatcapRequest& request) {
  const auto values = parseList<double>(text, "--camera", parseFiniteNumber);
  if (values.size() != 2) {
    throw Error(Error::Kind::InvalidArgument,
                "--camera: give YAW,PITCH in degrees (two numbers), got " + std::to_string(values.size()));
  }
  request.yaw = values[0], request.pitch = values[1];
}

int runMatcap(MatcapArgs args) {
  MatcapRequest& request = args.request;
  request.material = args.material;
  request.environment = args.environment;
  request.output = args.outputs.first();
  request.moreOutputs = args.outputs.rest();
  if (!args.camera.empty()) parseCamera(args.camera, request);
  // The spec keys the request sets, named by their flags in messages.
  const FlagNames names = {
      {"matcap: maps[0].material.", args.material + ": "},
      {"matcap: maps[0].material", args.material},
      {"matcap: maps[0].environment.file", "ENVIRONMENT " + args.environment},
      {"matcap: maps[0].environment.max_error", "--max-error"},
      {"matcap: maps[0].environment.method", "--method"},
      {"matcap: maps[0].environment.from", "--from"},
      {"matcap: maps[0].camera", "--camera"},
      {"matcap: maps[0].resolution", "--resolution"},
      {"matcap: maps[0].parameterization", "--parameterization"},
      {"matcap: maps[0].samples_per_texel", "--samples-per-texel"},
      {"matcap: maps[0].exposure", "--exposure"},
      {"matcap: maps[0]", "matcap"},
  };
  FlagNames allNames = outputFlagNames("matcap");
  allNames.insert(allNames.end(), names.begin(), names.end());
  const MapResult result = namingFlags(allNames, [&] {
    return withProgress(args.flags, [&](const JobOptions& options) { return makeMatcap(request, options); });
  });
  return printResult(result, args.flags);
}

}  // namespace

Command addMatcapCommand(CLI::App& app) {
  auto args = std::make_shared<MatcapArgs>();
  MatcapRequest& r = args->request;
  auto* command = app.add_subcommand("matcap", "Shade a material under an environment: a matcap (sphere map)");
  command->footer(kFooter);
  command->add_option("material", args->material, "Material JSON, fit.json or measured table")->required();
  command->add_option("environment", args->environment, "Environment image (EXR, HDR, ...)")->required();
  addOutputFileOption(command, args->outputs, "Output map");
  addTexelFormatOption(command, r.texelFormat);
  addMapResolutionOption(command, r.resolution);
  command->add_option("--parameterization", r.parameterization, "sphere (the matcap) | paraboloid | cube | latlong")
      ->default_val("sphere")
      ->check(CLI::IsMember({"sphere", "paraboloid", "cube", "latlong"}));
  command->add_option("--camera", args->camera, "YAW,PITCH in degrees: turn the camera (default 0,0: looking down -z)");
  command->add_option("--method", r.method, "auto | sampled | reference (the brute-force sum: slow)")
      ->default_val("auto");
  addMaxErrorOption(command, r.maxError, "The bound on the estimated error (relative to the peak)");
  addSamplesPerTexelOption(command, r.samplesPerTexel, "Footprint samples per texel", false);
  command->add_option("--exposure", r.exposure, "Scale the map by 2^STOPS before writing (for .png)")
      ->default_val(0.0)
      ->check(CLI::Range(-30.0, 30.0));
  addEnvironmentFromOption(command, r.from);
  addComputeFlags(command, args->flags, /*makesMaps=*/true);
  addOutputFlags(command, args->flags, "the map's entry, as bake --json prints it: files, error estimate");
  return [args] { return runMatcap(*args); };
}

}  // namespace brdfbake::cli
