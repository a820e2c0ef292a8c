// brdfbake chart SPEC.json -o chart.png: bake time against accuracy over parameterization x
// resolution x samples per texel, with the Pareto front marked.
#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/bake/image_io.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/importers/spec.hpp>

#include <fstream>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "gnuplot.hpp"
#include "terminal.hpp"

namespace brdfbake::cli {
namespace fs = std::filesystem;

namespace {

struct Point {
  std::string map, parameterization;
  int resolution = 0, samples = 0;
  long long texels = 0;
  double seconds = 0.0;
  ErrorStats error;
  bool pareto = false;
};

template <class T>
std::vector<T> parseList(const std::string& text, const std::string& flag, const std::function<T(const std::string&)>& parse) {
  std::vector<T> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    try {
      out.push_back(parse(item));
    } catch (const std::exception&) {
      throw Error(Error::Kind::InvalidArgument, flag + ": cannot read '" + item + "' in '" + text + "'");
    }
  }
  if (out.empty()) throw Error(Error::Kind::InvalidArgument, flag + ": empty list");
  return out;
}

// Marks the points no other point beats in both time and RMS error.
void markPareto(std::vector<Point>& points) {
  for (auto& p : points) {
    p.pareto = std::none_of(points.begin(), points.end(), [&](const Point& q) {
      return q.seconds <= p.seconds && q.error.rms <= p.error.rms && (q.seconds < p.seconds || q.error.rms < p.error.rms);
    });
  }
}

void writeCsv(const std::vector<Point>& points, const fs::path& path) {
  const fs::path temporary = path.string() + ".tmp";
  {
    std::ofstream out(temporary);
    out << "map,parameterization,resolution,samples_per_texel,texels,seconds,rms,max,visible_rms,pareto\n";
    for (const auto& p : points) {
      out << p.map << "," << p.parameterization << "," << p.resolution << "," << p.samples << "," << p.texels << ","
          << p.seconds << "," << p.error.rms << "," << p.error.max << "," << p.error.visibleRms << "," << p.pareto << "\n";
    }
    if (!out) throw Error(Error::Kind::Io, path.string() + ": cannot write");
  }
  fs::rename(temporary, path);
}

// Plots log-log time against RMS error, one colour per parameterization, the Pareto front as a line.
void plot(const std::vector<Point>& points, const std::string& title, const fs::path& output) {
  std::ostringstream gp;
  gp << "set title '" << title << "'\nset logscale xy\nset grid\nset key outside right\n";
  gp << "set xlabel 'bake time (s)'\nset ylabel 'RMS error (relative to peak)'\nset format x '%g'\nset format y '%g'\n";
  std::vector<std::string> kinds;
  for (const auto& p : points)
    if (std::find(kinds.begin(), kinds.end(), p.parameterization) == kinds.end()) kinds.push_back(p.parameterization);
  for (const auto& kind : kinds) {
    gp << "$" << kind << " << EOD\n";
    for (const auto& p : points)
      if (p.parameterization == kind) gp << p.seconds << " " << p.error.rms << " \"" << p.resolution << "/" << p.samples << "\"\n";
    gp << "EOD\n";
  }
  std::vector<Point> front;
  for (const auto& p : points)
    if (p.pareto) front.push_back(p);
  std::sort(front.begin(), front.end(), [](const Point& a, const Point& b) { return a.seconds < b.seconds; });
  gp << "$pareto << EOD\n";
  for (const auto& p : front) gp << p.seconds << " " << p.error.rms << "\n";
  gp << "EOD\nplot ";
  for (const auto& kind : kinds) {
    gp << "$" << kind << " using 1:2 with points pt 7 ps 1.2 title '" << kind << "', ";
    gp << "$" << kind << " using 1:2:3 with labels font ',7' offset 0,0.8 notitle, ";
  }
  gp << "$pareto using 1:2 with lines lw 2 lc rgb 'black' title 'Pareto front'\n";
  renderWithGnuplot(gp.str(), output);
}

}  // namespace

Command addChartCommand(CLI::App& app) {
  struct Args {
    std::string spec, output, csv;
    std::string resolutions = "32,64,128,256,512", samples = "1,4,16", parameterizations = "sphere,paraboloid,cube,latlong";
    int threads = 0, lookups = 20000;
    bool json = false;
  };
  auto args = std::make_shared<Args>();
  auto* command = app.add_subcommand("chart", "Chart bake time against accuracy for the maps of a spec");
  command->footer(R"(For each map of the spec, bakes every combination of parameterization x resolution x samples
per texel, measures the time and the error of bilinear lookups against the exact model (RMS and max
over directions uniform on the sphere, relative to the peak; for sphere maps also over the reflected
vectors of a visible sphere), and plots time against RMS error (log-log) with the Pareto front. Sphere
maps skip the rim (their singular set). Non-sphere maps of view-dependent materials use the spec's
view, or +z. Several maps: one chart each, NAME_1.png, NAME_2.png, ...

Examples:
  brdfbake chart data_samples/specs/phong_eye.json -o phong_chart.png --csv phong_chart.csv
  brdfbake chart spec.json -o c.svg --resolutions 64,256 --samples 1,16 --parameterizations sphere,cube)");
  command->add_option("spec", args->spec, "Spec file")->required();
  command->add_option("-o,--output", args->output, "Chart (.png or .svg)")->required();
  command->add_option("--csv", args->csv, "Also write the points as CSV");
  command->add_option("--resolutions", args->resolutions, "Comma-separated resolutions")->default_str(args->resolutions);
  command->add_option("--samples", args->samples, "Comma-separated samples per texel")->default_str(args->samples);
  command->add_option("--parameterizations", args->parameterizations, "Comma-separated parameterizations")->default_str(args->parameterizations);
  command->add_option("--lookups", args->lookups, "Random directions per error measurement")->default_val(20000)->check(CLI::Range(100, 10000000));
  command->add_option("--threads", args->threads, "Worker threads (0 = all cores)")->default_val(0)->check(CLI::NonNegativeNumber);
  command->add_flag("--json", args->json, "Print the points as JSON");
  return [args] {
    const auto toInt = [](const std::string& s) {
      std::size_t used = 0;
      const int v = std::stoi(s, &used);
      if (used != s.size() || v < 1) throw std::invalid_argument(s);
      return v;
    };
    const auto resolutions = parseList<int>(args->resolutions, "--resolutions", toInt);
    const auto samples = parseList<int>(args->samples, "--samples", toInt);
    const auto kinds = parseList<ParameterizationKind>(args->parameterizations, "--parameterizations",
                                                       [](const std::string& s) { return parseParameterizationKind(s); });
    const fs::path output = args->output;
    checkChartPath(output);
    const BakeSpec spec = loadBakeSpec(args->spec);
    // Warm up the thread pool, so the first point does not carry its start-up.
    bake(*makeParameterization(ParameterizationKind::Sphere, 8), *spec.maps.front().makeFunction());
    nlohmann::json report = nlohmann::json::array();
    std::vector<Point> all;
    for (std::size_t m = 0; m < spec.maps.size(); ++m) {
      const MapSpec& map = spec.maps[m];
      const auto function = map.makeFunction();
      std::vector<Point> points;
      ProgressBar bar(map.jsonPath, !args->json);
      const double total = double(kinds.size() * resolutions.size() * samples.size());
      int done = 0;
      for (const auto kind : kinds) {
        for (const int resolution : resolutions) {
          for (const int spt : samples) {
            const auto parameterization = makeParameterization(kind, resolution);
            BakeOptions options;
            options.samplesPerTexel = spt;
            options.threads = args->threads;
            BakeSummary summary;
            const Image image = bake(*parameterization, *function, options, &summary);
            ErrorOptions errorOptions;
            errorOptions.samples = args->lookups;
            Point p;
            p.map = map.jsonPath;
            p.parameterization = std::string(toString(kind));
            p.resolution = resolution;
            p.samples = spt;
            p.texels = static_cast<long long>(parameterization->width()) * parameterization->height();
            p.seconds = summary.seconds;
            p.error = measureMapError(image, *parameterization, *function, errorOptions);
            points.push_back(p);
            if (auto cb = bar.callback()) cb(++done / total);
          }
        }
      }
      markPareto(points);
      fs::path chart = output;
      if (spec.maps.size() > 1) chart = output.parent_path() / (output.stem().string() + "_" + std::to_string(m + 1) + output.extension().string());
      plot(points, map.jsonPath + ": " + std::string(map.material->model()) + " (" + map.output.filename().string() + ")", chart);
      for (const auto& p : points) {
        report.push_back({{"map", p.map}, {"parameterization", p.parameterization}, {"resolution", p.resolution},
                          {"samples_per_texel", p.samples}, {"texels", p.texels}, {"seconds", p.seconds},
                          {"rms", p.error.rms}, {"max", p.error.max}, {"visible_rms", p.error.visibleRms},
                          {"pareto", p.pareto}, {"chart", chart.string()}});
      }
      all.insert(all.end(), points.begin(), points.end());
      if (!args->json) std::cout << "wrote " << chart.string() << "\n";
    }
    if (!args->csv.empty()) writeCsv(all, args->csv);
    if (args->json) std::cout << report.dump(2) << "\n";
    return 0;
  };
}

}  // namespace brdfbake::cli
