// brdfbake sample | info: look up and describe any output of bake or prefilter.
#include <brdfbake/run/describe_output.hpp>
#include <brdfbake/run/sample_output.hpp>

#include "commands.hpp"
#include "flags.hpp"

namespace brdfbake::cli {

namespace {

constexpr const char* kSampleFooter =
    R"(MAP is any output of bake or prefilter: a map (sphere, paraboloid, cube, lat-long; a mip level
STEM_mipK.EXT, or --mip-level K), a cube written as six faces (STEM.EXT or any face), a 1-D radial
profile, an elevation stack STEM_elev0.EXT ... (pass STEM.EXT, and --cos-view), a 1-D Fresnel table
(--cos-view only, no direction), or an SH irradiance JSON. The direction is the one the map is
indexed by, in the map's frame: the reflected direction r (eye space for sphere maps and profiles:
+z towards the viewer, y up), or the normal n for irradiance. Prints R G B A (alpha: the map's
coverage), one line per direction. --dirs FILE holds one "x y z" per line ('#' comments, blank lines
skipped; errors name FILE:LINE).

Examples:
  brdfbake sample out/phong_eye.exr --dir 0.2,0.3,1
  brdfbake sample out/phong_eye_profile.exr --dirs directions.txt --json
  brdfbake sample out/sky_varying.exr --dir 0,0.5,1 --cos-view 0.7)";

}  // namespace

Command addSampleCommand(CLI::App& app) {
  struct SampleArgs {
    CommonFlags flags;
    SampleOptions options;
  };
  auto args = std::make_shared<SampleArgs>();
  SampleOptions& options = args->options;
  auto* command = app.add_subcommand(
      "sample", "Look up any output of bake or prefilter as a renderer does (bilinear, as a GPU filters)");
  command->footer(kSampleFooter);
  addSourceOptions(command, options.source, /*cosView=*/true);
  auto* dir = addParsed(
      command, "--dir", options.directions, [](const std::string& text) { return std::vector<Vec3>{parseVec3(text)}; },
      "Direction X,Y,Z (need not be unit length)");
  command->add_option("--dirs", options.directionsFile, "File of directions, one \"x y z\" per line")->excludes(dir);
  addCommonFlags(command, args->flags, Computes::Values, "the direction and the value (an array of them with --dirs)");
  return [args] {
    const SampleResult result = namingFields({{"directions", "--dir"}}, [&] { return sampleOutput(args->options); });
    return printResult(result, args->flags, Printing::Query, -1);
  };
}

Command addInfoCommand(CLI::App& app) {
  struct InfoArgs {
    CommonFlags flags;
    std::string map;
  };
  auto args = std::make_shared<InfoArgs>();
  auto* command = app.add_subcommand(
      "info", "Say what an output is: its kind, files, size, how to look it up, the spec it was made from");
  command->footer(
      "Reads every output of bake and prefilter (see brdfbake sample --help): a cube's six faces and an\n"
      "elevation stack are named by STEM.EXT. A plain image is reported as one.");
  command->add_option("map", args->map, "Output, map or image file")->required();
  addCommonFlags(command, args->flags, Computes::Nothing, "the kind, files, size, lookup rule, spec and metadata");
  return [args] { return printResult(describeOutput(args->map), args->flags, Printing::Query); };
}

}  // namespace brdfbake::cli
