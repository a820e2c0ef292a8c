// fit_bench: lobe fits of the shared Cornell tables: error and time against lobe count (chart
// docs/images/fit_lobes.png), and the default (auto) fit of each table as a Markdown table for
// docs/fitting.md. Also writes the synthetic tables and fits of data_samples/ (--samples).
//
//   fit_bench [--shared ../shared/data/cornell] [--chart docs/images/fit_lobes.png] [--max-lobes 4]
//   fit_bench --samples data_samples
#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/cornell_grid.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/fit/gnuplot.hpp>
#include <brdfbake/fit/lobe_fit.hpp>
#include <brdfbake/measured/measured_io.hpp>

#include <chrono>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <sstream>

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
  for (const Sample& s : {Sample{"synthetic_two_lobes", twoLobes(), 1}, Sample{"synthetic_varying", varyingLobe(), 2}}) {
    const fs::path table = root / "tables" / (std::string(s.name) + ".astm");
    writeAstm(table, makeSyntheticTable(s.model, 0.01, s.seed));
    // Fit what was written (as `brdfbake fit` would), with the defaults.
    const MeasuredTable read = readMeasuredTable(table);
    FitFile file;
    file.source = {"../tables/" + std::string(s.name) + ".astm", "astm", read.size(), "rgb: as stored in the file", read.notes};
    file.fit = fitLobes(read);
    const fs::path fit = root / "fits" / (std::string(s.name) + ".json");
    writeFitFile(fit, file);
    std::cout << "wrote " << table.string() << " and " << fit.string() << "\n" << file.fit.briefReport();
  }
  return 0;
}

struct Point {
  std::string table;
  LobeElevation elevation;
  int lobes;
  double error, rms, seconds;
};

double meanRms(const FitResult& fit) {
  double sum = 0.0;
  for (const auto& c : fit.channels) sum += c.rmsCosineWeighted;
  return sum / static_cast<double>(fit.channels.size());
}

double chosenError(const FitResult& fit) {
  for (const auto& c : fit.candidates) {
    if (c.chosen) return c.heldOutScore;
  }
  return 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  fs::path shared = "../shared/data/cornell";
  fs::path chart = "docs/images/fit_lobes.png";
  int maxLobes = 4;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--samples" && i + 1 < argc) return writeSamples(argv[++i]);
    if (arg == "--shared" && i + 1 < argc) shared = argv[++i];
    else if (arg == "--chart" && i + 1 < argc) chart = argv[++i];
    else if (arg == "--max-lobes" && i + 1 < argc) maxLobes = std::atoi(argv[++i]);
    else {
      std::cerr << "usage: fit_bench [--shared DIR] [--chart PNG] [--max-lobes N] | --samples DIR\n";
      return 2;
    }
  }
  const std::vector<std::string> names{"garnet_red.astm", "garnet_red_RGB.astm", "krylon_blue.astm", "krylon_blue_RGB.astm",
                                       "krylon_blue.brdf"};
  if (!fs::is_directory(shared)) {
    std::cerr << "fit_bench: " << shared.string() << " not found; pass --shared DIR\n";
    return 1;
  }
  try {
    // 1. The default fit of each table (for docs/fitting.md).
    std::cout << "| table | model | rms(cos f) R / G / B (1/sr) | log-RMSE R / G / B | worst sample (G) | iterations | time (s) | termination |\n";
    std::cout << "|---|---|---|---|---|---|---|---|\n";
    for (const auto& name : names) {
      const MeasuredTable table = readTableForFitting(shared / name).toRgb();
      const FitResult fit = fitLobes(table);
      std::ostringstream row;
      row << std::fixed;
      row << "| " << name << " | " << fit.model.channels[0].lobes.size() << " " << toString(fit.model.elevation) << " | ";
      row << std::setprecision(3);
      for (std::size_t c = 0; c < 3; ++c) row << (c ? " / " : "") << fit.channels[c].rmsCosineWeighted;
      row << " | ";
      for (std::size_t c = 0; c < 3; ++c) row << (c ? " / " : "") << fit.channels[c].logRmse;
      const auto& w = fit.channels[1].worst;
      row << " | " << std::setprecision(2) << w.measured << " measured, " << w.fitted << " fitted at theta_i " << std::setprecision(0)
          << degrees(w.angles.thetaIn) << ", theta_s " << degrees(w.angles.thetaOut) << ", phi_s " << degrees(w.angles.phiOut)
          << " | ";
      int iterations = 0;
      for (const auto& c : fit.channels) iterations += c.totalIterations;
      row << iterations << " | " << std::setprecision(2) << fit.seconds << " | " << fit.channels[0].solver.termination << " |";
      std::cout << row.str() << "\n" << std::flush;
    }

    // 2. Error and time against lobe count.
    std::vector<Point> points;
    for (const auto& name : names) {
      const MeasuredTable table = readTableForFitting(shared / name).toRgb();
      for (ElevationChoice elevation : {ElevationChoice::Constant, ElevationChoice::Varying}) {
        for (int lobes = 1; lobes <= maxLobes; ++lobes) {
          FitOptions options;
          options.lobes = lobes;
          options.elevation = elevation;
          const FitResult fit = fitLobes(table, options);
          points.push_back({name, fit.model.elevation, lobes, chosenError(fit), meanRms(fit), fit.seconds});
          std::cerr << name << " " << toString(elevation) << " " << lobes << ": error " << chosenError(fit) << ", rms(cos f) "
                    << meanRms(fit) << ", " << fit.seconds << " s\n";
        }
      }
    }
    std::cout << "\n| table | elevation | lobes | RMS cube-root error | mean rms(cos f) (1/sr) | time (s) |\n|---|---|---|---|---|---|\n";
    for (const auto& p : points) {
      std::cout << "| " << p.table << " | " << toString(p.elevation) << " | " << p.lobes << " | " << std::setprecision(4) << p.error
                << " | " << p.rms << " | " << std::setprecision(3) << p.seconds << " |\n";
    }

    if (!findGnuplot()) {
      std::cerr << "fit_bench: gnuplot not found; no chart written\n";
      return 0;
    }
    std::ostringstream script;
    script.precision(6);
    for (std::size_t t = 0; t < names.size(); ++t) {
      for (int e = 0; e < 2; ++e) {
        script << "$d" << t << "_" << e << " << EOD\n";
        for (const auto& p : points) {
          if (p.table == names[t] && static_cast<int>(p.elevation) == e) {
            script << p.lobes << " " << p.error << " " << p.rms << " " << p.seconds << "\n";
          }
        }
        script << "EOD\n";
      }
    }
    script << "set terminal pngcairo size 1500,520 font 'sans,10'\nset output " << gnuplotQuote(chart.string()) << "\n";
    script << "set termoption noenhanced\nset grid\nset xtics 1\nset xrange [0.8:" << maxLobes + 0.2 << "]\nset xlabel 'lobes per channel'\n";
    script << "set multiplot layout 1,3 title 'Lobe fits of the Cornell tables (RGB; dashed constant, solid varying; krylon_blue.brdf = krylon_blue.astm)'\n";
    const char* colors[] = {"#c0392b", "#e67e22", "#2e6fd0", "#16a085", "#8e44ad"};
    const char* labels[] = {"RMS cube-root residual ((1/sr)^(1/3))", "mean rms of cos(theta_i) (f_fit - f) (1/sr)", "fit time (s)"};
    const int columns[] = {2, 3, 4};
    for (int panel = 0; panel < 3; ++panel) {
      script << "set ylabel '" << labels[panel] << "'\n";
      if (panel == 2) script << "set key top left font ',8'\n";
      else script << "unset key\n";
      if (panel == 1) script << "set logscale y\n";
      else script << "unset logscale y\n";
      script << "plot ";
      for (std::size_t t = 0; t < names.size(); ++t) {
        for (int e = 0; e < 2; ++e) {
          if (t || e) script << ", ";
          script << "$d" << t << "_" << e << " using 1:" << columns[panel] << " with linespoints lw 1.5 pt " << (e ? 7 : 6)
                 << " dt " << (e ? 1 : 2) << " lc rgb '" << colors[t] << "' title "
                 << gnuplotQuote(names[t] + (e ? " varying" : " constant"));
        }
      }
      script << "\n";
    }
    script << "unset multiplot\n";
    runGnuplot(script.str());
    std::cerr << "wrote " << chart.string() << "\n";
  } catch (const Error& e) {
    std::cerr << "fit_bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
