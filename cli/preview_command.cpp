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

}  // namespace

Command addPreviewCommand(CLI::App& app) {
  struct PreviewArgs {
    CommonFlags flags;
    PreviewJobOptions options;
  };
  auto args = std::make_shared<PreviewArgs>();
  PreviewOptions& preview = args->options.preview;
  auto* command = app.add_subcommand("preview", "Render an object shaded with a map (see it as a renderer would)");
  command->footer(kFooter);
  addSourceOptions(command, args->options.source, /*cosView=*/false);
  command
      ->add_option(
          "-o,--output", args->options.output,
          std::string("Output image (") + kOutputContainers + "; .png is 8-bit sRGB, the others keep HDR values)")
      ->required();
  addParsed(command, "--object", preview.object, parsePreviewObject, "sphere | torus | teapot")->default_str("sphere");
  addParsed(command, "--view", preview.view, parseVec3,
            "View vector X,Y,Z towards the viewer, in the map frame (default 0,0,1)");
  command->add_option("--resolution", preview.resolution, "Output size in pixels")
      ->default_val(512)
      ->check(CLI::Range(8, 8192));
  command->add_option("--size", preview.resolution, "(old spelling of --resolution)")->group("");
  command->add_option("--segments", preview.segments, "Tessellation (default 64, or 16 with --per-vertex)")
      ->check(CLI::Range(3, 1024));
  command->add_option("--exposure", preview.exposure, "Scale values by 2^EXPOSURE")->default_val(0.0);
  command->add_flag("--per-vertex", preview.perVertex,
                    "Interpolate per-vertex texture coordinates like fixed-function hardware");
  addCommonFlags(command, args->flags, Computes::Values, "the output and notes");
  return [args] { return printResult(withProgress(args->flags, args->options, makePreview), args->flags); };
}

}  // namespace brdfbake::cli
