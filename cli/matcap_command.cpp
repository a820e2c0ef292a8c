// brdfbake matcap MATERIAL ENVIRONMENT -o OUT: a material shaded under an environment, as a sphere map
// looked up by the view-space normal (makeMatcap).
#include <brdfbake/core/text_numbers.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/run/matcap_job.hpp>

#include <algorithm>
#include <cmath>
#include <optional>

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
--max-error. A .png output is 8-bit sRGB, clamped to [0, 1] after --exposure: auto (the default
for .png) scales the map so its 99th percentile is white and records the stops in the file; STOPS
scales by 2^STOPS. .exr keeps linear floats (exposure 0 unless given).
Units, orientation and method: docs/matcap.md.

Examples:
  echo '{"model": "cook_torrance", "distribution": "ggx", "roughness": 0.3,
         "fresnel": {"schlick": [1.0, 0.78, 0.34]}, "shadowing": "smith_separable"}' > gold.json
  brdfbake matcap gold.json data_samples/environments/sky_latlong.exr -o out/gold.png
  brdfbake matcap data_samples/fits/synthetic_two_lobes.json data_samples/environments/sky_latlong.exr \
      --resolution 512 --camera 90,10 --json -o out/fit.exr)";

// "YAW,PITCH" in degrees.
CameraFrame parseCamera(const std::string& text) {
  const auto values = listOf(parseFiniteNumber)(text);
  if (values.size() != 2) {
    throw Error(Error::Kind::InvalidArgument,
                "give YAW,PITCH in degrees (two numbers), got " + std::to_string(values.size()));
  }
  return CameraFrame::fromYawPitch(values[0], values[1]);
}

}  // namespace

Command addMatcapCommand(CLI::App& app) {
  struct MatcapArgs {
    CommonFlags flags;
    MatcapFiles files;
  };
  auto args = std::make_shared<MatcapArgs>();
  MatcapRequest& r = args->files.request;
  auto* command = app.add_subcommand("matcap", "Shade a material under an environment: a matcap (sphere map)");
  command->footer(kFooter);
  command->add_option("material", args->files.material, "Material JSON, fit.json or measured table")->required();
  addEnvironmentOptions(command, args->files.environment, args->files.from);
  addMapOutputOptions(command, args->files.outputs);
  addMapResolutionOption(command, r.resolution);
  addParsed(command, "--parameterization", r.parameterization, parseParameterizationKind,
            "sphere (the matcap) | paraboloid | cube | latlong")
      ->default_str("sphere");
  addParsed(command, "--camera", r.camera, parseCamera,
            "YAW,PITCH in degrees: turn the camera (default 0,0: looking down -z)");
  addParsed(command, "--method", r.method, parseUnderEnvironmentMethod,
            "auto | sampled | reference (the brute-force sum: slow)")
      ->default_str("auto");
  addMaxErrorOption(command, r.maxError, "The bound on the estimated error (RMS relative to the peak)");
  command
      ->add_option("--max-relative-error", r.maxRelativeError,
                   "The bound on each texel's relative error where above 1 % of the median (default 3 x --max-error)")
      ->check(CLI::Range(1e-6, 10.0));
  addSamplesPerTexelOption(command, r.samplesPerTexel, "Footprint samples per texel", false);
  struct Exposure {
    std::optional<double> stops;  // none: auto
  };
  auto exposure = std::make_shared<Exposure>();
  addParsed(
      command, "--exposure", exposure->stops,
      [](const std::string& text) -> std::optional<double> {
        if (text == "auto") return std::nullopt;
        const double stops = parseFiniteNumber(text);
        if (std::abs(stops) > 30.0) throw Error(Error::Kind::InvalidArgument, "give auto or STOPS in [-30, 30]");
        return stops;
      },
      "auto | STOPS: scale the map by 2^STOPS before writing; auto puts its 99th percentile at white "
      "(for .png; the default there, 0 for other formats)")
      ->default_str("auto");
  addCommonFlags(command, args->flags, Computes::Maps,
                 "the map's entry, as bake --json prints it: files, error estimate");
  return [args, exposure] {
    MatcapRequest& request = args->files.request;
    const auto& files = args->files.outputs.files;
    request.exposure = exposure->stops.value_or(0.0);
    request.autoExposure = !exposure->stops && std::any_of(files.begin(), files.end(), [](const auto& f) {
      return imageFormatFor(f) == ImageFormat::Png;
    });
    const FieldFlags names = {{"outputs", "-o"},
                              {"material", "MATERIAL " + printable(args->files.material.string())},
                              {"environment", "ENVIRONMENT"}};
    return printResult(namingFields(names, [&] { return withProgress(args->flags, args->files, runMatcap); }),
                       args->flags);
  };
}

}  // namespace brdfbake::cli
