// brdfbake eval MODEL: BRDF values of a fit.json, a measured table or a material file (evaluateBrdf).
#include <brdfbake/run/evaluate.hpp>

#include "commands.hpp"
#include "flags.hpp"

namespace brdfbake::cli {

namespace {

constexpr const char* kFooter =
    R"(Directions are in the local frame, z along the normal, both pointing away from the surface:
wi towards the light, wo towards the viewer. Prints one BRDF value (1/sr) per channel; 0 when a
direction is at or below the horizon. More than three channels (a spectral table or fit): their
names go to stderr once, so stdout keeps one line per direction.

MODEL is a fit.json from `brdfbake fit`; a measured table (.astm, .brdf, .mat: nearest incident
angle, then inverse-distance weighting over the 4 nearest outgoing directions; .binary MERL: the
nearest bin); or a JSON file holding one material object, e.g. {"model": "phong", "exponent": 50}.
--pairs FILE reads lines "theta_i phi_i theta_s phi_s" (radians, Cornell convention) and prints one
line per input line (blank and # lines echoed).

Examples:
  brdfbake eval fit.json --wi 0.5,0,0.866 --wo -0.5,0,0.866
  brdfbake eval garnet_red.astm --wi 0.5,0,0.866 --wo -0.5,0,0.866 --json
  printf '0.5236 0 0.5236 3.1416\n' > pairs.txt && brdfbake eval fit.json --pairs pairs.txt)";

}  // namespace

Command addEvalCommand(CLI::App& app) {
  struct EvalArgs {
    CommonFlags flags;
    EvaluateOptions options;
  };
  auto args = std::make_shared<EvalArgs>();
  EvaluateOptions& options = args->options;
  auto* command =
      app.add_subcommand("eval", "Evaluate a BRDF (fit.json, measured table or material file) at given directions");
  command->footer(kFooter);
  command->add_option("model", options.model, "fit.json, measured table, or material JSON")->required();
  auto* wi = addParsed(command, "--wi", options.wi, parseVec3, "Light direction X,Y,Z (local frame)");
  auto* wo = addParsed(command, "--wo", options.wo, parseVec3, "View direction X,Y,Z (local frame)");
  command->add_option("--pairs", options.pairs, "File of 'theta_i phi_i theta_s phi_s' lines (radians)")
      ->excludes(wi)
      ->excludes(wo);
  addParsed(command, "--format", options.format, parseTableFormat,
            "Table format when MODEL is a table: auto (by content) | astm | pbrt | merl | mat")
      ->default_str("auto");
  addCommonFlags(command, args->flags, Computes::Values, "the model, its channels and the values");
  return [args] {
    const EvaluateResult result = evaluateBrdf(args->options);
    if (!args->flags.json && !args->flags.quiet) writeStderr(result.columnsLine());
    return printResult(result, args->flags, Printing::Query, -1);
  };
}

}  // namespace brdfbake::cli
