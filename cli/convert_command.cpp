// brdfbake convert MAP --to KIND -o OUT: resample an output into another parameterization (convertOutput).
#include <brdfbake/run/convert_output.hpp>

#include "commands.hpp"
#include "flags.hpp"

namespace brdfbake::cli {

namespace {

constexpr const char* kFooter =
    R"(Each output texel averages lookups of the input over its footprint, the lookups a renderer makes
(brdfbake sample --help): any output of bake or prefilter converts. An elevation stack needs
--cos-view (the map at that n.v); a Fresnel table converts --to sphere only, as seen from +z (the
texel at r holds F(n.v), n = normalize(r + z)). Plain environment images (no brdfbake metadata)
need --from.

Examples:
  brdfbake convert out/phong_paraboloid.exr --to cube -o out/phong_cube.exr
  brdfbake convert sky.hdr --from latlong --to sphere --resolution 512 -o sky_sphere.exr)";

struct ConvertArgs {
  CommonFlags flags;
  ConvertOptions options;
  OutputFiles outputs;
  std::optional<std::string> texelFormat;
  std::string map, to, from;
  bool faces = false;
};

int runConvert(ConvertArgs a) {
  ConvertOptions& options = a.options;
  options.source.path = a.map;
  if (!a.from.empty()) options.source.from = parseParameterizationKind(a.from);
  options.to = parseParameterizationKind(a.to);
  options.layout = a.faces ? CubeLayout::Faces : CubeLayout::Cross;
  options.output = a.outputs.first();
  options.moreOutputs = a.outputs.rest();
  if (a.texelFormat) options.texelFormat = parseFlag("--texel-format", *a.texelFormat, parseTexelFormat);
  const FieldFlags names = {{"cos_view", "--cos-view"},
                            {"to", "--to"},
                            {"resolution", "--resolution"},
                            {"texel format", "--texel-format"},
                            {"output", "-o"}};
  return printResult(namingFields(names, [&] { return withProgress(a.flags, options, convertOutput); }), a.flags);
}

}  // namespace

Command addConvertCommand(CLI::App& app) {
  auto args = std::make_shared<ConvertArgs>();
  auto* command = app.add_subcommand("convert", "Resample a map into another parameterization");
  command->footer(kFooter);
  command->add_option("map", args->map, "Input map or image")->required();
  addToOption(command, args->to);
  addFromOption(command, args->from);
  command->add_option("--resolution", args->options.resolution, "Output resolution (default: the input's)")
      ->check(CLI::Range(1, 65536));
  addSamplesPerTexelOption(command, args->options.samplesPerTexel, "Samples per output texel", true);
  addCosViewOption(command, args->options.source.cosView);
  addMipLevelOption(command, args->options.source.mipLevel);
  command->add_flag("--faces", args->faces, "Write a cube map as six files instead of a cross");
  addOutputFileOption(command, args->outputs, "Output map");
  addTexelFormatOption(command, args->texelFormat);
  addComputeFlags(command, args->flags, /*makesMaps=*/true);
  addOutputFlags(command, args->flags, "files, seconds, notes");
  return [args] { return runConvert(*args); };
}

}  // namespace brdfbake::cli
