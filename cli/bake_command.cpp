// brdfbake bake SPEC.json: bake every map of a spec (runSpec).
#include <brdfbake/run/spec_runner.hpp>

#include "commands.hpp"
#include "flags.hpp"

namespace brdfbake::cli {

namespace {

constexpr const char* kFooter =
    R"(A spec lists maps; each names its output, parameterization (sphere | paraboloid | cube |
latlong | profile | auto), resolution, samples_per_texel, material and lights. Relative paths
resolve against the spec's folder (or --out-dir). The whole spec is validated, and every file it
reads and writes checked, before anything is baked; a map that fails while baking does not stop
the others (the exit status is the first failure's). Specs for every model: data_samples/specs/.
Format: docs/spec.md. Models: phong, blinn_phong, cook_torrance, fresnel, colorgram, gooch,
silhouette, hatching (docs/materials.md), measured, lobes (docs/fitting.md). "environment" in place
of a material prefilters an HDR environment (docs/prefilter.md). "auto" values with "max_error" let
the tool pick the cheapest map that meets it, a 1-D radial profile included when the map is
radially symmetric.

  {"maps": [{"output": "phong_eye.exr", "parameterization": "sphere", "resolution": 256,
             "samples_per_texel": 16,
             "material": {"model": "phong", "specular": [1, 1, 1], "exponent": 50},
             "lights": [{"direction": "eye", "color": [1, 1, 1]}]}]})";

struct BakeArgs {
  CommonFlags flags;
  std::string spec, outDir, misplacedOutput;
};

int runBake(const BakeArgs& args) {
  if (!args.misplacedOutput.empty()) {
    throw Error(Error::Kind::InvalidArgument,
                "-o: bake writes one file per map, named by the spec's \"output\" keys; give the folder they go "
                "in with --out-dir DIR");
  }
  SpecRunOptions options;
  options.spec = args.spec;
  options.outDir = args.outDir;
  const SpecRunResult result = withProgress(args.flags, options, runSpec);
  if (args.flags.json) {
    printResult(result, args.flags);
  } else {
    // Written maps' lines on stdout, failures on stderr (a failed map's line is "maps[i] failed: ...").
    for (const auto& map : result.maps) {
      if (map.written)
        printJsonOrText(nullptr, map.briefReport(), args.flags);
      else
        writeStderr("brdfbake: " + map.briefReport());
    }
    if (result.maps.size() > 1 && result.firstError) writeStderr("brdfbake: " + result.failureSummary());
  }
  if (result.firstError) throw *result.firstError;
  return 0;
}

}  // namespace

Command addBakeCommand(CLI::App& app) {
  auto args = std::make_shared<BakeArgs>();
  auto* command = app.add_subcommand("bake", "Bake every map described by a JSON spec");
  command->footer(kFooter);
  command->add_option("spec", args->spec, "Spec file (JSON)")->required();
  command->add_option(
      "-d,--out-dir", args->outDir,
      "Write the spec's outputs under this folder instead of the spec's own (they must stay inside it)");
  // -o names one output file on every command; bake writes a file per map, so it takes a folder.
  command->add_option("-o,--output", args->misplacedOutput, "(bake takes --out-dir: it writes one file per map)")
      ->group("");
  addCommonFlags(command, args->flags, Computes::Maps, "per map its status, files, seconds baking and writing, notes");
  return [args] { return runBake(*args); };
}

}  // namespace brdfbake::cli
