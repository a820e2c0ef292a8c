#include <brdfbake/bake/baker.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/run/gnuplot.hpp>

#include "chart_internal.hpp"

namespace brdfbake {
using namespace run_detail;

namespace {

// Every input and output checked before any work.
void checkFiles(const BakeSpec& spec, const ChartOptions& options) {
  FilePlan plan;
  plan.addInput(options.spec, "spec");
  for (const auto& map : spec.maps) {
    for (const auto& input : map.inputs) plan.addInput(input.file, input.role);
  }
  if (!options.chart.empty()) plan.addOutput(options.chart, "chart");
  if (!options.csv.empty()) plan.addOutput(options.csv, "CSV");
  plan.check();
}

template <class T>
void requireListIn(const std::vector<T>& values, T lowest, T highest, const std::string& what) {
  require(!values.empty(), what + ": the list is empty");
  for (const T& v : values) require(v >= lowest && v <= highest, what + ": each must be in the documented range");
}

}  // namespace

void ChartOptions::validate() const {
  requireListIn(resolutions, 1, 65536, "resolutions");
  requireListIn(environmentResolutions, 1, 65536, "environment resolutions");
  requireListIn(samplesPerTexel, 1, 4096, "samples per texel");
  require(!parameterizations.empty() && !methods.empty(), "parameterizations and methods must not be empty");
  require(maxError == 0.0 || (maxError >= 1e-6 && maxError <= 0.5), "max error must be in [1e-6, 0.5] (0: the map's)");
  require(subset >= 16 && subset <= 1000000, "subset must be in [16, 1e6]");
  require(lookups >= 100 && lookups <= 10000000, "lookups must be in [100, 1e7]");
  if (!chart.empty()) checkChartPath(chart);
}

ChartResult chartSpec(const ChartOptions& options, const Context& context) {
  options.validate();
  BakeSpec spec = loadBakeSpec(options.spec);
  checkFiles(spec, options);
  // Environments are read (and checked) before any work, as runSpec does.
  std::vector<std::optional<Environment>> environments(spec.maps.size());
  for (std::size_t i = 0; i < spec.maps.size(); ++i)
    if (const EnvironmentMapSpec* e = spec.maps[i].environmentMap()) {
      environments[i] = loadEnvironment(e->file, EnvironmentLoadOptions{e->from});
    }
  // Warm up the thread pool, so the first point does not carry its start-up.
  bake(*makeParameterization(ParameterizationKind::Sphere, 8), ConstantEnvironment(), {}, context.withoutProgress());

  ChartResult result;
  std::vector<std::string> panels;  // one chart per map, drawn into the chart as one picture
  for (std::size_t m = 0; m < spec.maps.size(); ++m) {
    MapSpec& map = spec.maps[m];
    MapChart chart =
        std::visit(Overloaded{[&](const EnvironmentMapSpec& e) {
                                return chartEnvironmentMap(map, e, *environments[m], options, context, result.skipped);
                              },
                              [&](const MaterialMapSpec&) { return chartMaterialMap(map, options, context); }},
                   map.content);
    markPareto(chart.points, options.lookupError);
    if (!options.chart.empty() && !chart.points.empty()) panels.push_back(chartScript(chart, options.lookupError));
    result.points.insert(result.points.end(), chart.points.begin(), chart.points.end());
  }
  if (!panels.empty()) {
    renderChart(panels, options.chart);
    result.chart = options.chart;
    result.panels = static_cast<int>(panels.size());
    result.files.push_back(options.chart);
  }
  if (!options.csv.empty())
    writeFileAtomically(options.csv, chartCsv(result.points)), result.files.push_back(options.csv);
  return result;
}

std::string ChartResult::briefReport() const {
  std::string text;
  for (const auto& skip : skipped) text += skipLine(skip) + "\n";
  if (!chart.empty()) {
    text += "wrote " + chart.string() + " (" + std::to_string(panels) +
            (panels == 1 ? " chart)\n" : " charts, one per map)\n");
  }
  for (const auto& file : files)
    if (file != chart) text += "wrote " + file.string() + "\n";
  return text;
}

nlohmann::json ChartResult::toJson() const {
  nlohmann::json report = nlohmann::json::array();
  for (const auto& p : points) report.push_back(pointJson(p, chart));
  for (const auto& skip : skipped) report.push_back(skipJson(skip));
  return report;
}

}  // namespace brdfbake
