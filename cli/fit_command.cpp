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

// " mirror", " Lafortune", " half-vector" or " mixed", for the report title.
const char* lobeKindName(const LobeModel& model) {
  if (model.allAboutMirror()) return " mirror";
  bool half = false, other = false;
  for (const auto& lobe : model.channels[0].lobes) (lobe.halfVector ? half : other) = true;
  return half ? (other ? " mixed" : " half-vector") : " Lafortune";
}

struct FitArgs {
  std::string table;
  std::string format = "auto";
  std::string lobes = "auto";
  std::string elevation = "auto";
  std::string method = "shared";
  std::string kind = "auto";
  std::string maxExponent = "auto";
  std::string heldOut = "on";
  int folds = 5;
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

// "auto": the cap is chosen by held-out error from 1e4 down (FitOptions::chooseMaxExponent);
// a number fixes it.
void parseMaxExponent(const std::string& text, FitOptions& options) {
  if (text == "auto") return;
  try {
    std::size_t used = 0;
    const double cap = std::stod(text, &used);
    if (used == text.size() && cap >= 1.0 && cap <= 1e5) {
      options.maxExponent = cap;
      options.chooseMaxExponent = false;
      return;
    }
  } catch (const std::exception&) {
  }
  throw Error(Error::Kind::InvalidArgument,
              "--max-exponent: expected auto or a number in [1, 1e5], got '" + text + "'");
}

int runFit(FitArgs args) {
  FitOptions options;
  options.lobes = parseLobes(args.lobes);
  options.elevation = parseElevationChoice(args.elevation);  // checked by CLI11
  options.threads = args.threads;
  options.method = parseFitMethod(args.method);  // checked by CLI11
  options.kind = parseLobeKindChoice(args.kind);
  parseMaxExponent(args.maxExponent, options);
  options.estimateHeldOut = args.heldOut == "on";
  options.heldOut.folds = args.folds;
  options.heldOut.threads = args.threads;
  if (options.method == FitMethod::Shared && options.elevation == ElevationChoice::Varying) {
    throw Error(Error::Kind::InvalidArgument,
                "--elevation varying needs --method per_channel (the shared method fits constant lobes; Lafortune "
                "lobes vary with elevation)");
  }
  options.validate();
  const TableFormat format = parseTableFormat(args.format);
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
      throw Error(Error::Kind::InvalidArgument, args.table +
                                                    ": --channels spectral needs a spectral table; this one has " +
                                                    std::to_string(read.channelCount()) + " non-spectral channel(s)");
    }
    table = read;
    source.channels = "spectral: " + std::to_string(read.channelCount()) + " channels as measured";
  } else {
    table = read.toRgb(rgbMethod);
    source.channels =
        read.kind == ChannelKind::Spectral
            ? std::string("rgb: ") +
                  (rgbMethod == RgbMethod::Cie1931 ? "CIE 1931 / D65 to linear sRGB" : "single wavelengths") +
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
          << toString(file.fit.model.elevation) << lobeKindName(file.fit.model) << " lobe(s)";
    if (const auto& h = file.fit.heldOut) {
      title << std::fixed << std::setprecision(2) << "; held-out / Lambert: k-fold " << h->kfold.ratio()
            << "x, elevations";
      for (const auto& e : h->elevations) title << " " << std::lround(e.elevationDegrees) << ":" << e.ratio() << "x";
    }
    writeFitReport(args.report, table, file.fit.model, title.str());
  }

  if (args.json) {
    // The run report, as every command's --json: what was read and written, and the fit itself.
    nlohmann::json report = {{"table", args.table},         {"samples", read.size()},
                             {"channels", source.channels}, {"seconds", file.fit.seconds},
                             {"usable", file.fit.usable()}, {"files", nlohmann::json::array()},
                             {"notes", source.notes},       {"fit", fitFileToJson(file)}};
    if (!args.output.empty()) report["files"].push_back(args.output);
    if (!args.report.empty()) report["files"].push_back(args.report);
    std::cout << report.dump(2) << "\n";
  } else if (!args.quiet) {
    std::cout << args.table << ": " << read.size() << " samples, " << source.channels << "\n" << file.fit.briefReport();
    std::cout << std::fixed << std::setprecision(4) << "  in-sample log error " << file.fit.inSampleError << "\n";
    if (const auto& h = file.fit.heldOut) {
      std::cout << std::setprecision(2) << "  held-out log error / Lambert: " << h->kfold.name << " "
                << h->kfold.ratio() << "x";
      for (const auto& e : h->elevations) std::cout << ", " << e.name << " " << e.ratio() << "x";
      std::cout << " (" << std::setprecision(1) << h->seconds << " s)\n";
    }
    if (!file.fit.candidates.empty()) {
      std::cout << "  models tried (held-out score = mean of the k-fold and elevation ratios to Lambert):\n";
      for (const auto& c : file.fit.candidates) {
        std::cout << "    " << c.lobes << " " << toString(c.kind) << " " << toString(c.elevation) << ", "
                  << c.parameters << " parameters: " << std::setprecision(3) << c.heldOutScore << " (k-fold "
                  << c.kfoldRatio << "x, elevations " << c.elevationRatio << "x, " << std::setprecision(1) << c.seconds
                  << " s)" << (c.chosen ? " chosen" : "") << "\n";
      }
    }
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
  auto* command = app.add_subcommand(
      "fit",
      "Fit radially symmetric lobes (Kautz-McCool, Lafortune) to a measured BRDF table; reports its held-out error");
  command->footer(R"(Model, per channel (1/sr):
  f(l, v) = k_d/pi + sum_k C_k (n_k + 2)/(2 pi) max(0, c_k (l_x v_x + l_y v_y) + l_z v_z)^n_k,
c_k = -1: a Phong lobe about the mirrored view (--kind mirror); other c_k: Lafortune et al. 1997's
generalised cosine lobes (back-scatter for c_k > 0, growth towards grazing for |c_k| > 1).
--method shared (default): every channel shares the lobes' n_k and c_k, k_d and C_k per channel by
non-negative least squares on the log error below; constant lobes. --method per_channel: Ceres per
channel on cube roots of cos(theta_i) f with a Cauchy loss, mirror lobes, C_k and n_k constant or
varying with the view elevation (a 3-D map).
Held-out error: sqrt(mean (ln(1 + cos theta_i f_fit) - ln(1 + cos theta_i f_measured))^2) on rows
the fit did not see: k-fold (--folds) over rows more than 5 deg from the mirror direction, and each
interior incident elevation held out whole; printed as a ratio to a per-channel Lambertian fit on
the same split, written to fit.json ("held_out") and the --report title. --lobes / --kind /
--elevation auto choose by that estimate (the fewest parameters within 1 % of the best), up to 3
lobes. MERL tables are sampled on the Cornell grid first. Details and the fit.json format:
docs/fitting.md. Exit status 1 when a solve failed: the fit is still written, with "usable": false.

Examples:
  brdfbake fit ../shared/data/cornell/garnet_red.astm --lobes auto -o fit.json
  brdfbake fit krylon_blue.astm --lobes 2 --kind lafortune -o fit.json --report fit.png
  brdfbake fit krylon_blue.astm --method per_channel --lobes 2 --elevation varying -o fit.json
  brdfbake fit garnet_red.astm --channels spectral -o fit_spectral.json --json
  brdfbake eval fit.json --wi 0,0.5,0.866 --wo 0,-0.5,0.866
Then bake a map from it: {"model": "lobes", "file": "fit.json"} in a spec (data_samples/specs/measured_lobes.json).)");
  command->add_option("table", args->table, "Measured table (.astm, .brdf, .binary, .mat)")->required();
  command->add_option("--format", args->format, "Table format (auto detects by content)")
      ->default_val("auto")
      ->check(CLI::IsMember({"auto", "astm", "pbrt", "merl", "mat"}));
  command->add_option("--lobes", args->lobes, "Lobes per channel: auto or 1..6")->default_val("auto");
  command
      ->add_option("--elevation", args->elevation,
                   "Lobe parameters constant, or varying with the view elevation (varying: --method per_channel)")
      ->default_val("auto")
      ->check(CLI::IsMember({"auto", "constant", "varying"}));
  command
      ->add_option("--method", args->method,
                   "shared: lobe shapes shared by every channel, weights by NNLS; per_channel: Ceres per channel")
      ->default_val("shared")
      ->check(CLI::IsMember({"shared", "per_channel"}));
  command
      ->add_option("--kind", args->kind,
                   "Lobes of the shared method: mirror (Phong), lafortune (c_xy free), half_vector (microfacet form "
                   "with a Fresnel weight; does not prefilter), or auto")
      ->default_val("auto")
      ->check(CLI::IsMember({"auto", "mirror", "lafortune", "half_vector"}));
  command
      ->add_option("--max-exponent", args->maxExponent,
                   "Largest lobe exponent of the shared method: a number in [1, 1e5] fixes it; auto starts at 1e4 and "
                   "keeps 3000 or 1000 where that lowers the held-out error")
      ->default_val("auto");
  command
      ->add_option("--held-out", args->heldOut, "Estimate the held-out error of the fit (always on with auto choices)")
      ->default_val("on")
      ->check(CLI::IsMember({"on", "off"}));
  command->add_option("--folds", args->folds, "Folds of the off-mirror held-out split")
      ->default_val(5)
      ->check(CLI::Range(2, 20));
  command->add_option("--channels", args->channels, "Fit R, G, B (spectral tables converted), or every wavelength")
      ->default_val("rgb")
      ->check(CLI::IsMember({"rgb", "spectral"}));
  command
      ->add_option("--rgb", args->rgb,
                   "Spectral to RGB: CIE 1931 (default) or Zimmons & Bastos 1999's single wavelengths")
      ->default_val("cie1931")
      ->check(CLI::IsMember({"cie1931", "single_wavelengths"}));
  command->add_option(
      "-o,--output", args->output,
      "Write the fit here (fit.json format; default TABLESTEM_fit.json in the current folder, none with --json)");
  command->add_option("--report", args->report,
                      "Also write a PNG of measured vs fitted values per incident angle (needs gnuplot)");
  addThreadsOption(command, args->threads);
  addJsonFlag(command, args->json, "files, seconds, and the fit document under \"fit\"");
  addQuietFlag(command, args->quiet);
  return [args] { return runFit(*args); };
}

}  // namespace brdfbake::cli
