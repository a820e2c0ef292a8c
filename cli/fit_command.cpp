// brdfbake fit TABLE: fit radially symmetric lobes to a measured table (docs/fitting.md).
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>
#include <brdfbake/fit/cornell_grid.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/fit/fit_report.hpp>
#include <brdfbake/fit/gnuplot.hpp>
#include <brdfbake/fit/lobe_fit.hpp>
#include <brdfbake/measured/measured_io.hpp>

#include <iomanip>
#include <iostream>

#include "commands.hpp"
#include "terminal.hpp"

namespace brdfbake::cli {
namespace fs = std::filesystem;

namespace {

struct FitArgs {
  std::string table;
  std::string format = "auto";
  std::string lobes = "auto";
  std::string elevation = "auto";
  std::string channels = "rgb";
  std::string rgb = "cie1931";
  std::string output;
  std::string report;
  int threads = 0;
  bool json = false;
  bool quiet = false;
};

int parseLobes(const std::string& text) {
  if (text == "auto") return 0;
  try {
    std::size_t used = 0;
    const int lobes = std::stoi(text, &used);
    if (used == text.size() && lobes >= 1 && lobes <= kMaxFitLobes) return lobes;
  } catch (const std::exception&) {
  }
  throw Error(Error::Kind::InvalidArgument,
              "--lobes: expected auto or a whole number 1.." + std::to_string(kMaxFitLobes) + ", got '" + text + "'");
}

int runFit(FitArgs args) {
  FitOptions options;
  options.lobes = parseLobes(args.lobes);
  options.elevation = *parseElevationChoice(args.elevation);  // checked by CLI11
  options.threads = args.threads;
  const TableFormat format = *parseTableFormat(args.format);
  const RgbMethod rgbMethod = args.rgb == "cie1931" ? RgbMethod::Cie1931 : RgbMethod::SingleWavelengths;
  // Refuse what cannot be done before the (slow) fit.
  if (!args.report.empty() && !findGnuplot()) {
    throw Error(Error::Kind::InvalidArgument,
                "--report needs gnuplot, which was not found on PATH (Debian: apt-get install gnuplot-nox)");
  }
  // Without -o the fit goes to TABLESTEM_fit.json in the current folder (never thrown away), except
  // with --json, which prints it.
  if (args.output.empty() && !args.json) args.output = fs::path(args.table).stem().string() + "_fit.json";
  FilePlan plan;
  plan.addInput(args.table, "table");
  if (!args.output.empty()) plan.addOutput(args.output, "-o");
  if (!args.report.empty()) plan.addOutput(args.report, "--report");
  plan.check();

  const MeasuredTable read = readTableForFitting(args.table, format);
  MeasuredTable table;
  FitSource source;
  source.file = args.table;
  source.format = std::string(tableFormatName(read.format));
  source.samples = read.size();
  if (args.channels == "spectral") {
    if (read.kind != ChannelKind::Spectral) {
      throw Error(Error::Kind::InvalidArgument, args.table + ": --channels spectral needs a spectral table; this one has " +
                                                    std::to_string(read.channelCount()) + " non-spectral channel(s)");
    }
    table = read;
    source.channels = "spectral: " + std::to_string(read.channelCount()) + " channels as measured";
  } else {
    table = read.toRgb(rgbMethod);
    source.channels = read.kind == ChannelKind::Spectral
                          ? std::string("rgb: ") + (rgbMethod == RgbMethod::Cie1931 ? "CIE 1931 / D65 to linear sRGB" : "single wavelengths") +
                                " from " + std::to_string(read.channelCount()) + " spectral channels"
                          : "rgb: as stored in the file";
  }
  source.notes = table.notes;

  ProgressBar bar("fit " + fs::path(args.table).filename().string(), !args.json && !args.quiet);
  options.progress = bar.callback();
  FitFile file;
  file.source = source;
  file.fit = fitLobes(table, options);
  options.progress = nullptr;
  bar.done();

  if (!args.output.empty()) writeFitFile(args.output, file);
  if (!args.report.empty()) {
    std::ostringstream title;
    title << fs::path(args.table).filename().string() << ": " << file.fit.model.channels[0].lobes.size() << " "
          << toString(file.fit.model.elevation) << " lobe(s)";
    writeFitReport(args.report, table, file.fit.model, title.str());
  }

  if (args.json) {
    // The run report, as every command's --json: what was read and written, and the fit itself.
    nlohmann::json report = {{"table", args.table},
                             {"samples", read.size()},
                             {"channels", source.channels},
                             {"seconds", file.fit.seconds},
                             {"usable", file.fit.usable()},
                             {"files", nlohmann::json::array()},
                             {"notes", source.notes},
                             {"fit", fitFileToJson(file)}};
    if (!args.output.empty()) report["files"].push_back(args.output);
    if (!args.report.empty()) report["files"].push_back(args.report);
    std::cout << report.dump(2) << "\n";
  } else if (!args.quiet) {
    std::cout << args.table << ": " << read.size() << " samples, " << source.channels << "\n" << file.fit.briefReport();
    std::cout << "  models tried (error = RMS cube-root residual):";
    for (const auto& c : file.fit.candidates) {
      std::cout << " " << c.lobes << " " << toString(c.elevation) << " " << std::setprecision(4) << c.error
                << (c.chosen ? " (chosen)" : "") << ";";
    }
    std::cout << "\n";
    for (const auto& note : source.notes) std::cout << "  note: " << note << "\n";
    if (!args.output.empty()) std::cout << "wrote " << args.output << "\n";
    if (!args.report.empty()) std::cout << "wrote " << args.report << "\n";
  }
  if (!file.fit.usable()) {
    std::cerr << "brdfbake: warning: the fit is not usable (a solve failed); see the termination per channel"
              << (args.output.empty() ? "" : " in " + args.output) << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

Command addFitCommand(CLI::App& app) {
  auto args = std::make_shared<FitArgs>();
  auto* command = app.add_subcommand("fit", "Fit radially symmetric lobes (Kautz-McCool) to a measured BRDF table with Ceres");
  command->footer(R"(Model, per channel (1/sr):
  f(l, v) = k_d/pi + sum_k C_k (n_k + 2)/(2 pi) max(0, r_v.l)^n_k,  r_v = view mirrored about the normal,
with C_k, n_k constant (one 2-D lobe) or varying with the view elevation (a 3-D map). Residual: cube
roots of cos(theta_i) f, Cauchy loss; bounds C >= 0, 1 <= n <= 1e5. --lobes auto keeps the smallest
count that one more lobe improves by less than 3 % (up to 3 lobes); --elevation auto keeps constant
lobes unless varying ones are 10 % better. MERL tables are sampled on the Cornell grid first. Details and the
fit.json format: docs/fitting.md. Exit status 1 when a solve failed: the fit is still written, with
"usable": false.

Examples:
  brdfbake fit ../shared/data/cornell/garnet_red.astm --lobes auto -o fit.json
  brdfbake fit krylon_blue.astm --lobes 2 --elevation varying -o fit.json --report fit.png
  brdfbake fit garnet_red.astm --channels spectral -o fit_spectral.json --json
  brdfbake eval fit.json --wi 0,0.5,0.866 --wo 0,-0.5,0.866
Then bake a map from it: {"model": "lobes", "file": "fit.json"} in a spec (data_samples/specs/measured_lobes.json).)");
  command->add_option("table", args->table, "Measured table (.astm, .brdf, .binary, .mat)")->required();
  command->add_option("--format", args->format, "Table format (auto detects by content)")
      ->default_val("auto")
      ->check(CLI::IsMember({"auto", "astm", "pbrt", "merl", "mat"}));
  command->add_option("--lobes", args->lobes, "Lobes per channel: auto or 1..6")->default_val("auto");
  command->add_option("--elevation", args->elevation, "Lobe parameters constant, or varying with the view elevation")
      ->default_val("auto")
      ->check(CLI::IsMember({"auto", "constant", "varying"}));
  command->add_option("--channels", args->channels, "Fit R, G, B (spectral tables converted), or every wavelength")
      ->default_val("rgb")
      ->check(CLI::IsMember({"rgb", "spectral"}));
  command->add_option("--rgb", args->rgb, "Spectral to RGB: CIE 1931 (default) or Zimmons & Bastos 1999's single wavelengths")
      ->default_val("cie1931")
      ->check(CLI::IsMember({"cie1931", "single_wavelengths"}));
  command->add_option("-o,--output", args->output, "Write the fit here (fit.json format; default TABLESTEM_fit.json in the current folder, none with --json)");
  command->add_option("--report", args->report, "Also write a PNG of measured vs fitted values per incident angle (needs gnuplot)");
  addThreadsOption(command, args->threads);
  addJsonFlag(command, args->json, "files, seconds, and the fit document under \"fit\"");
  addQuietFlag(command, args->quiet);
  return [args] { return runFit(*args); };
}

}  // namespace brdfbake::cli
