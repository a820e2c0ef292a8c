// brdfbake preview MAP -o preview.png: an object shaded with the map.
#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/map_file.hpp>
#include <brdfbake/output/baked_output.hpp>
#include <brdfbake/output/preview.hpp>

#include <iostream>

#include "commands.hpp"
#include "terminal.hpp"

namespace brdfbake::cli {

Command addPreviewCommand(CLI::App& app) {
  struct Args {
    std::string map, output, object = "sphere", view, from;
    int size = 512, segments = 0, mipLevel = 0;
    double exposure = 0.0;
    bool perVertex = false, json = false, quiet = false;
  };
  auto args = std::make_shared<Args>();
  auto* command = app.add_subcommand("preview", "Render an object shaded with a map (see it as a renderer would)");
  command->footer(R"(Orthographic view along -VIEW (map frame; sphere maps are in eye space, view +z only).
Per pixel, the interpolated normal gives the reflected vector r = 2 (n.v) n - v and the map is looked up
at r. With --per-vertex, texture coordinates (sphere maps) or reflected vectors (other maps) are
computed at the vertices and interpolated across triangles, as fixed-function hardware did: lower
--segments to see the papers' interpolation artefacts near the sphere map's rim.

Examples:
  brdfbake preview out/phong_eye.exr -o phong_teapot.png --object teapot
  brdfbake preview out/phong_eye.exr -o coarse.png --per-vertex --segments 8
  brdfbake preview out/phong_paraboloid.exr -o side.png --object torus --view 1,0.5,0

Every output of bake and prefilter previews as a renderer shades it: a 1-D radial profile at r, an
elevation stack at r and each pixel's n.v, a Fresnel table at n.v, irradiance (maps other than
sphere maps, SH JSON) at the normal. --per-vertex applies to 2-D maps looked up at r.)");
  command->add_option("map", args->map, "Output of bake or prefilter (or a plain image with --from)")->required();
  command->add_option("-o,--output", args->output, "Output image (.png is 8-bit sRGB; .exr keeps HDR values)")
      ->required();
  command->add_option("--object", args->object, "Object to render")
      ->check(CLI::IsMember({"sphere", "torus", "teapot"}))
      ->default_val("sphere");
  command->add_option("--view", args->view, "View vector X,Y,Z towards the viewer, in the map frame (default 0,0,1)");
  command->add_option("--from", args->from, "Parameterization of a plain image")
      ->check(CLI::IsMember({"sphere", "paraboloid", "cube", "latlong"}));
  addMipLevelOption(command, args->mipLevel);
  command->add_option("--size", args->size, "Output size in pixels")->default_val(512)->check(CLI::Range(8, 8192));
  command->add_option("--segments", args->segments, "Tessellation (default 64, or 16 with --per-vertex)")
      ->check(CLI::Range(3, 1024));
  command->add_option("--exposure", args->exposure, "Scale values by 2^EXPOSURE")->default_val(0.0);
  command->add_flag("--per-vertex", args->perVertex,
                    "Interpolate per-vertex texture coordinates like fixed-function hardware");
  addJsonFlag(command, args->json, "the output and notes");
  addQuietFlag(command, args->quiet);
  return [args] {
    const BakedOutput source = openOutput(args->map, args->from, args->mipLevel);
    PreviewOptions options;
    options.object = args->object == "torus"    ? PreviewObject::Torus
                     : args->object == "teapot" ? PreviewObject::Teapot
                                                : PreviewObject::Sphere;
    options.size = args->size;
    options.perVertex = args->perVertex;
    options.segments = args->segments > 0 ? args->segments : (args->perVertex ? 16 : 64);
    options.exposure = args->exposure;
    if (!args->view.empty()) options.view = parseVector(args->view, "--view");
    imageFormatFor(args->output);
    FilePlan plan;
    plan.addInput(args->map, "map");
    for (const auto& f : mapOutputFiles(args->output, "-o")) plan.addOutput(f.file, f.role);
    plan.check();
    Image image = renderPreview(source, options);
    image.metadata = {{"preview_of", args->map}, {"object", args->object}, {"per_vertex", args->perVertex}};
    const auto report = writeImage(image, args->output, {{std::filesystem::path(args->map)}});
    if (args->json) {
      std::cout << nlohmann::json{{"output", args->output}, {"notes", report.notes}}.dump(2) << "\n";
    } else if (!args->quiet) {
      std::cout << "wrote " << args->output << "\n";
    }
    return 0;
  };
}

}  // namespace brdfbake::cli
