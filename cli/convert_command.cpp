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

}  // namespace

Command addConvertCommand(CLI::App& app) {
  struct ConvertArgs {
    CommonFlags flags;
    ConvertOptions options;
  };
  auto args = std::make_shared<ConvertArgs>();
  ConvertOptions& options = args->options;
  auto* command = app.add_subcommand("convert", "Resample a map into another parameterization");
  command->footer(kFooter);
  addSourceOptions(command, options.source, /*cosView=*/true);
  addToOption(command, options.to);
  command->add_option("--resolution", options.resolution, "Output resolution (default: the input's)")
      ->check(CLI::Range(1, 65536));
  addSamplesPerTexelOption(command, options.samplesPerTexel, "Samples per output texel", true);
  addMapOutputOptions(command, options.outputs);
  addCommonFlags(command, args->flags, Computes::Maps, "files, seconds, notes");
  return [args] {
    const auto converted = namingFields({{"outputs", "-o"}, {"source", "MAP"}},
                                        [&] { return withProgress(args->flags, args->options, convertOutput); });
    return printResult(converted, args->flags);
  };
}

}  // namespace brdfbake::cli
