// Drawing and listing chart points (run/chart.hpp): gnuplot panels, CSV, the JSON report.
#include <algorithm>
#include <sstream>

#include "chart_internal.hpp"

namespace brdfbake::run_detail {

namespace {

// The error a point is charted (and its Pareto front taken) by: for material maps the bound
// max_error means (docs/accuracy.md), for environments the texel or lookup RMS relative error.
double plotted(const ChartPoint& p, bool lookups) {
  if (!p.environment) return p.bound;
  return lookups ? p.lookupRms : p.rms;
}

// Log scales cannot show 0 (an exact furnace): plotted errors are floored.
double plottable(double error) { return std::max(error, 1e-9); }

std::string optionalNumber(double value) {
  if (value < 0.0) return "";
  std::ostringstream out;
  out << value;
  return out.str();
}

template <class Key>
std::vector<std::string> distinct(const std::vector<ChartPoint>& points, Key key) {
  std::vector<std::string> values;
  for (const auto& p : points)
    if (std::find(values.begin(), values.end(), key(p)) == values.end()) values.push_back(key(p));
  return values;
}

std::string paretoBlock(const std::vector<ChartPoint>& points, bool lookups) {
  std::vector<ChartPoint> front;
  for (const auto& p : points)
    if (p.pareto) front.push_back(p);
  std::sort(front.begin(), front.end(), [](const auto& a, const auto& b) { return a.seconds < b.seconds; });
  std::ostringstream gp;
  gp << "$pareto << EOD\n";
  for (const auto& p : front) gp << p.seconds << " " << plottable(plotted(p, lookups)) << "\n";
  gp << "EOD\n";
  return gp.str();
}

// Material maps: log-log time against error, one colour per parameterization, labels
// resolution/samples, the Pareto front as a line.
std::string materialScript(const std::vector<ChartPoint>& points, const std::string& title) {
  std::ostringstream gp;
  gp << "set title '" << title << "'\nset logscale xy\nset grid\nset key outside right\n";
  gp << "set xlabel 'bake time (s)'\nset ylabel 'error: max(value-weighted RMS, lookup RMS) / peak'\n"
        "set format x '%g'\nset format y '%g'\n";
  const auto kinds = distinct(points, [](const ChartPoint& p) { return p.parameterization; });
  for (const auto& kind : kinds) {
    gp << "$" << kind << " << EOD\n";
    for (const auto& p : points)
      if (p.parameterization == kind)
        gp << p.seconds << " " << plottable(p.bound) << " \"" << p.resolution << "/" << p.samples << "\"\n";
    gp << "EOD\n";
  }
  gp << paretoBlock(points, false) << "plot ";
  for (const auto& kind : kinds) {
    gp << "$" << kind << " using 1:2 with points pt 7 ps 1.2 title '" << kind << "', ";
    gp << "$" << kind << " using 1:2:3 with labels font ',7' offset 0,0.8 notitle, ";
  }
  gp << "$pareto using 1:2 with lines lw 2 lc rgb 'black' title 'Pareto front'\n";
  return gp.str();
}

// Environment maps: one colour per method, one point shape per parameterization, labels the
// resolution, Pareto points ringed and joined.
std::string environmentScript(const std::vector<ChartPoint>& points, const std::string& title, bool lookups) {
  static const char* colours[] = {"#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#7f7f7f", "#9467bd"};
  static const int shapes[] = {7, 5, 9, 13, 11};  // filled circle, square, triangle, diamond, inverted triangle
  const auto methods = distinct(points, [](const ChartPoint& p) { return p.method; });
  const auto kinds = distinct(points, [](const ChartPoint& p) { return p.parameterization; });
  std::ostringstream gp;
  gp << "set title '" << title << "'\nset logscale xy\nset grid\nset key outside right\n";
  gp << "set xlabel 'prefilter time (s)'\nset ylabel '"
     << (lookups ? "RMS relative error of bilinear lookups" : "RMS relative error at texels") << " (vs reference)'\n"
     << "set format x '%g'\nset format y '%g'\n";
  std::vector<std::string> plots;
  for (std::size_t m = 0; m < methods.size(); ++m) {
    for (std::size_t k = 0; k < kinds.size(); ++k) {
      const std::string block = "$m" + std::to_string(m) + "k" + std::to_string(k);
      std::ostringstream data;
      for (const auto& p : points)
        if (p.method == methods[m] && p.parameterization == kinds[k])
          data << p.seconds << " " << plottable(plotted(p, lookups)) << " \"" << p.resolution << "\"\n";
      if (data.str().empty()) continue;
      gp << block << " << EOD\n" << data.str() << "EOD\n";
      const std::string colour = std::string("lc rgb '") + colours[m % 6] + "'";
      plots.push_back(block + " using 1:2 with points pt " + std::to_string(shapes[k % 5]) + " ps 1.3 " + colour +
                      " notitle");
      plots.push_back(block + " using 1:2:3 with labels font ',7' offset 0,0.8 tc rgb '" + colours[m % 6] +
                      "' notitle");
    }
  }
  gp << paretoBlock(points, lookups);
  // Key entries: methods by colour, parameterizations by shape (points outside any range).
  for (std::size_t m = 0; m < methods.size(); ++m)
    plots.push_back("NaN with points pt 7 ps 1.3 lc rgb '" + std::string(colours[m % 6]) + "' title '" + methods[m] +
                    "'");
  for (std::size_t k = 0; k < kinds.size(); ++k)
    plots.push_back("NaN with points pt " + std::to_string(shapes[k % 5]) + " ps 1.3 lc rgb 'black' title '" +
                    kinds[k] + "'");
  plots.push_back("$pareto using 1:2 with points pt 6 ps 2.2 lw 1.5 lc rgb 'black' notitle");
  plots.push_back("$pareto using 1:2 with lines lw 2 lc rgb 'black' title 'Pareto front'");
  gp << "plot ";
  for (std::size_t i = 0; i < plots.size(); ++i) gp << (i ? ", \\\n  " : "") << plots[i];
  gp << "\n";
  return gp.str();
}

}  // namespace

void markPareto(std::vector<ChartPoint>& points, bool lookups) {
  for (auto& p : points) {
    const double e = plotted(p, lookups);
    p.pareto = std::none_of(points.begin(), points.end(), [&](const ChartPoint& q) {
      const double f = plotted(q, lookups);
      return q.seconds <= p.seconds && f <= e && (q.seconds < p.seconds || f < e);
    });
  }
}

std::string chartScript(const MapChart& chart, bool lookups) {
  return chart.environment ? environmentScript(chart.points, chart.title, lookups)
                           : materialScript(chart.points, chart.title);
}

std::string chartCsv(const std::vector<ChartPoint>& points) {
  std::ostringstream out;
  // The first ten columns are those of material charts before environment maps were charted.
  out << "map,parameterization,resolution,samples_per_texel,texels,seconds,rms,max,visible_rms,pareto,"
         "method,detail,estimate,lookup_rms,lookup_max,reference_seconds,highlight_rms,highlight_max,error\n";
  for (const auto& p : points) {
    std::string detail = p.detail;
    std::replace(detail.begin(), detail.end(), ',', ';');
    out << p.map << "," << p.parameterization << "," << p.resolution << "," << p.samples << "," << p.texels << ","
        << p.seconds << "," << p.rms << "," << p.max << "," << p.visibleRms << "," << p.pareto << "," << p.method << ","
        << detail << "," << optionalNumber(p.estimate) << "," << optionalNumber(p.lookupRms) << ","
        << optionalNumber(p.lookupMax) << "," << optionalNumber(p.referenceSeconds) << ","
        << optionalNumber(p.highlightRms) << "," << optionalNumber(p.highlightMax) << "," << optionalNumber(p.bound)
        << "\n";
  }
  return out.str();
}

nlohmann::json pointJson(const ChartPoint& p, const std::filesystem::path& chart) {
  nlohmann::json entry = {{"map", p.map},
                          {"parameterization", p.parameterization},
                          {"resolution", p.resolution},
                          {"samples_per_texel", p.samples},
                          {"texels", p.texels},
                          {"seconds", p.seconds},
                          {"rms", p.rms},
                          {"max", p.max},
                          {"visible_rms", p.visibleRms},
                          {"pareto", p.pareto},
                          {"method", p.method}};
  if (!chart.empty()) entry["chart"] = chart.string();
  if (!p.environment) {
    entry["highlight_rms"] = p.highlightRms;
    entry["highlight_max"] = p.highlightMax;
    entry["error"] = p.bound;
    return entry;
  }
  entry["detail"] = p.detail;
  entry["estimate"] = p.estimate >= 0.0 ? nlohmann::json(p.estimate) : nlohmann::json(nullptr);
  entry["met_bound"] = p.metBound;
  entry["lookup_rms"] = p.lookupRms;
  entry["lookup_max"] = p.lookupMax;
  entry["reference_seconds"] = p.referenceSeconds;
  return entry;
}

nlohmann::json skipJson(const ChartSkip& k) {
  nlohmann::json entry = {{"map", k.map}, {"skipped", true}, {"note", k.note}};
  if (!k.method.empty()) {
    entry["parameterization"] = k.parameterization;
    entry["resolution"] = k.resolution;
    entry["method"] = k.method;
  }
  return entry;
}

std::string skipLine(const ChartSkip& k) {
  std::string line = "note: " + k.map;
  if (!k.method.empty())
    line += " " + k.parameterization + " " + std::to_string(k.resolution) + " " + k.method + " skipped";
  return line + ": " + k.note;
}

}  // namespace brdfbake::run_detail
