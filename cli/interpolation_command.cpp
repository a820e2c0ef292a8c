// brdfbake interpolation -o error.png [--line-chart line.png]: per-vertex interpolation error of
// sphere-map texture coordinates and of reflected vectors, against the exact per-pixel lookup, and
// Zimmons 1999's line experiment.
#include <brdfbake/bake/interpolation_error.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>

#include <nlohmann/json.hpp>

#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "gnuplot.hpp"
#include "terminal.hpp"

namespace brdfbake::cli {
namespace fs = std::filesystem;

namespace {

struct Args {
  std::string output, lineChart, csv, sizes = "1,2,5,10,20", places = "0,10,20,30,40,50,60,70,75,80,85,88";
  std::string viewer = "-8.3,1,0";
  double segment = 20.0;
  bool json = false, quiet = false;
};

std::vector<double> parseNumbers(const std::string& text, const std::string& flag) {
  std::vector<double> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || !std::isfinite(v))
      throw Error(Error::Kind::InvalidArgument, flag + ": cannot read '" + item + "'");
    out.push_back(v);
  }
  if (out.empty()) throw Error(Error::Kind::InvalidArgument, flag + ": empty list");
  return out;
}
// The sweep chart: per triangle size, the error against the place on the map, both schemes.
std::string sweepScript(const std::vector<double>& sizes, const std::vector<InterpolationPoint>& sweep) {
  std::ostringstream gp;
  gp << "set title 'Per-vertex interpolation error (solid: sphere-map (s,t); dashed: reflected vector)'\n"
        "set logscale y\nset grid\nset key outside right\nset format y '%g'\n"
        "set xlabel 'triangle centre, degrees between normal and view (90 = sphere-map rim)'\n"
        "set ylabel 'largest angular error (degrees)'\n";
  for (double size : sizes) {
    gp << "$s" << static_cast<int>(size * 100) << " << EOD\n";
    for (const auto& p : sweep)
      if (p.sizeDegrees == size)
        gp << p.placeDegrees << " " << std::max(p.sphereMapError, 1e-6) << " " << std::max(p.reflectedVectorError, 1e-6)
           << "\n";
    gp << "EOD\n";
  }
  gp << "plot ";
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    const std::string block = "$s" + std::to_string(static_cast<int>(sizes[i] * 100));
    std::ostringstream size;
    size << sizes[i];
    gp << block << " using 1:2 with linespoints lw 2 lc " << i + 1 << " title '" << size.str() << " deg, (s,t)', "
       << block << " using 1:3 with linespoints lw 1 dt 2 lc " << i + 1 << " title '" << size.str() << " deg, r'"
       << (i + 1 < sizes.size() ? ", " : "\n");
  }
  return gp.str();
}

// The line experiment's chart: the error along x.
std::string lineScript(const LineExperiment& line, const Vec3& viewer, double segment) {
  std::ostringstream gp;
  gp << "set title 'Zimmons 1999 line experiment: viewer (" << viewer.x() << ", " << viewer.y() << ", " << viewer.z()
     << "), vertices every " << segment << " units; max " << line.maxError << " deg at x = " << line.maxAt << "'\n"
     << "set grid\nset xlabel 'x'\nset ylabel 'angle between interpolated and computed r (degrees)'\n$line << EOD\n";
  for (std::size_t i = 0; i < line.x.size(); ++i) gp << line.x[i] << " " << line.errorDegrees[i] << "\n";
  gp << "EOD\nplot $line using 1:2 with lines lw 2 notitle\n";
  return gp.str();
}

std::string sweepCsv(const std::vector<InterpolationPoint>& sweep) {
  std::ostringstream csv;
  csv << "size_degrees,place_degrees,sphere_map_error_degrees,reflected_vector_error_degrees\n";
  for (const auto& p : sweep)
    csv << p.sizeDegrees << "," << p.placeDegrees << "," << p.sphereMapError << "," << p.reflectedVectorError << "\n";
  return csv.str();
}

nlohmann::json runReport(const std::vector<InterpolationPoint>& sweep, const LineExperiment& line, const Args& args,
                         const std::vector<std::string>& written) {
  nlohmann::json points = nlohmann::json::array();
  for (const auto& p : sweep) {
    points.push_back({{"size_degrees", p.sizeDegrees},
                      {"place_degrees", p.placeDegrees},
                      {"sphere_map_error_degrees", p.sphereMapError},
                      {"reflected_vector_error_degrees", p.reflectedVectorError}});
  }
  return {{"sweep", points},
          {"line", {{"max_error_degrees", line.maxError}, {"at_x", line.maxAt}, {"segment", args.segment}}},
          {"files", written}};
}

// Checks the flags and the files before any work; returns the files to be written, in order.
FilePlan planOutputs(const Args& args) {
  if (args.output.empty() && args.lineChart.empty() && args.csv.empty() && !args.json) {
    throw Error(Error::Kind::InvalidArgument,
                "nothing to write: give -o CHART, --line-chart CHART, --csv FILE or --json");
  }
  FilePlan plan;
  if (!args.output.empty()) checkChartPath(args.output), plan.addOutput(args.output, "-o");
  if (!args.lineChart.empty()) checkChartPath(args.lineChart), plan.addOutput(args.lineChart, "--line-chart");
  if (!args.csv.empty()) plan.addOutput(args.csv, "--csv");
  plan.check();
  return plan;
}

void registerOptions(CLI::App* command, Args& args) {
  command->add_option("-o,--output", args.output, "Sweep chart (.png or .svg)");
  command->add_option("--line-chart", args.lineChart, "Also chart the line experiment (.png or .svg)");
  command->add_option("--csv", args.csv, "Also write the sweep as CSV");
  command->add_option("--sizes", args.sizes, "Triangle sizes, degrees between vertex normals")->default_str(args.sizes);
  command->add_option("--places", args.places, "Triangle centres, degrees from the view axis")
      ->default_str(args.places);
  command->add_option("--viewer", args.viewer, "Line experiment: viewer position X,Y,Z")->default_str(args.viewer);
  command->add_option("--segment", args.segment, "Line experiment: vertex spacing (20 = one polygon)")
      ->default_val(20.0)
      ->check(CLI::Range(0.01, 20.0));
  addJsonFlag(command, args.json, "the sweep and the line experiment");
  addQuietFlag(command, args.quiet);
}

int run(const Args& args) {
  planOutputs(args);
  const auto sizes = parseNumbers(args.sizes, "--sizes");
  const auto places = parseNumbers(args.places, "--places");
  for (double s : sizes)
    if (!(s > 0 && s <= 60)) throw Error(Error::Kind::InvalidArgument, "--sizes: each must be in (0, 60] degrees");
  for (double p : places)
    if (!(p >= 0 && p < 90)) throw Error(Error::Kind::InvalidArgument, "--places: each must be in [0, 90) degrees");
  const Vec3 viewer = parseVector(args.viewer, "--viewer");
  const auto sweep = interpolationSweep(sizes, places);
  const LineExperiment line = planarLineExperiment(viewer, args.segment);

  std::vector<std::string> written;
  if (!args.output.empty()) renderWithGnuplot(sweepScript(sizes, sweep), args.output), written.push_back(args.output);
  if (!args.lineChart.empty()) {
    renderWithGnuplot(lineScript(line, viewer, args.segment), args.lineChart);
    written.push_back(args.lineChart);
  }
  if (!args.csv.empty()) writeFileAtomically(args.csv, sweepCsv(sweep)), written.push_back(args.csv);
  if (args.json) {
    std::cout << runReport(sweep, line, args, written).dump(2) << "\n";
  } else if (!args.quiet) {
    for (const auto& file : written) std::cout << "wrote " << file << "\n";
    std::cout << "line experiment: max " << line.maxError << " degrees at x = " << line.maxAt << "\n";
  }
  return 0;
}

}  // namespace

Command addInterpolationCommand(CLI::App& app) {
  auto args = std::make_shared<Args>();
  auto* command =
      app.add_subcommand("interpolation", "Chart the error of per-vertex environment lookups, to pick a tessellation");
  command->footer(R"(Triangles of normals SIZE degrees apart, centred PLACE degrees from the view axis (eye space,
orthographic view +z; PLACE 90 is the sphere map's rim): the largest angle between the direction
looked up and the exact reflected vector of the interpolated normal, for per-vertex sphere-map
texture coordinates interpolated linearly (fixed-function GL_SPHERE_MAP) and for per-vertex reflected
vectors interpolated linearly (hardware cube mapping).

The line experiment (Zimmons 1999): a flat surface over x in [-10, 10] (normal +y), a perspective
viewer at --viewer, reflected vectors computed at vertices every --segment units and interpolated
between them; its maximum is always reported (text and --json), its chart only with --line-chart.

Outputs, each named by its own flag (as on every command, -o names one file): -o the sweep chart,
--line-chart the line chart, --csv the sweep as CSV, --json the run report. Give at least one.

Examples:
  brdfbake interpolation -o interpolation.png --csv interpolation.csv
  brdfbake interpolation -o i.svg --line-chart line.svg --sizes 2,8 --viewer -8.3,1,0 --segment 1)");
  registerOptions(command, *args);
  return [args] { return run(*args); };
}

}  // namespace brdfbake::cli
