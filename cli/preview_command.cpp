// brdfbake preview MAP -o preview.png: an object shaded with an output (makePreview).
#include <brdfbake/run/preview_job.hpp>

#include "commands.hpp"
#include "flags.hpp"

namespace brdfbake::cli {

namespace {

constexpr const char* kFooter =
    R"(Orthographic view along -VIEW (map frame; sphere maps are in eye space, view +z only). Per
pixel, the interpolated normal gives the reflected vector r = 2 (n.v) n - v and the map is looked
up at r (irradiance at n, a Fresnel table at n.v, a stack at r and each pixel's n.v). With
--per-vertex, texture coordinates (sphere maps) or reflected vectors (other maps) are computed at
the vertices and interpolated across triangles, as fixed-function hardware did: lower --segments
to see the papers' interpolation artefacts near the sphere map's rim.

Examples:
  brdfbake preview out/phong_eye.exr -o phong_teapot.png --object teapot
  brdfbake preview out/phong_eye.exr -o coarse.png --per-vertex --segments 8
  brdfbake preview out/phong_paraboloid.exr -o side.png --object torus --view 1,0.5,0)";

struct PreviewArgs {
  CommonFlags flags;
  PreviewJobOptions options;
  std::string map, output, object = "sphere", view, from;
  int segments = 0;
};

int runPreview(PreviewArgs a) {
  PreviewJobOptions& options = a.options;
  options.source.path = a.map;
  if (!a.from.empty()) options.source.from = parseParameterizationKind(a.from);
  options.output = a.output;
  options.preview.object = parseFlag("--object", a.object, parsePreviewObject);
  options.preview.segments = a.segments > 0 ? a.segments : (options.preview.perVertex ? 16 : 64);
  if (!a.view.empty()) options.preview.view = parseVector(a.view, "--view");
  return printResult(withProgress(a.flags, options, makePreview), a.flags);
}

}  // namespace

Command addPreviewCommand(CLI::App& app) {
  auto args = std::make_shared<PreviewArgs>();
  PreviewOptions& preview = args->options.preview;
  auto* command = app.add_subcommand("preview", "Render an object shaded with a map (see it as a renderer would)");
  command->footer(kFooter);
  command->add_option("map", args->map, "Output of bake or prefilter (or a plain image with --from)")->required();
  command
      ->add_option(
          "-o,--output", args->output,
          std::string("Output image (") + kOutputContainers + "; .png is 8-bit sRGB, the others keep HDR values)")
      ->required();
  command->add_option("--object", args->object, "sphere | torus | teapot")->default_str("sphere");
  command->add_option("--view", args->view, "View vector X,Y,Z towards the viewer, in the map frame (default 0,0,1)");
  addFromOption(command, args->from);
  addMipLevelOption(command, args->options.source.mipLevel);
  command->add_option("--resolution", preview.resolution, "Output size in pixels")
      ->default_val(512)
      ->check(CLI::Range(8, 8192));
  command->add_option("--size", preview.resolution, "(old spelling of --resolution)")->group("");
  command->add_option("--segments", args->segments, "Tessellation (default 64, or 16 with --per-vertex)")
      ->check(CLI::Range(3, 1024));
  command->add_option("--exposure", preview.exposure, "Scale values by 2^EXPOSURE")->default_val(0.0);
  command->add_flag("--per-vertex", preview.perVertex,
                    "Interpolate per-vertex texture coordinates like fixed-function hardware");
  addComputeFlags(command, args->flags, /*makesMaps=*/false);
  addOutputFlags(command, args->flags, "the output and notes");
  return [args] { return runPreview(*args); };
}

}  // namespace brdfbake::cli
