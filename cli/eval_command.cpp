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

struct EvalArgs {
  CommonFlags flags;
  std::string model, wi, wo, pairs, format = "auto";
};

int runEval(const EvalArgs& a) {
  EvaluateOptions options;
  options.model = a.model;
  options.format = parseFlag("--format", a.format, parseTableFormat);
  if (!a.wi.empty()) options.wi = parseVector(a.wi, "--wi");
  if (!a.wo.empty()) options.wo = parseVector(a.wo, "--wo");
  options.pairs = a.pairs;
  if (options.wi.has_value() != options.wo.has_value()) {
    throw Error(Error::Kind::InvalidArgument, "--wi and --wo go together");
  }
  if (options.wi && (!(options.wi->norm() > 0.0) || !(options.wo->norm() > 0.0))) {
    throw Error(Error::Kind::InvalidArgument, "--wi and --wo must be non-zero");
  }
  if (!options.wi && a.pairs.empty())
    throw Error(Error::Kind::InvalidArgument, "give either --wi and --wo, or --pairs FILE");
  const EvaluateResult result = evaluateBrdf(options);
  if (!a.flags.json && !a.flags.quiet) writeStderr(result.columnsLine());
  return printResult(result, a.flags, Printing::Query, -1);
}

}  // namespace

Command addEvalCommand(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  auto* command =
      app.add_subcommand("eval", "Evaluate a BRDF (fit.json, measured table or material file) at given directions");
  command->footer(kFooter);
  command->add_option("model", args->model, "fit.json, measured table, or material JSON")->required();
  auto* wi = command->add_option("--wi", args->wi, "Light direction X,Y,Z (local frame)");
  auto* wo = command->add_option("--wo", args->wo, "View direction X,Y,Z (local frame)");
  command->add_option("--pairs", args->pairs, "File of 'theta_i phi_i theta_s phi_s' lines (radians)")
      ->excludes(wi)
      ->excludes(wo);
  command->add_option("--format", args->format, "Table format when MODEL is a table (auto: by content)")
      ->default_str("auto");
  addComputeFlags(command, args->flags, /*makesMaps=*/false);
  addOutputFlags(command, args->flags, "the model, its channels and the values");
  return [args] { return runEval(*args); };
}

}  // namespace brdfbake::cli
