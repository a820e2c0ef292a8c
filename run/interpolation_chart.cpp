#include <brdfbake/io/files.hpp>
#include <brdfbake/run/gnuplot.hpp>
#include <brdfbake/run/interpolation_chart.hpp>

#include <sstream>

namespace brdfbake {

namespace {

// The sweep chart: per triangle size, the error against the place on the map, both schemes.
std::string sweepScript(const std::vector<double>& sizes, const std::vector<InterpolationPoint>& sweep) {
  std::ostringstream gp;
  gp << "set title 'Per-vertex interpolation error (solid: sphere-map (s,t); dashed: reflected vector)'\n"
        "set logscale y\nset grid\nset key outside right\nset format y '%g'\n"
        "set xlabel 'triangle centre, degrees between normal and view (90 = sphere-map rim)'\n"
        "set ylabel 'largest angular error (degrees)'\n";
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    gp << "$s" << i << " << EOD\n";
    for (const auto& p : sweep)
      if (p.sizeDegrees == sizes[i])
        gp << p.placeDegrees << " " << std::max(p.sphereMapError, 1e-6) << " " << std::max(p.reflectedVectorError, 1e-6)
           << "\n";
    gp << "EOD\n";
  }
  gp << "plot ";
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    std::ostringstream size;
    size << sizes[i];
    gp << "$s" << i << " using 1:2 with linespoints lw 2 lc " << i + 1 << " title '" << size.str() << " deg, (s,t)', "
       << "$s" << i << " using 1:3 with linespoints lw 1 dt 2 lc " << i + 1 << " title '" << size.str() << " deg, r'"
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

FilePlan planOutputs(const InterpolationOptions& options) {
  FilePlan plan;
  if (!options.chart.empty()) checkChartPath(options.chart), plan.addOutput(options.chart, "chart");
  if (!options.lineChart.empty()) checkChartPath(options.lineChart), plan.addOutput(options.lineChart, "line chart");
  if (!options.csv.empty()) plan.addOutput(options.csv, "CSV");
  return plan;
}

}  // namespace

void InterpolationOptions::validate() const {
  requireField(!sizesDegrees.empty(), "sizes", "must not be empty");
  requireField(!placesDegrees.empty(), "places", "must not be empty");
  for (double s : sizesDegrees) requireField(s > 0 && s <= 60, "sizes", "each must be in (0, 60] degrees");
  for (double p : placesDegrees) requireField(p >= 0 && p < 90, "places", "each must be in [0, 90) degrees");
  requireField(viewer.allFinite() && viewer.norm() <= 1e6, "viewer",
               "the eye must be a finite point within 1e6 units of the surface's centre");
  requireField(viewer.y() > 0.0, "viewer", "the eye must be above the surface (y > 0), where it sees the reflection");
  requireField(segment >= 0.01 && segment <= 20.0, "segment", "the vertex spacing must be in [0.01, 20]");
}

InterpolationResult chartInterpolation(const InterpolationOptions& options, const Context& context) {
  context.checkCancelled();
  options.validate();
  planOutputs(options).check();
  InterpolationResult result;
  result.sweep = interpolationSweep(options.sizesDegrees, options.placesDegrees);
  result.line = planarLineExperiment(options.viewer, options.segment);
  result.segment = options.segment;
  if (!options.chart.empty()) {
    renderChart({sweepScript(options.sizesDegrees, result.sweep)}, options.chart);
    result.files.push_back(options.chart);
  }
  if (!options.lineChart.empty()) {
    renderChart({lineScript(result.line, options.viewer, options.segment)}, options.lineChart);
    result.files.push_back(options.lineChart);
  }
  if (!options.csv.empty())
    writeFileAtomically(options.csv, sweepCsv(result.sweep)), result.files.push_back(options.csv);
  return result;
}

std::string InterpolationResult::briefReport() const {
  std::ostringstream out;
  for (const auto& file : files) out << "wrote " << file.string() << "\n";
  out << "line experiment: max " << line.maxError << " degrees at x = " << line.maxAt << "\n";
  return out.str();
}

nlohmann::json InterpolationResult::toJson() const {
  nlohmann::json points = nlohmann::json::array();
  for (const auto& p : sweep) {
    points.push_back({{"size_degrees", p.sizeDegrees},
                      {"place_degrees", p.placeDegrees},
                      {"sphere_map_error_degrees", p.sphereMapError},
                      {"reflected_vector_error_degrees", p.reflectedVectorError}});
  }
  return {{"sweep", points},
          {"line", {{"max_error_degrees", line.maxError}, {"at_x", line.maxAt}, {"segment", segment}}},
          {"files", pathsToJson(files)}};
}

}  // namespace brdfbake
