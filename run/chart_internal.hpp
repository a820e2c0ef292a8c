#pragma once
// The parts of chartSpec (run/chart.hpp): sweeping one map (chart_sweep.cpp) and drawing and
// writing the points (chart_plot.cpp). Private to the run layer.
#include <brdfbake/env/environment.hpp>
#include <brdfbake/run/chart.hpp>
#include <brdfbake/spec/spec.hpp>

namespace brdfbake::run_detail {

/// One map's points and its panel's title (no points: nothing to draw).
struct MapChart {
  std::vector<ChartPoint> points;
  std::string title;
  bool environment = false;
};

MapChart chartEnvironmentMap(const MapSpec& map, const EnvironmentMapSpec& e, const Environment& environment,
                             const ChartOptions& options, const Context& context, std::vector<ChartSkip>& skipped);
MapChart chartMaterialMap(MapSpec& map, const ChartOptions& options, const Context& context);

/// Marks the points no other point beats in both time and charted error.
void markPareto(std::vector<ChartPoint>& points, bool lookups);
/// The gnuplot panel of one map.
std::string chartScript(const MapChart& chart, bool lookups);
/// The points as CSV.
std::string chartCsv(const std::vector<ChartPoint>& points);
/// A point and a skipped map as the JSON report lists them.
nlohmann::json pointJson(const ChartPoint& point, const std::filesystem::path& chart);
nlohmann::json skipJson(const ChartSkip& skip);
std::string skipLine(const ChartSkip& skip);

}  // namespace brdfbake::run_detail
