// brdfbake chart SPEC.json -o chart.png: time against accuracy with the Pareto front marked, for
// every map of a spec. Material maps: bake time over parameterization x resolution x samples per
// texel, bilinear lookups against the exact model. Prefiltered environment maps: prefilter time
// over parameterization x resolution x method, against the reference prefilter on random output
// texels (env_accuracy.hpp). docs/charts.md.
#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/auto_config.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>
#include <brdfbake/env/env_accuracy.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/maps/image_io.hpp>
#include <brdfbake/spec/spec.hpp>

#include <chrono>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include "commands.hpp"
#include "gnuplot.hpp"
#include "terminal.hpp"

namespace brdfbake::cli {
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

// Default resolutions: materials bake fast; prefiltering also pays the reference on the subset and
// every method's error estimate, so environment maps default to smaller maps.
constexpr const char* kMaterialResolutions = "32,64,128,256,512";
constexpr const char* kEnvironmentResolutions = "16,32,64";

struct Point {
  std::string map, parameterization;
  std::string method = "bake";  // "bake" for material maps; auto, sh, direct, importance, reference
  std::string detail;           // the setting the prefilter chose ("order 16 on a 88x44 grid")
  int resolution = 0, samples = 0;
  long long texels = 0;
  double seconds = 0.0;
  double rms = 0.0, max = 0.0, visibleRms = 0.0;
  // Material maps only (-1: none): ErrorStats' value-weighted RMS and maximum, and the bound
  // max_error is checked against (ErrorStats::bound), which the chart plots.
  double highlightRms = -1.0, highlightMax = -1.0, bound = -1.0;
  // Environment maps only (-1: none).
  double estimate = -1.0;  // the prefilter's own error estimate
  double lookupRms = -1.0, lookupMax = -1.0;
  double referenceSeconds = -1.0;  // the reference over the whole map, scaled from the subset
  bool metBound = true;
  bool environment = false;
  bool pareto = false;
};

struct Skipped {
  std::string map, parameterization, method, note;
  int resolution = 0;
};

template <class T>
std::vector<T> parseList(const std::string& text, const std::string& flag,
                         const std::function<T(const std::string&)>& parse) {
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

// The error a point is charted (and its Pareto front taken) by: for material maps the bound
// max_error means (docs/accuracy.md), for environments the texel or lookup RMS relative error.
double plotted(const Point& p, bool lookups) {
  if (!p.environment) return p.bound;
  return lookups ? p.lookupRms : p.rms;
}

// Marks the points no other point beats in both time and charted RMS error.
void markPareto(std::vector<Point>& points, bool lookups) {
  for (auto& p : points) {
    const double e = plotted(p, lookups);
    p.pareto = std::none_of(points.begin(), points.end(), [&](const Point& q) {
      const double f = plotted(q, lookups);
      return q.seconds <= p.seconds && f <= e && (q.seconds < p.seconds || f < e);
    });
  }
}

std::string optionalNumber(double value) {
  if (value < 0.0) return "";
  std::ostringstream out;
  out << value;
  return out.str();
}

void writeCsv(const std::vector<Point>& points, const fs::path& path) {
  std::ostringstream out;
  {
    // The first ten columns are those of material charts before environment maps were charted.
    out << "map,parameterization,resolution,samples_per_texel,texels,seconds,rms,max,visible_rms,pareto,"
           "method,detail,estimate,lookup_rms,lookup_max,reference_seconds,highlight_rms,highlight_max,error\n";
    for (const auto& p : points) {
      std::string detail = p.detail;
      std::replace(detail.begin(), detail.end(), ',', ';');
      out << p.map << "," << p.parameterization << "," << p.resolution << "," << p.samples << "," << p.texels << ","
          << p.seconds << "," << p.rms << "," << p.max << "," << p.visibleRms << "," << p.pareto << "," << p.method
          << "," << detail << "," << optionalNumber(p.estimate) << "," << optionalNumber(p.lookupRms) << ","
          << optionalNumber(p.lookupMax) << "," << optionalNumber(p.referenceSeconds) << ","
          << optionalNumber(p.highlightRms) << "," << optionalNumber(p.highlightMax) << "," << optionalNumber(p.bound)
          << "\n";
    }
  }
  writeFileAtomically(path, out.str());
}

// Log scales cannot show 0 (an exact furnace): plotted errors are floored.
double plottable(double error) { return std::max(error, 1e-9); }

// Material maps: log-log time against RMS error, one colour per parameterization, labels
// resolution/samples, the Pareto front as a line.
std::string materialScript(const std::vector<Point>& points, const std::string& title) {
  std::ostringstream gp;
  gp << "set title '" << title << "'\nset logscale xy\nset grid\nset key outside right\n";
  gp << "set xlabel 'bake time (s)'\nset ylabel 'error: max(value-weighted RMS, lookup RMS) / peak'\nset format x "
        "'%g'\nset format y '%g'\n";
  std::vector<std::string> kinds;
  for (const auto& p : points)
    if (std::find(kinds.begin(), kinds.end(), p.parameterization) == kinds.end()) kinds.push_back(p.parameterization);
  for (const auto& kind : kinds) {
    gp << "$" << kind << " << EOD\n";
    for (const auto& p : points)
      if (p.parameterization == kind)
        gp << p.seconds << " " << plottable(p.bound) << " \"" << p.resolution << "/" << p.samples << "\"\n";
    gp << "EOD\n";
  }
  std::vector<Point> front;
  for (const auto& p : points)
    if (p.pareto) front.push_back(p);
  std::sort(front.begin(), front.end(), [](const Point& a, const Point& b) { return a.seconds < b.seconds; });
  gp << "$pareto << EOD\n";
  for (const auto& p : front) gp << p.seconds << " " << plottable(p.bound) << "\n";
  gp << "EOD\nplot ";
  for (const auto& kind : kinds) {
    gp << "$" << kind << " using 1:2 with points pt 7 ps 1.2 title '" << kind << "', ";
    gp << "$" << kind << " using 1:2:3 with labels font ',7' offset 0,0.8 notitle, ";
  }
  gp << "$pareto using 1:2 with lines lw 2 lc rgb 'black' title 'Pareto front'\n";
  return gp.str();
}

// Environment maps: one colour per method, one point shape per parameterization, labels the
// resolution, Pareto points ringed and joined.
std::string environmentScript(const std::vector<Point>& points, const std::string& title, bool lookups) {
  static const char* colours[] = {"#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#7f7f7f", "#9467bd"};
  static const int shapes[] = {7, 5, 9, 13, 11};  // filled circle, square, triangle, diamond, inverted triangle
  std::vector<std::string> methods, kinds;
  for (const auto& p : points) {
    if (std::find(methods.begin(), methods.end(), p.method) == methods.end()) methods.push_back(p.method);
    if (std::find(kinds.begin(), kinds.end(), p.parameterization) == kinds.end()) kinds.push_back(p.parameterization);
  }
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
      int count = 0;
      for (const auto& p : points) {
        if (p.method != methods[m] || p.parameterization != kinds[k]) continue;
        data << p.seconds << " " << plottable(plotted(p, lookups)) << " \"" << p.resolution << "\"\n";
        ++count;
      }
      if (count == 0) continue;
      gp << block << " << EOD\n" << data.str() << "EOD\n";
      plots.push_back(block + " using 1:2 with points pt " + std::to_string(shapes[k % 5]) + " ps 1.3 lc rgb '" +
                      colours[m % 6] + "' notitle");
      plots.push_back(block + " using 1:2:3 with labels font ',7' offset 0,0.8 tc rgb '" + colours[m % 6] +
                      "' notitle");
    }
  }
  std::vector<Point> front;
  for (const auto& p : points)
    if (p.pareto) front.push_back(p);
  std::sort(front.begin(), front.end(), [](const Point& a, const Point& b) { return a.seconds < b.seconds; });
  gp << "$pareto << EOD\n";
  for (const auto& p : front) gp << p.seconds << " " << plottable(plotted(p, lookups)) << "\n";
  gp << "EOD\n";
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

std::string percent(double fraction) {
  std::ostringstream out;
  out << 100.0 * fraction << " %";
  return out.str();
}

struct EnvironmentSweep {
  std::vector<ParameterizationKind> kinds;
  std::vector<int> resolutions;
  std::vector<PrefilterMethod> methods;
  int subset = 256;
  double maxError = 0.0;  // 0: the spec's
  int threads = 0;
};

// What one (parameterization, resolution) of an environment sweep compares against: the reference
// prefilter at a random texel subset and at random lookup directions, computed once for every method.
struct SweepReference {
  PrefilterCheckPoints texels, lookups;
  std::vector<Rgb> texelValues, lookupValues;
  long long mapTexels = 0;
  double seconds = 0.0;  // the reference over the whole map, scaled from the subset
};

SweepReference sweepReference(const Environment& environment, const EnvironmentMapSpec& e, const Parameterization& map,
                              const PrefilterOptions& options, const EnvironmentSweep& sweep) {
  const PrefilterLobe* lobe = e.analyticLobe();
  // Axes of a lobe model are the reflected directions, as phong's.
  const PrefilterLobe axisLobe = lobe ? *lobe : PrefilterLobe::phong(1.0);
  SweepReference r;
  r.texels = prefilterTexelSubset(map, axisLobe, options, sweep.subset, 7);
  r.lookups = prefilterLookupSet(map, axisLobe, options, sweep.subset, 8);
  std::vector<Vec3> axes = r.texels.axes;
  axes.insert(axes.end(), r.lookups.axes.begin(), r.lookups.axes.end());
  const auto start = Clock::now();
  const std::vector<Rgb> reference =
      lobe ? prefilterReferenceAt(environment, *lobe, axes, sweep.threads)
           : prefilterLobeModelReferenceAt(environment, *e.lobeModel(), axes, sweep.threads);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const auto split = reference.begin() + static_cast<std::ptrdiff_t>(r.texels.size());
  r.texelValues.assign(reference.begin(), split);
  r.lookupValues.assign(split, reference.end());
  r.mapTexels = static_cast<long long>(map.width()) * map.height();
  r.seconds = seconds * double(r.mapTexels) / double(axes.size());
  return r;
}

// One prefilter of an environment map, timed and measured against the reference. Throws Error when
// the method cannot make the map.
Point environmentPoint(const MapSpec& map, const EnvironmentMapSpec& e, const Environment& environment,
                       const PrefilterOptions& options, const SweepReference& reference, double floor) {
  const PrefilterLobe* lobe = e.analyticLobe();
  const auto start = Clock::now();
  const PrefilteredMap result = lobe ? prefilter(environment, *lobe, options)
                                     : prefilterLobeModel(environment, *e.lobeModel(), e.lobeName, options);
  Point p;
  p.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  p.environment = true;
  p.map = map.jsonPath;
  p.parameterization = std::string(toString(options.parameterization));
  p.resolution = options.resolution;
  p.method = std::string(toString(options.method));
  p.detail = result.summary.detail;
  if (options.method == PrefilterMethod::Auto && lobe)
    p.detail = std::string(toString(result.summary.method)) + ": " + p.detail;
  p.texels = reference.mapTexels;
  const PrefilterError texelError =
      prefilterPointsError(prefilterValuesAt(result.levels[0], *result.map, reference.texels), reference.texelValues,
                           reference.texels.weights, floor);
  const PrefilterError lookupError =
      prefilterPointsError(prefilterValuesAt(result.levels[0], *result.map, reference.lookups), reference.lookupValues,
                           reference.lookups.weights, floor);
  p.rms = texelError.rms;
  p.max = texelError.max;
  p.visibleRms = texelError.rms;
  p.lookupRms = lookupError.rms;
  p.lookupMax = lookupError.max;
  if (result.summary.errorEstimated) p.estimate = result.summary.errorEstimate;
  p.metBound = result.summary.metTarget;
  p.referenceSeconds = reference.seconds;
  return p;
}

// One prefiltered environment map swept over parameterization x resolution x method. Each
// (parameterization, resolution) pays the reference once, on a random texel subset and on random
// lookup directions; combinations that fail are skipped with a note.
std::vector<Point> sweepEnvironment(const MapSpec& map, const EnvironmentMapSpec& e, const Environment& environment,
                                    const EnvironmentSweep& sweep, std::vector<Skipped>& skipped, ProgressBar& bar) {
  const PrefilterLobe* lobe = e.analyticLobe();
  const double floor =
      lobe ? prefilterErrorFloor(environment, *lobe) : prefilterLobeModelErrorFloor(environment, *e.lobeModel());
  std::vector<Point> points;
  const double total = double(sweep.kinds.size() * sweep.resolutions.size() * sweep.methods.size());
  int done = 0;
  const auto progress = bar.callback();
  for (const auto kind : sweep.kinds) {
    for (const int resolution : sweep.resolutions) {
      PrefilterOptions options = map.prefilterOptions();
      options.parameterization = kind;
      options.resolution = resolution;
      options.mips = false;
      if (sweep.maxError > 0.0) options.maxError = sweep.maxError;
      options.threads = sweep.threads;
      const SweepReference reference =
          sweepReference(environment, e, *makeParameterization(kind, resolution), options, sweep);
      for (const auto method : sweep.methods) {
        options.method = method;
        try {
          points.push_back(environmentPoint(map, e, environment, options, reference, floor));
        } catch (const Error& error) {
          skipped.push_back(
              {map.jsonPath, std::string(toString(kind)), std::string(toString(method)), error.what(), resolution});
        }
        if (progress) progress(++done / total);
      }
    }
  }
  return points;
}

// The flags, as given.
struct Args {
  std::string spec, output, csv;
  std::string resolutions = kMaterialResolutions, samples = "1,4,16",
              parameterizations = "sphere,paraboloid,cube,latlong";
  std::string methods = "auto,sh,direct,importance", environmentError = "texel";
  int threads = 0, lookups = 20000, subset = 256;
  double maxError = 0.0;
  bool json = false, quiet = false;
  bool resolutionsGiven = false;  // --resolutions was given: it sets both kinds of map
};

// The flags, parsed and checked.
struct Settings {
  std::vector<int> resolutions, environmentResolutions, samples;
  std::vector<ParameterizationKind> kinds;
  std::vector<PrefilterMethod> methods;
  fs::path output;
  bool lookupError = false;  // --environment-error lookup
  bool progress = true;      // progress bars and notes on the terminal
};

// One map's points and its panel's title (no points: nothing to draw).
struct MapChart {
  std::vector<Point> points;
  std::string title;
  bool environment = false;  // drawn with environmentScript, else materialScript
};

void registerOptions(CLI::App* command, Args& args, CLI::Option*& resolutionsOption) {
  command->add_option("spec", args.spec, "Spec file")->required();
  command->add_option("-o,--output", args.output, "Chart (.png or .svg); several maps: one panel each in this picture");
  command->add_option("--csv", args.csv, "Also write the points as CSV");
  resolutionsOption = command->add_option("--resolutions", args.resolutions,
                                          "Comma-separated resolutions (default 32,64,128,256,512 for materials, "
                                          "16,32,64 for environment maps)");
  command->add_option("--samples", args.samples, "Comma-separated samples per texel (material maps)")
      ->default_str(args.samples);
  command->add_option("--parameterizations", args.parameterizations, "Comma-separated parameterizations")
      ->default_str(args.parameterizations);
  command
      ->add_option("--methods", args.methods,
                   "Comma-separated prefilter methods (environment maps): auto, sh, direct, importance, reference")
      ->default_str(args.methods);
  addEnvironmentMaxErrorOption(
      command, args.maxError,
      "Environment maps: the bound methods choose their settings for (default: the map's max_error)");
  command
      ->add_option("--subset", args.subset,
                   "Environment maps: random output texels (and lookup directions) compared with the reference")
      ->default_val(256)
      ->check(CLI::Range(16, 1000000));
  command
      ->add_option("--environment-error", args.environmentError,
                   "Environment maps: the error charted and the Pareto front taken on: texel (at texel centres) or "
                   "lookup (bilinear lookups)")
      ->default_str(args.environmentError)
      ->check(CLI::IsMember({"texel", "lookup"}));
  command->add_option("--lookups", args.lookups, "Material maps: random directions per error measurement")
      ->default_val(20000)
      ->check(CLI::Range(100, 10000000));
  addThreadsOption(command, args.threads);
  addQuietFlag(command, args.quiet);
  addJsonFlag(command, args.json, "the points (skipped ones with \"skipped\": true)");
}

Settings parseSettings(const Args& args) {
  const auto toInt = [](const std::string& s) {
    std::size_t used = 0;
    const int v = std::stoi(s, &used);
    if (used != s.size() || v < 1) throw std::invalid_argument(s);
    return v;
  };
  Settings settings;
  settings.resolutions = parseList<int>(args.resolutions, "--resolutions", toInt);
  settings.environmentResolutions =
      args.resolutionsGiven ? settings.resolutions : parseList<int>(kEnvironmentResolutions, "--resolutions", toInt);
  settings.samples = parseList<int>(args.samples, "--samples", toInt);
  settings.kinds = parseList<ParameterizationKind>(args.parameterizations, "--parameterizations",
                                                   [](const std::string& s) { return parseParameterizationKind(s); });
  settings.methods = parseList<PrefilterMethod>(args.methods, "--methods",
                                                [](const std::string& s) { return parsePrefilterMethod(s); });
  if (args.output.empty() && args.csv.empty() && !args.json) {
    throw Error(Error::Kind::InvalidArgument, "chart: give -o CHART.png, --csv FILE or --json (nothing to write)");
  }
  settings.output = args.output;
  if (!settings.output.empty()) checkChartPath(settings.output);
  settings.lookupError = args.environmentError == "lookup";
  settings.progress = !args.json && !args.quiet;
  return settings;
}

// Every input and output checked before any work.
void checkFiles(const BakeSpec& spec, const Args& args) {
  FilePlan plan;
  plan.addInput(args.spec, "spec");
  for (const auto& map : spec.maps) {
    for (const auto& input : map.inputs) plan.addInput(input.file, input.role);
  }
  if (!args.output.empty()) plan.addOutput(args.output, "-o");
  if (!args.csv.empty()) plan.addOutput(args.csv, "--csv");
  plan.check();
}

// Why an environment map cannot be charted, or empty.
std::string environmentSkipReason(const EnvironmentMapSpec& e) {
  if (e.analyticLobe() && e.analyticLobe()->isMirror()) {
    return "the mirror lobe is a resampling with no reference to chart against; map skipped";
  }
  if (e.lobeModel() && e.lobeModel()->elevation != LobeElevation::Constant) {
    return "lobes that vary with elevation prefilter into a stack of maps (one per elevation); chart a slice's "
           "constant model instead; map skipped";
  }
  return "";
}

MapChart chartEnvironmentMap(const MapSpec& map, const EnvironmentMapSpec& e, const Environment& environment,
                             const Args& args, const Settings& settings, std::vector<Skipped>& skipped) {
  if (const std::string reason = environmentSkipReason(e); !reason.empty()) {
    skipped.push_back({map.jsonPath, "", "", reason, 0});
    return {};
  }
  EnvironmentSweep sweep;
  sweep.kinds = settings.kinds;
  sweep.resolutions = settings.environmentResolutions;
  sweep.methods = settings.methods;
  sweep.subset = args.subset;
  sweep.maxError = args.maxError;
  sweep.threads = args.threads;
  ProgressBar bar(map.jsonPath, settings.progress);
  MapChart chart;
  chart.environment = true;
  chart.points = sweepEnvironment(map, e, environment, sweep, skipped, bar);
  chart.title = map.jsonPath + ": " + e.lobeName + " of " + e.file.filename().string() + ", bound " +
                percent(args.maxError > 0.0 ? args.maxError : e.maxError) + " (" + map.output.filename().string() + ")";
  return chart;
}

// One bake of a material map, timed and measured against the exact model.
Point materialPoint(const MapSpec& map, const MapFunction& function, const ErrorProbes& probes,
                    ParameterizationKind kind, int resolution, int samplesPerTexel, int threads) {
  const auto parameterization = makeParameterization(kind, resolution);
  BakeOptions options;
  options.samplesPerTexel = samplesPerTexel;
  options.threads = threads;
  const auto [image, summary] = bakeMap(*parameterization, function, options);
  Point p;
  p.map = map.jsonPath;
  p.parameterization = std::string(toString(kind));
  p.resolution = resolution;
  p.samples = samplesPerTexel;
  p.texels = static_cast<long long>(parameterization->width()) * parameterization->height();
  p.seconds = summary.seconds;
  const ErrorStats error = measureMapError(image, *parameterization, probes);
  p.rms = error.rms;
  p.max = error.max;
  p.visibleRms = error.visibleRms;
  p.highlightRms = error.highlightRms;
  p.highlightMax = error.highlightMax;
  p.bound = autoErrorMeasure(error, kind);
  return p;
}

MapChart chartMaterialMap(MapSpec& map, const Args& args, const Settings& settings) {
  if (map.materialMap()->deferredFit) {
    ProgressBar fitting(map.jsonPath + " fitting lobes", settings.progress);
    map.prepare(fitting.callback());
  }
  const auto function = map.makeFunction();
  ProgressBar bar(map.jsonPath, settings.progress);
  const auto progress = bar.callback();
  const double total = double(settings.kinds.size() * settings.resolutions.size() * settings.samples.size());
  int done = 0;
  ErrorOptions errorOptions;
  errorOptions.samples = args.lookups;
  const ErrorProbes probes(*function, errorOptions);
  MapChart chart;
  for (const auto kind : settings.kinds)
    for (const int resolution : settings.resolutions)
      for (const int spt : settings.samples) {
        chart.points.push_back(materialPoint(map, *function, probes, kind, resolution, spt, args.threads));
        if (progress) progress(++done / total);
      }
  chart.title = map.jsonPath + ": " + map.modelName() + " (" + map.output.filename().string() + ")";
  return chart;
}

// A point as --json reports it; `chart` is the picture holding its panel (empty: none).
nlohmann::json pointEntry(const Point& p, const fs::path& chart) {
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
  } else {
    entry["detail"] = p.detail;
    entry["estimate"] = p.estimate >= 0.0 ? nlohmann::json(p.estimate) : nlohmann::json(nullptr);
    entry["met_bound"] = p.metBound;
    entry["lookup_rms"] = p.lookupRms;
    entry["lookup_max"] = p.lookupMax;
    entry["reference_seconds"] = p.referenceSeconds;
  }
  return entry;
}

// A skipped map or combination as --json reports it, also noted on the terminal.
nlohmann::json skippedEntry(const Skipped& k, bool print) {
  nlohmann::json entry = {{"map", k.map}, {"skipped", true}, {"note", k.note}};
  if (!k.method.empty()) {
    entry["parameterization"] = k.parameterization;
    entry["resolution"] = k.resolution;
    entry["method"] = k.method;
  }
  if (print) {
    std::cout << "note: " << k.map;
    if (!k.method.empty())
      std::cout << " " << k.parameterization << " " << k.resolution << " " << k.method << " skipped";
    std::cout << ": " << k.note << "\n";
  }
  return entry;
}

// The chart (one panel per map with points), the CSV and the JSON report.
void writeOutputs(const Args& args, const Settings& settings, const std::vector<std::string>& panels,
                  const std::vector<Point>& points, const nlohmann::json& report) {
  if (!panels.empty()) {
    renderWithGnuplot(panels, settings.output);
    if (settings.progress) {
      std::cout << "wrote " << settings.output.string() << " (" << panels.size()
                << (panels.size() == 1 ? " chart)" : " charts, one per map)") << "\n";
    }
  }
  if (!args.csv.empty()) writeCsv(points, args.csv);
  if (args.json) std::cout << report.dump(2) << "\n";
}

int run(const Args& args) {
  const Settings settings = parseSettings(args);
  BakeSpec spec = loadBakeSpec(args.spec);
  checkFiles(spec, args);
  // Environments are read (and checked) before any work, as `bake` does.
  std::vector<std::optional<Environment>> environments(spec.maps.size());
  for (std::size_t i = 0; i < spec.maps.size(); ++i)
    if (const EnvironmentMapSpec* e = spec.maps[i].environmentMap()) {
      environments[i] = loadEnvironment(e->file, EnvironmentLoadOptions{e->from});
    }
  // Warm up the thread pool, so the first point does not carry its start-up.
  bake(*makeParameterization(ParameterizationKind::Sphere, 8), ConstantEnvironment());

  nlohmann::json report = nlohmann::json::array();
  std::vector<Point> all;
  std::vector<Skipped> skipped;
  std::vector<std::string> panels;  // one chart per map, drawn into -o as one picture
  for (std::size_t m = 0; m < spec.maps.size(); ++m) {
    MapSpec& map = spec.maps[m];
    const std::size_t skippedBefore = skipped.size();
    MapChart chart =
        std::visit(Overloaded{[&](const EnvironmentMapSpec& e) {
                                return chartEnvironmentMap(map, e, *environments[m], args, settings, skipped);
                              },
                              [&](const MaterialMapSpec&) { return chartMaterialMap(map, args, settings); }},
                   map.content);
    markPareto(chart.points, settings.lookupError);
    const bool drawn = !settings.output.empty() && !chart.points.empty();
    if (drawn) {
      panels.push_back(chart.environment ? environmentScript(chart.points, chart.title, settings.lookupError)
                                         : materialScript(chart.points, chart.title));
    }
    for (const auto& p : chart.points) report.push_back(pointEntry(p, drawn ? settings.output : fs::path()));
    for (std::size_t s = skippedBefore; s < skipped.size(); ++s)
      report.push_back(skippedEntry(skipped[s], settings.progress));
    all.insert(all.end(), chart.points.begin(), chart.points.end());
  }
  writeOutputs(args, settings, panels, all, report);
  return 0;
}

}  // namespace

Command addChartCommand(CLI::App& app) {
  auto args = std::make_shared<Args>();
  auto* command = app.add_subcommand("chart", "Chart bake or prefilter time against accuracy for the maps of a spec");
  command->footer(R"(Material maps: bakes every combination of parameterization x resolution x samples per texel,
measures the time and the error of bilinear lookups against the exact model (RMS and max over
directions uniform on the sphere, relative to the peak; for sphere maps also over the reflected
vectors of a visible sphere), and plots time against RMS error (log-log) with the Pareto front.
Sphere maps skip the rim (their singular set). Non-sphere maps of view-dependent materials use the
spec's view, or +z. Points are labelled resolution/samples. Default resolutions 32,64,128,256,512.

Prefiltered environment maps ("environment" in the spec, docs/prefilter.md): prefilters every
combination of parameterization x resolution x method (--methods; each named method picks its
cheapest setting for the bound, the map's max_error or --max-error) and measures the whole
prefilter's wall-clock time and the RMS and max relative error against the reference prefilter on
--subset random output texels (solid-angle weighted; every texel if the map has fewer), plus
bilinear lookups in --subset random directions (lookup_rms). The reference runs once per
parameterization and resolution. Default resolutions 16,32,64 (--resolutions sets both kinds);
--samples does not apply. Colour = method, shape = parameterization, label = resolution. A
combination that fails is skipped with a note. Mirror maps (no integral, no reference) and fitted lobes
that vary with elevation (a stack of maps) are skipped.

Outputs: one chart, a panel per map, --csv (one row per point:
map, parameterization, resolution, samples_per_texel (0 for environments), texels, seconds, rms,
max, visible_rms, pareto, method (bake for materials), detail, estimate, lookup_rms, lookup_max,
reference_seconds) and --json (the points; skipped combinations as entries with "skipped": true).
-o is needed unless --csv or --json is given; the chart needs gnuplot, the CSV and JSON do not.
docs/charts.md.

Examples:
  brdfbake chart data_samples/specs/phong_eye.json -o phong_chart.png --csv phong_chart.csv
  brdfbake chart spec.json -o c.svg --resolutions 64,256 --samples 1,16 --parameterizations sphere,cube
  brdfbake chart data_samples/specs/prefilter_sky.json -o sky.png --csv sky.csv --methods auto,sh,direct)");
  CLI::Option* resolutionsOption = nullptr;
  registerOptions(command, *args, resolutionsOption);
  return [args, resolutionsOption] {
    args->resolutionsGiven = resolutionsOption->count() > 0;
    return run(*args);
  };
}

}  // namespace brdfbake::cli
