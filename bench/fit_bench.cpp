// fit_bench: the fit time targets (issue 26: the default fit in at most 2 s, the per-channel fit in at
// most 10 s; issue 13's were 2 s for 31 wavelengths and 0.5 s for RGB), side by side in one run. For each Cornell table
// of
// --shared (garnet_red.astm and krylon_blue.astm as their 31 wavelengths and converted to RGB with
// CIE 1931, garnet_red_RGB.astm, krylon_blue_RGB.astm, krylon_blue.brdf as its 31 wavelengths) it
// runs
//   - the default fit, fitLobes(table) (shared shapes, lobes and kind auto, exponent cap chosen), and
//   - the per-channel Ceres fit (FitMethod::PerChannel): lobes and elevation auto (on spectral tables
//     --per-channel-spectral-lobes K fixes K varying lobes instead),
// each with 1 and 2 threads, --repetitions times (default 3), and prints a Markdown table (machine,
// date and load average at the top): median wall seconds and their spread (min-max), median process
// CPU seconds (getrusage, every thread), and the held-out figures of FitResult::heldOut (off-mirror
// k-fold ratio, pooled leave-one-elevation-out ratio, and the worse of them, the score the auto choices
// minimise; ratios to a Lambertian fit on the same split, fit/held_out.hpp) with the chosen model.
// The chart (gnuplot) of wall time (log) against held-out score goes where --chart says, or to the
// tracked docs/images/fit_speed_error.png with --update-docs; else none is drawn.
//
//   fit_bench [--shared ../shared/data/cornell] [--repetitions 3] [--tables a,b] [--quick]
//             [--per-channel-spectral-lobes auto|K] [--chart PNG | --update-docs]
//   fit_bench --samples data_samples     (the synthetic tables and fits of data_samples/)
//
// --tables: case names (garnet_red.astm, garnet_red.astm:rgb, ...; a file name alone selects each
// of its cases). --quick: one repetition, and no per-channel fit of the spectral tables (they take
// more than half of a run).
#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/cornell_grid.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/fit/lobe_fit.hpp>
#include <brdfbake/measured/measured_io.hpp>
#include <brdfbake/run/gnuplot.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <sys/resource.h>

using namespace brdfbake;
namespace fs = std::filesystem;

namespace {

// The models of data_samples/tables (also in docs/fitting.md): two constant lobes per channel,
// and one lobe that grows and sharpens towards grazing.
LobeModel twoLobes() {
  LobeModel m;
  m.elevation = LobeElevation::Constant;
  m.channels = {{"R", 0.20, {{{0.30}, {12.0}}, {{0.50}, {300.0}}}},
                {"G", 0.10, {{{0.20}, {30.0}}, {{0.45}, {800.0}}}},
                {"B", 0.05, {{{0.10}, {5.0}}, {{0.60}, {150.0}}}}};
  return m;
}

LobeModel varyingLobe() {
  LobeModel m;
  m.elevation = LobeElevation::Varying;
  m.minCos = std::cos(2.0 * std::asin(0.9 / std::sqrt(2.0)));  // the Cornell views reach 79.05 degrees
  m.maxCos = 1.0;
  m.channels = {{"R", 0.15, {{{0.80, 0.25, 0.08}, {120.0, 60.0, 25.0}}}},
                {"G", 0.05, {{{0.90, 0.30, 0.10}, {150.0, 70.0, 30.0}}}},
                {"B", 0.02, {{{1.00, 0.35, 0.12}, {180.0, 80.0, 35.0}}}}};
  return m;
}

int writeSamples(const fs::path& root) {
  fs::create_directories(root / "tables");
  fs::create_directories(root / "fits");
  struct Sample {
    const char* name;
    LobeModel model;
    std::uint32_t seed;
  };
  for (const Sample& s :
       {Sample{"synthetic_two_lobes", twoLobes(), 1}, Sample{"synthetic_varying", varyingLobe(), 2}}) {
    const fs::path table = root / "tables" / (std::string(s.name) + ".astm");
    writeAstm(table, makeSyntheticTable(s.model, 0.01, s.seed));
    // Fit what was written (as `brdfbake fit` would), with the defaults.
    const MeasuredTable read = readMeasuredTable(table);
    FitFile file;
    file.source = {"../tables/" + std::string(s.name) + ".astm", "astm", read.size(), "rgb: as stored in the file",
                   read.notes};
    file.fit = fitLobes(read);
    const fs::path fit = root / "fits" / (std::string(s.name) + ".json");
    writeFitFile(fit, file);
    std::cout << "wrote " << table.string() << " and " << fit.string() << "\n" << file.fit.briefReport();
  }
  return 0;
}

// ---- the benchmark ---------------------------------------------------------------------------

using Clock = std::chrono::steady_clock;

// CPU seconds (user + system) of this process, every thread.
double processCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// One table as fitted: a file, its 31 wavelengths or converted to RGB.
struct Case {
  std::string name;  // "garnet_red.astm", "garnet_red.astm:rgb"
  std::string file;
  bool spectral = false;
  bool converted = false;  // spectral file converted to RGB (CIE 1931)
};

std::vector<Case> allCases() {
  return {{"garnet_red.astm", "garnet_red.astm", true, false},
          {"garnet_red.astm:rgb", "garnet_red.astm", false, true},
          {"garnet_red_RGB.astm", "garnet_red_RGB.astm", false, false},
          {"krylon_blue.astm", "krylon_blue.astm", true, false},
          {"krylon_blue.astm:rgb", "krylon_blue.astm", false, true},
          {"krylon_blue_RGB.astm", "krylon_blue_RGB.astm", false, false},
          {"krylon_blue.brdf", "krylon_blue.brdf", true, false}};
}

std::string channelsLabel(const Case& c, const MeasuredTable& table) {
  if (c.spectral) return std::to_string(table.channelCount()) + " wavelengths";
  return c.converted ? "RGB (CIE 1931)" : "RGB (file)";
}

// The table as the case fits it (as `brdfbake fit --channels spectral|rgb` reads it).
MeasuredTable loadCase(const fs::path& shared, const Case& c) {
  const MeasuredTable read = readTableForFitting(shared / c.file);
  if (c.spectral && read.kind != ChannelKind::Spectral) {
    throw Error(Error::Kind::InvalidInput, (shared / c.file).string() + ": expected a spectral table");
  }
  return c.converted ? read.toRgb(RgbMethod::Cie1931) : read;
}

struct Settings {
  fs::path shared = "../shared/data/cornell";
  fs::path chart;  // none unless asked: the tracked picture changes only with --update-docs
  int repetitions = 3;
  int perChannelSpectralLobes = 0;  // 0: auto
  bool quick = false;
  std::vector<std::string> tables;  // empty = every case
};

// A method as the bench runs it on one case.
struct Method {
  std::string name;   // "shared (default)", "per-channel"
  std::string setup;  // the options, as `brdfbake fit` flags
  FitOptions options;
};

std::vector<Method> methodsFor(const Case& c, const Settings& settings) {
  std::vector<Method> methods;
  methods.push_back({"shared (default)", "defaults", FitOptions{}});
  if (c.spectral && settings.quick) return methods;
  Method perChannel{"per-channel", "--method per_channel", FitOptions{}};
  perChannel.options.method = FitMethod::PerChannel;
  if (c.spectral && settings.perChannelSpectralLobes > 0) {
    perChannel.options.lobes = settings.perChannelSpectralLobes;
    perChannel.options.elevation = ElevationChoice::Varying;
    perChannel.setup += " --lobes " + std::to_string(settings.perChannelSpectralLobes) + " --elevation varying";
  }
  methods.push_back(perChannel);
  return methods;
}

// Every repetition of one method on one case at one thread count.
struct Run {
  std::string caseName, channels, method, setup, model;
  int threads = 1;
  std::vector<double> wall, cpu;
  double kfold = 0.0, elevation = 0.0, score = 0.0;
  std::size_t candidates = 0;
  bool usable = true;
  bool heldOutVaried = false;  // the held-out figures differed between repetitions or thread counts
};

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// "3 half_vector varying, profiled, cap 3000" or "2 mirror varying".
std::string modelLabel(const FitResult& fit) {
  const auto chosen =
      std::find_if(fit.candidates.begin(), fit.candidates.end(), [](const ModelCandidate& m) { return m.chosen; });
  const int lobes =
      chosen != fit.candidates.end() ? chosen->lobes : static_cast<int>(fit.model.channels.front().lobes.size());
  LobeKindChoice kind = fit.options.method == FitMethod::PerChannel ? LobeKindChoice::Mirror : fit.options.kind;
  if (chosen != fit.candidates.end()) kind = chosen->kind;
  std::ostringstream label;
  label << lobes << " " << toString(kind) << " " << toString(fit.model.elevation);
  if (fit.model.colorProfile != ColorProfile::None) label << ", profiled";
  if (fit.options.method == FitMethod::Shared) label << ", cap " << fit.options.maxExponent;
  return label.str();
}

void recordHeldOut(Run& run, const FitResult& fit) {
  if (!fit.heldOut) throw Error(Error::Kind::InvalidInput, run.caseName + ": the fit made no held-out estimate");
  const double kfold = fit.heldOut->kfold.ratio(), elevation = fit.heldOut->pooledElevations().ratio(),
               score = fit.heldOut->score();
  if (!run.wall.empty() && (kfold != run.kfold || elevation != run.elevation || score != run.score))
    run.heldOutVaried = true;
  run.kfold = kfold, run.elevation = elevation, run.score = score;
  run.model = modelLabel(fit);
  run.candidates = fit.candidates.size();
  run.usable = run.usable && fit.usable();
}

Run timeMethod(const Case& c, const MeasuredTable& table, const Method& method, int threads, int repetitions) {
  Run run;
  run.caseName = c.name, run.channels = channelsLabel(c, table), run.method = method.name, run.setup = method.setup;
  run.threads = threads;
  const FitOptions& options = method.options;
  const Context context({.threads = threads});
  for (int r = 0; r < repetitions; ++r) {
    const double cpu0 = processCpuSeconds();
    const auto start = Clock::now();
    const FitResult fit = fitLobes(table, options, context);
    const double wall = std::chrono::duration<double>(Clock::now() - start).count();
    const double cpu = processCpuSeconds() - cpu0;
    recordHeldOut(run, fit);
    run.wall.push_back(wall);
    run.cpu.push_back(cpu);
    std::cerr << c.name << ", " << method.name << ", " << threads << " thread(s), run " << r + 1 << "/" << repetitions
              << ": " << std::fixed << std::setprecision(2) << wall << " s wall, " << cpu << " s CPU, score "
              << std::setprecision(3) << run.score << " (" << run.model << ")\n"
              << std::defaultfloat;
  }
  return run;
}

std::string firstLine(const fs::path& file, const std::string& key) {
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(key, 0) == 0) {
      const auto colon = line.find(':');
      return colon == std::string::npos ? line : line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  }
  return "unknown";
}

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string one;
  return in >> one ? one : std::string("unknown");
}

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M UTC", &tm);
  return text;
}

std::string fixed(double value, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

// Seconds with two significant digits at least ("0.043", "1.9", "12.3").
std::string seconds(double value) { return fixed(value, value < 0.1 ? 3 : value < 10 ? 2 : 1); }

// Issue 26's targets: the default fit in at most 2 s (RGB or 31 wavelengths), the per-channel fit in
// at most 10 s.
double targetSeconds(const Run& run) { return run.method == "shared (default)" ? 2.0 : 10.0; }

void printRuns(const std::vector<Run>& runs) {
  std::cout << "| table | channels | method | threads | chosen model | wall s, median (min-max) | CPU s, median | "
               "k-fold ratio | "
               "elevation ratio | score | candidates | target |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Run& run : runs) {
    const auto [lo, hi] = std::minmax_element(run.wall.begin(), run.wall.end());
    const double wall = median(run.wall);
    std::cout << "| " << run.caseName << " | " << run.channels << " | " << run.method
              << (run.setup == "defaults" ? "" : " (" + run.setup + ")") << " | " << run.threads << " | " << run.model
              << (run.usable ? "" : " (NOT usable)") << " | " << seconds(wall) << " (" << seconds(*lo) << "-"
              << seconds(*hi) << ") | " << seconds(median(run.cpu)) << " | " << fixed(run.kfold, 3) << " | "
              << fixed(run.elevation, 3) << " | " << fixed(run.score, 3) << (run.heldOutVaried ? " (varied)" : "")
              << " | " << run.candidates << " | ";
    std::cout << (wall <= targetSeconds(run) ? "met" : "not met") << " (<= " << targetSeconds(run) << " s) |\n";
  }
}

// Per case: the default fit against the per-channel one, at 1 and 2 threads.
void printComparison(const std::vector<Run>& runs) {
  std::cout
      << "\n| table | score shared / per-channel | wall s shared, 1 / 2 threads | wall s per-channel, 1 / 2 threads | "
         "per-channel / shared time, 1 thread | speed-up at 2 threads, shared / per-channel "
         "|\n|---|---|---|---|---|---|\n";
  for (const Run& a : runs) {
    if (a.method != "shared (default)" || a.threads != 1) continue;
    auto find = [&](const std::string& method, int threads) -> const Run* {
      for (const Run& r : runs) {
        if (r.caseName == a.caseName && r.method == method && r.threads == threads) return &r;
      }
      return nullptr;
    };
    const Run *a2 = find(a.method, 2), *p1 = find("per-channel", 1), *p2 = find("per-channel", 2);
    auto wall = [](const Run* r) { return r ? seconds(median(r->wall)) : std::string("-"); };
    auto ratio = [](const Run* x, const Run* y) {
      return x && y ? fixed(median(x->wall) / median(y->wall), 1) + "x" : std::string("-");
    };
    std::cout << "| " << a.caseName << " | " << fixed(a.score, 3) << " / " << (p1 ? fixed(p1->score, 3) : "-") << " | "
              << wall(&a) << " / " << wall(a2) << " | " << wall(p1) << " / " << wall(p2) << " | " << ratio(p1, &a)
              << " | " << ratio(&a, a2) << " / " << ratio(p1, p2) << " |\n";
  }
}

// Wall time (log x, min-max as error bars) against held-out score, a colour per case, a symbol per
// method and thread count, a line joining 1 and 2 threads.
void writeChart(const std::vector<Run>& runs, const fs::path& chart, const std::string& title) {
  const std::vector<Case> cases = allCases();
  const char* colors[] = {"#7b1f1f", "#d0413a", "#e69138", "#1d3f8f", "#3d85d8", "#16a085", "#8e44ad"};
  std::ostringstream script, plots;
  script.precision(6);
  int block = 0;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    for (const std::string method : {"shared (default)", "per-channel"}) {
      std::ostringstream data;
      int points = 0;
      for (const Run& run : runs) {
        if (run.caseName != cases[k].name || run.method != method) continue;
        const auto [lo, hi] = std::minmax_element(run.wall.begin(), run.wall.end());
        data << median(run.wall) << " " << run.score << " " << *lo << " " << *hi << " " << run.threads << "\n";
        ++points;
      }
      if (!points) continue;
      const bool shared = method == std::string("shared (default)");
      script << "$d" << block << " << EOD\n" << data.str() << "EOD\n";
      const std::string color = std::string("lc rgb '") + colors[k] + "'";
      plots << (block ? ", " : "") << "$d" << block << " using 1:2 with lines lw 1.2 dt " << (shared ? 1 : 2) << " "
            << color << " notitle";
      for (int threads : {1, 2}) {
        const int pt = shared ? (threads == 1 ? 7 : 6) : (threads == 1 ? 5 : 4);
        plots << ", $d" << block << " using ($5 == " << threads << " ? $1 : NaN):2:3:4 with xerrorbars pt " << pt
              << " ps 1.4 " << color << " "
              << (shared && threads == 1 ? "title " + gnuplotQuote(cases[k].name) : std::string("notitle"));
      }
      ++block;
    }
  }
  if (!block) return;
  double fastest = 1e300, slowest = 0.0;
  for (const Run& run : runs) {
    fastest = std::min(fastest, *std::min_element(run.wall.begin(), run.wall.end()));
    slowest = std::max(slowest, *std::max_element(run.wall.begin(), run.wall.end()));
  }
  const char* keys[] = {"shared (default), 1 thread", "shared (default), 2 threads", "per-channel, 1 thread",
                        "per-channel, 2 threads"};
  const int keyPoints[] = {7, 6, 5, 4};
  for (int i = 0; i < 4; ++i)
    plots << ", NaN with points pt " << keyPoints[i] << " ps 1.4 lc rgb 'black' title " << gnuplotQuote(keys[i]);
  script << "set terminal pngcairo size 1100,700 font 'sans,10'\nset output " << gnuplotQuote(chart.string()) << "\n"
         << "set termoption noenhanced\nset grid\nset logscale x\nset format x '%g'\nset xrange ["
         << std::min(0.25, 0.7 * fastest) << ":" << std::max(4.0, 1.5 * slowest)
         << "]\nset key outside right top\nset yrange [0:*]\n"
         << "set xlabel 'fit wall time, s (median; bars: min-max over repetitions)'\n"
         << "set ylabel 'held-out score (worse of k-fold and pooled elevation ratios to Lambert; lower is better)'\n"
         << "set title " << gnuplotQuote(title) << "\n"
         << "set arrow from 2, graph 0 to 2, graph 1 nohead dt 3 lc rgb '#555555'\n"
         << "set arrow from 10, graph 0 to 10, graph 1 nohead dt 3 lc rgb '#555555'\n"
         << "set label 'default fit target 2 s' at 2, graph 0.5 right offset -0.5,0 font ',8'\n"
         << "set label 'per-channel target 10 s' at 10, graph 0.5 right offset -0.5,0 font ',8'\n"
         << "plot " << plots.str() << "\n";
  runGnuplot(script.str());
  std::cerr << "wrote " << chart.string() << "\n";
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

std::vector<Case> selectedCases(const Settings& settings) {
  std::vector<Case> cases;
  for (const Case& c : allCases()) {
    const bool wanted =
        settings.tables.empty() || std::any_of(settings.tables.begin(), settings.tables.end(),
                                               [&](const std::string& t) { return t == c.name || t == c.file; });
    if (wanted) cases.push_back(c);
  }
  for (const std::string& t : settings.tables) {
    if (std::none_of(cases.begin(), cases.end(), [&](const Case& c) { return t == c.name || t == c.file; })) {
      throw Error(Error::Kind::InvalidArgument,
                  "--tables: no case " + t +
                      " (garnet_red.astm, garnet_red.astm:rgb, garnet_red_RGB.astm, "
                      "krylon_blue.astm, krylon_blue.astm:rgb, krylon_blue_RGB.astm, krylon_blue.brdf)");
    }
  }
  return cases;
}

int runBench(const Settings& settings) {
  const std::vector<Case> cases = selectedCases(settings);
  const int repetitions = settings.quick ? 1 : settings.repetitions;
  const std::string machine = firstLine("/proc/cpuinfo", "model name") + ", " +
                              std::to_string(std::thread::hardware_concurrency()) + " logical cores";
  const std::string started = utcNow(), loadBefore = loadAverage();
  const auto start = Clock::now();
  std::vector<Run> runs;
  for (const Case& c : cases) {
    const MeasuredTable table = loadCase(settings.shared, c);
    for (const Method& method : methodsFor(c, settings)) {
      for (int threads : {1, 2}) runs.push_back(timeMethod(c, table, method, threads, repetitions));
    }
  }
  const double total = std::chrono::duration<double>(Clock::now() - start).count();
  std::cout
      << "# fit_bench: the default fit against the per-channel fit\n\n"
      << "Machine: " << machine << ". Started " << started << ", load average (1 min) " << loadBefore
      << " at the start, " << loadAverage() << " at the end; the whole run took " << fixed(total, 0) << " s. "
      << repetitions << " repetition(s) per row"
      << (settings.quick ? " (--quick: per-channel fits of the spectral tables skipped)" : "") << ".\n\n"
      << "Held-out figures (FitResult::heldOut, fit/held_out.hpp): ratios of the held-out log error to a "
         "Lambertian fit on the same split; "
         "score = the worse of the off-mirror k-fold ratio and the pooled leave-one-elevation-out ratio, what auto "
         "choices minimise. "
         "CPU s: the process's user + system time during the fit (every thread).\n\n";
  printRuns(runs);
  printComparison(runs);
  if (settings.chart.empty()) return 0;
  if (!findGnuplot()) {
    std::cerr << "fit_bench: gnuplot not found; no chart written\n";
    return 0;
  }
  writeChart(runs, settings.chart,
             "Cornell tables, fit time against held-out score (" + machine + ", " + started + ", load " + loadBefore +
                 ", " + std::to_string(repetitions) + " rep.)");
  return 0;
}

// A lobe count from text, -1 (refused below) if it is less than 1.
int countOrInvalid(const std::string& text) {
  const int count = std::stoi(text);
  return count >= 1 ? count : -1;
}

int usage() {
  std::cerr << "usage: fit_bench [--shared DIR] [--repetitions N] [--tables a,b] [--quick] "
               "[--per-channel-spectral-lobes auto|K] [--chart PNG | --update-docs]\n"
               "       fit_bench --samples DIR\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      const bool value = i + 1 < argc;
      if (arg == "--samples" && value) return writeSamples(argv[++i]);
      if (arg == "--shared" && value)
        settings.shared = argv[++i];
      else if (arg == "--chart" && value)
        settings.chart = argv[++i];
      else if (arg == "--repetitions" && value)
        settings.repetitions = std::stoi(argv[++i]);
      else if (arg == "--per-channel-spectral-lobes" && value)
        settings.perChannelSpectralLobes = std::string_view(argv[++i]) == "auto" ? 0 : countOrInvalid(argv[i]);
      else if (arg == "--tables" && value)
        settings.tables = splitList(argv[++i]);
      else if (arg == "--quick")
        settings.quick = true;
      else if (arg == "--update-docs")
        settings.chart = "docs/images/fit_speed_error.png";
      else
        return usage();
    }
    if (settings.repetitions < 1) throw Error(Error::Kind::InvalidArgument, "--repetitions must be >= 1");
    if (settings.perChannelSpectralLobes < 0 || settings.perChannelSpectralLobes > kMaxFitLobes) {
      throw Error(Error::Kind::InvalidArgument,
                  "--per-channel-spectral-lobes must be auto or 1.." + std::to_string(kMaxFitLobes));
    }
    if (!fs::is_directory(settings.shared)) {
      std::cerr << "fit_bench: " << settings.shared.string() << " not found; pass --shared DIR\n";
      return 1;
    }
    return runBench(settings);
  } catch (const Error& e) {
    std::cerr << "fit_bench: " << e.what() << "\n";
    return 1;
  } catch (const std::logic_error& e) {  // std::stoi
    std::cerr << "fit_bench: bad number: " << e.what() << "\n";
    return 2;
  }
}
