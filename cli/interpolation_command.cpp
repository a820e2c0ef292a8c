// brdfbake interpolation -o error.png: the error of per-vertex environment lookups (chartInterpolation).
#include <brdfbake/run/interpolation_chart.hpp>

#include "commands.hpp"
#include "flags.hpp"

namespace brdfbake::cli {

namespace {

constexpr const char* kFooter =
    R"(Triangles of normals SIZE degrees apart, centred PLACE degrees from the view axis (eye space,
orthographic view +z; PLACE 90 is the sphere map's rim): the largest angle between the direction
looked up and the exact reflected vector of the interpolated normal, for per-vertex sphere-map
texture coordinates interpolated linearly (fixed-function GL_SPHERE_MAP) and for per-vertex
reflected vectors interpolated linearly (hardware cube mapping).

The line experiment (Zimmons 1999): a flat surface over x in [-10, 10] (normal +y), a perspective
viewer at --viewer (above it, y > 0), reflected vectors computed at vertices every --segment units
and interpolated between them; its maximum is always reported, its chart with --line-chart.
Outputs, each its own flag: -o the sweep chart, --line-chart, --csv, --json. Give at least one.

Examples:
  brdfbake interpolation -o interpolation.png --csv interpolation.csv
  brdfbake interpolation -o i.svg --line-chart line.svg --sizes 2,8 --viewer -8.3,1,0 --segment 1)";

struct InterpolationArgs {
  CommonFlags flags;
  InterpolationOptions options;
  std::string chart, lineChart, csv, sizes = "1,2,5,10,20", places = "0,10,20,30,40,50,60,70,75,80,85,88",
                                     viewer = "-8.3,1,0";
};

int runInterpolation(InterpolationArgs a) {
  if (a.chart.empty() && a.lineChart.empty() && a.csv.empty() && !a.flags.json) {
    throw Error(Error::Kind::InvalidArgument,
                "nothing to write: give -o CHART, --line-chart CHART, --csv FILE or --json");
  }
  InterpolationOptions& options = a.options;
  options.chart = a.chart;
  options.lineChart = a.lineChart;
  options.csv = a.csv;
  options.sizesDegrees = parseList<double>(a.sizes, "--sizes", parseFiniteNumber);
  options.placesDegrees = parseList<double>(a.places, "--places", parseFiniteNumber);
  options.viewer = parseVector(a.viewer, "--viewer");
  const FieldFlags names = {
      {"sizes", "--sizes"}, {"places", "--places"}, {"viewer", "--viewer"}, {"segment", "--segment"}};
  return printResult(namingFields(names, [&] { return chartInterpolation(options); }), a.flags);
}

}  // namespace

Command addInterpolationCommand(CLI::App& app) {
  auto args = std::make_shared<InterpolationArgs>();
  auto* command =
      app.add_subcommand("interpolation", "Chart the error of per-vertex environment lookups, to pick a tessellation");
  command->footer(kFooter);
  command->add_option("-o,--output", args->chart, "Sweep chart (.png or .svg)");
  command->add_option("--line-chart", args->lineChart, "Also chart the line experiment (.png or .svg)");
  command->add_option("--csv", args->csv, "Also write the sweep as CSV");
  command->add_option("--sizes", args->sizes, "Triangle sizes, degrees between vertex normals")
      ->default_str(args->sizes);
  command->add_option("--places", args->places, "Triangle centres, degrees from the view axis")
      ->default_str(args->places);
  command->add_option("--viewer", args->viewer, "Line experiment: viewer position X,Y,Z")->default_str(args->viewer);
  command->add_option("--segment", args->options.segment, "Line experiment: vertex spacing (20 = one polygon)")
      ->default_val(20.0)
      ->check(CLI::Range(0.01, 20.0));
  addComputeFlags(command, args->flags, /*makesMaps=*/false);
  addOutputFlags(command, args->flags, "the sweep and the line experiment");
  return [args] { return runInterpolation(*args); };
}

}  // namespace brdfbake::cli
