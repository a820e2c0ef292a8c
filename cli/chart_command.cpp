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
  std::optional<std::vector<int>> resolutions;
};

void addChartFlags(CLI::App* command, ChartArgs& a) {
  ChartOptions& o = a.options;
  command->add_option("spec", o.spec, "Spec file")->required();
  command->add_option("-o,--output", o.chart, "Chart (.png or .svg); several maps: one panel each");
  command->add_option("--csv", o.csv, "Also write the points as CSV");
  addParsed(command, "--resolution", a.resolutions, listOf(parseWholeNumber),
            "Comma-separated resolutions (both kinds of map)");
  addParsed(command, "--samples-per-texel", o.samplesPerTexel, listOf(parseWholeNumber),
            "Comma-separated samples per texel (material maps)")
      ->default_str("1,4,16");
  // The old spellings, hidden.
  addParsed(command, "--resolutions", a.resolutions, listOf(parseWholeNumber), "")->group("");
  addParsed(command, "--samples", o.samplesPerTexel, listOf(parseWholeNumber), "")->group("");
  addParsed(command, "--parameterizations", o.parameterizations, listOf(parseParameterizationKind),
            "Comma-separated parameterizations")
      ->default_str("sphere,paraboloid,cube,latlong");
  addParsed(command, "--methods", o.methods, listOf(parsePrefilterMethod),
            "Prefilter methods (environment maps): auto, sh, direct, importance, reference")
      ->default_str("auto,sh,direct,importance");
  command
      ->add_option("--max-error", o.maxError,
                   "Environment maps: the bound methods are set for (default: each map's max_error)")
      ->check(CLI::Range(1e-6, 0.5));
  command->add_option("--subset", o.subset, "Environment maps: random texels compared with the reference")
      ->default_val(256);
  command
      ->add_option_function<std::string>(
          "--environment-error", [&o](const std::string& text) { o.lookupError = text == "lookup"; },
          "Environment maps: texel or lookup error charted")
      ->check(CLI::IsMember({"texel", "lookup"}))
      ->default_str("texel");
  command->add_option("--lookups", o.lookups, "Material maps: random directions per error measurement")
      ->default_val(20000);
}

}  // namespace

Command addChartCommand(CLI::App& app) {
  auto args = std::make_shared<ChartArgs>();
  auto* command = app.add_subcommand("chart", "Chart bake or prefilter time against accuracy for the maps of a spec");
  command->footer(kFooter);
  addChartFlags(command, *args);
  addCommonFlags(command, args->flags, Computes::Values, "the points (skipped ones with \"skipped\": true)");
  return [args] {
    ChartOptions& options = args->options;
    if (options.chart.empty() && options.csv.empty() && !args->flags.json)
      throw Error(Error::Kind::InvalidArgument, "chart: give -o CHART.png, --csv FILE or --json (nothing to write)");
    if (args->resolutions) options.resolutions = options.environmentResolutions = *args->resolutions;
    return printResult(withProgress(args->flags, options, chartSpec), args->flags);
  };
}

}  // namespace brdfbake::cli
