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

}  // namespace

Command addInterpolationCommand(CLI::App& app) {
  struct InterpolationArgs {
    CommonFlags flags;
    InterpolationOptions options;
  };
  auto args = std::make_shared<InterpolationArgs>();
  InterpolationOptions& o = args->options;
  auto* command =
      app.add_subcommand("interpolation", "Chart the error of per-vertex environment lookups, to pick a tessellation");
  command->footer(kFooter);
  command->add_option("-o,--output", o.chart, "Sweep chart (.png or .svg)");
  command->add_option("--line-chart", o.lineChart, "Also chart the line experiment (.png or .svg)");
  command->add_option("--csv", o.csv, "Also write the sweep as CSV");
  addParsed(command, "--sizes", o.sizesDegrees, listOf(parseFiniteNumber),
            "Triangle sizes, degrees between vertex normals")
      ->default_str("1,2,5,10,20");
  addParsed(command, "--places", o.placesDegrees, listOf(parseFiniteNumber),
            "Triangle centres, degrees from the view axis")
      ->default_str("0,10,20,30,40,50,60,70,75,80,85,88");
  addParsed(command, "--viewer", o.viewer, parseVec3, "Line experiment: viewer position X,Y,Z")
      ->default_str("-8.3,1,0");
  command->add_option("--segment", o.segment, "Line experiment: vertex spacing (20 = one polygon)")
      ->default_val(20.0)
      ->check(CLI::Range(0.01, 20.0));
  addCommonFlags(command, args->flags, Computes::Values, "the sweep and the line experiment");
  return [args] {
    const InterpolationOptions& options = args->options;
    if (options.chart.empty() && options.lineChart.empty() && options.csv.empty() && !args->flags.json) {
      throw Error(Error::Kind::InvalidArgument,
                  "nothing to write: give -o CHART, --line-chart CHART, --csv FILE or --json");
    }
    return printResult(namingFields({}, [&] { return chartInterpolation(options); }), args->flags);
  };
}

}  // namespace brdfbake::cli
