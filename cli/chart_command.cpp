// brdfbake chart SPEC.json -o chart.png: time against accuracy for the maps of a spec (chartSpec).
#include <brdfbake/run/chart.hpp>

#include "commands.hpp"
#include "flags.hpp"

namespace brdfbake::cli {

namespace {

constexpr const char* kFooter =
    R"(Material maps: every parameterization x resolution x samples per texel is baked, timed and its
bilinear lookups measured against the exact model (the error `auto` bounds: max of the value-weighted
RMS and the lookup RMS, relative to the peak). Prefiltered environment maps: every parameterization
x resolution x method is prefiltered (each method set for the map's max_error or --max-error), timed
and measured against the reference prefilter on --subset random texels (and lookups); the reference
runs once per parameterization and resolution. Mirror maps, gloss chains and lobes varying with
elevation are skipped with a note. Default resolutions: 32,64,128,256,512 for materials, 16,32,64
for environments (--resolution sets both). One panel per map in -o (needs gnuplot); --csv and
--json list the points. docs/charts.md.

Examples:
  brdfbake chart data_samples/specs/phong_eye.json -o phong_chart.png --csv phong_chart.csv
  brdfbake chart spec.json -o c.svg --resolution 64,256 --samples-per-texel 1,16 --parameterizations sphere,cube
  brdfbake chart data_samples/specs/prefilter_sky.json -o sky.png --methods auto,sh,direct)";

struct ChartArgs {
  CommonFlags flags;
  ChartOptions options;
  std::string resolutions, samples = "1,4,16", parameterizations = "sphere,paraboloid,cube,latlong",
                           methods = "auto,sh,direct,importance", environmentError = "texel", spec, chart, csv;
};

void addChartFlags(CLI::App* command, ChartArgs& a) {
  command->add_option("spec", a.spec, "Spec file")->required();
  command->add_option("-o,--output", a.chart, "Chart (.png or .svg); several maps: one panel each");
  command->add_option("--csv", a.csv, "Also write the points as CSV");
  command->add_option("--resolution", a.resolutions, "Comma-separated resolutions (both kinds of map)");
  command->add_option("--resolutions", a.resolutions, "(old spelling of --resolution)")->group("");
  command->add_option("--samples-per-texel", a.samples, "Comma-separated samples per texel (material maps)")
      ->default_str(a.samples);
  command->add_option("--samples", a.samples, "(old spelling of --samples-per-texel)")->group("");
  command->add_option("--parameterizations", a.parameterizations, "Comma-separated parameterizations")
      ->default_str(a.parameterizations);
  command
      ->add_option("--methods", a.methods,
                   "Prefilter methods (environment maps): auto, sh, direct, importance, "
                   "reference")
      ->default_str(a.methods);
  command
      ->add_option("--max-error", a.options.maxError,
                   "Environment maps: the bound methods are set for "
                   "(default: each map's max_error)")
      ->check(CLI::Range(1e-6, 0.5));
  command->add_option("--subset", a.options.subset, "Environment maps: random texels compared with the reference")
      ->default_val(256);
  command->add_option("--environment-error", a.environmentError, "Environment maps: texel or lookup error charted")
      ->default_str(a.environmentError)
      ->check(CLI::IsMember({"texel", "lookup"}));
  command->add_option("--lookups", a.options.lookups, "Material maps: random directions per error measurement")
      ->default_val(20000);
}

int runChart(ChartArgs a) {
  if (a.chart.empty() && a.csv.empty() && !a.flags.json) {
    throw Error(Error::Kind::InvalidArgument, "chart: give -o CHART.png, --csv FILE or --json (nothing to write)");
  }
  ChartOptions& options = a.options;
  options.spec = a.spec;
  options.chart = a.chart;
  options.csv = a.csv;
  if (!a.resolutions.empty()) {
    options.resolutions = parseList<int>(a.resolutions, "--resolution", parseWholeNumber);
    options.environmentResolutions = options.resolutions;
  }
  options.samplesPerTexel = parseList<int>(a.samples, "--samples-per-texel", parseWholeNumber);
  options.parameterizations = parseList<ParameterizationKind>(
      a.parameterizations, "--parameterizations", [](const std::string& s) { return parseParameterizationKind(s); });
  options.methods =
      parseList<PrefilterMethod>(a.methods, "--methods", [](const std::string& s) { return parsePrefilterMethod(s); });
  options.lookupError = a.environmentError == "lookup";
  return printResult(withProgress(a.flags, options, chartSpec), a.flags);
}

}  // namespace

Command addChartCommand(CLI::App& app) {
  auto args = std::make_shared<ChartArgs>();
  auto* command = app.add_subcommand("chart", "Chart bake or prefilter time against accuracy for the maps of a spec");
  command->footer(kFooter);
  addChartFlags(command, *args);
  addComputeFlags(command, args->flags, /*makesMaps=*/false);
  addOutputFlags(command, args->flags, "the points (skipped ones with \"skipped\": true)");
  return [args] { return runChart(*args); };
}

}  // namespace brdfbake::cli
