// brdfbake fit TABLE: fit lobes to a measured table (fitTable).
#include <brdfbake/run/fit_table.hpp>

#include <sstream>

#include "commands.hpp"
#include "flags.hpp"

namespace brdfbake::cli {

namespace {

constexpr const char* kFooter = R"(Model, per channel (1/sr):
  f(l, v) = k_d/pi + sum_k C_k (n_k + 2)/(2 pi) max(0, c_k (l_x v_x + l_y v_y) + l_z v_z)^n_k
with c_k = -1 a Phong lobe about the mirrored view (--kind mirror), other c_k Lafortune et al.
1997's generalised cosine lobes, or half-vector lobes with a Fresnel weight (--kind half_vector);
--kind mixed lets each lobe be a half-vector or a mirror lobe. C_k and n_k are constant, or vary
smoothly with the view's elevation (--elevation varying). With --color-profile difference_angle
each channel's k_d, C_k (and Fresnel weight) are also multiplied by a cubic polynomial in theta_d,
the angle between light and half-vector: colours that shift with angle (interference paints).
Where no lobes follow a table, a smooth table of ln f over the half and difference angles
(theta_h, theta_d) may (--kind half_difference); with --kind auto and --lobes auto (and neither
--elevation varying nor --color-profile difference_angle), --half-difference auto (default) scores
it after the lobes and keeps it only if it does better held out.
--method shared (default): the lobes' shapes (and elevation profiles) are shared by every channel,
weights by non-negative least squares; --method per_channel: Ceres, each channel on its own.
The fit estimates its held-out error (log error on rows it did not see: k-fold over rows away from
the mirror, and each interior incident elevation held out whole, as a ratio to a Lambertian fit)
and --lobes / --kind / --elevation / --max-exponent / --varying-prior / --color-profile auto choose
by it: the worse of the two ratios decides. The report also names the best radially symmetric
model (mirror lobes, which prefilter an environment) and its held-out error, and each split where
one row holds half or more of the squared held-out error (a highlight sampled once), with the ratio
without it. Without -o the fit goes to
TABLESTEM_fit.json in the current folder (none with --json, which prints it). Exit status 1 when a
solve failed: the fit is still written, with "usable": false. Details and fit.json: docs/fitting.md.

Examples:
  brdfbake fit garnet_red.astm -o fit.json --report fit.png
  brdfbake fit krylon_blue.astm --lobes 2 --kind lafortune -o fit.json
  brdfbake fit garnet_red.astm --channels spectral -o fit_spectral.json --json
Then bake it: {"model": "lobes", "file": "fit.json"} in a spec, or brdfbake eval fit.json --wi ... --wo ...)";

struct FitArgs {
  CommonFlags flags;
  FitTableOptions options;
  std::optional<double> maxExponent, varyingPrior;
};

// "auto" (nullopt) or a number in [lowest, highest].
auto autoOrNumber(double lowest, double highest, bool whole) {
  return [=](const std::string& text) -> std::optional<double> {
    if (text == "auto") return std::nullopt;
    const double value = whole ? parseWholeNumber(text) : parseFiniteNumber(text);
    if (value >= lowest && value <= highest) return value;
    std::ostringstream range;
    range << "expected auto or a " << (whole ? "whole " : "") << "number " << lowest << ".." << highest << ", got '"
          << text.substr(0, 40) << "'";
    throw Error(Error::Kind::InvalidArgument, range.str());
  };
}

// One of two words, the first meaning true.
CLI::Option* addSwitch(CLI::App* command, const std::string& flag, bool& target, const std::string& yes,
                       const std::string& no, const std::string& help) {
  return command
      ->add_option_function<std::string>(
          flag, [&target, yes](const std::string& text) { target = text == yes; }, help)
      ->check(CLI::IsMember({yes, no}))
      ->default_str(target ? yes : no);
}

void addModelFlags(CLI::App* command, FitArgs& a) {
  FitOptions& fit = a.options.fit;
  addParsed(
      command, "--lobes", fit.lobes,
      [](const std::string& text) { return static_cast<int>(autoOrNumber(1, kMaxFitLobes, true)(text).value_or(0)); },
      "Lobes per channel: auto or 1.." + std::to_string(kMaxFitLobes))
      ->default_str("auto");
  addParsed(command, "--kind", fit.kind, parseLobeKindChoice,
            "auto | mirror | lafortune | half_vector | mixed | half_difference (the shared method's lobes, or a "
            "half-difference table)")
      ->default_str("auto");
  addParsed(command, "--elevation", fit.elevation, parseElevationChoice,
            "auto | constant | varying (with the view's elevation)")
      ->default_str("auto");
  addParsed(command, "--method", fit.method, parseFitMethod,
            "shared (shapes shared by every channel) | per_channel (Ceres)")
      ->default_str("shared");
  addParsed(command, "--max-exponent", a.maxExponent, autoOrNumber(1, 1e5, false),
            "auto, or a number in [1, 1e5] that fixes the cap")
      ->default_str("auto");
  addParsed(command, "--varying-prior", a.varyingPrior, autoOrNumber(0, 1, false),
            "auto, or a number in [0, 1] that fixes the prior on varying lobes' elevation profiles")
      ->default_str("auto");
  addParsed(command, "--color-profile", fit.colorProfile, parseColorProfileChoice,
            "auto | none | difference_angle (each channel's weights times a cubic in theta_d; shared method)")
      ->default_str("auto");
  addSwitch(command, "--half-difference", fit.halfDifference, "auto", "none",
            "auto | none: --kind auto also scores a half-difference table (docs/fitting.md)");
  addSwitch(command, "--held-out", fit.estimateHeldOut, "on", "off",
            "on | off: estimate the fit's held-out error (auto choices need it)");
  command->add_option("--folds", fit.heldOut.folds, "Folds of the off-mirror held-out split")
      ->default_val(5)
      ->check(CLI::Range(2, 20));
}

void addDataFlags(CLI::App* command, FitTableOptions& o) {
  command->add_option("table", o.table, "Measured table (.astm, .brdf, .binary, .mat)")->required();
  addParsed(command, "--format", o.format, parseTableFormat, "auto | astm | pbrt | merl | mat (auto: by content)")
      ->default_str("auto");
  addSwitch(command, "--channels", o.spectral, "spectral", "rgb",
            "rgb (spectral tables converted) | spectral (every wavelength)");
  addParsed(command, "--rgb", o.rgb, parseRgbMethod,
            "Spectral to RGB: cie1931 | single_wavelengths (Zimmons & Bastos 1999)")
      ->default_str("cie1931");
  command->add_option("-o,--output", o.output, "fit.json to write (default TABLESTEM_fit.json; none with --json)");
  command->add_option("--report", o.report, "Also a PNG of measured against fitted values (needs gnuplot)");
}

int runFit(FitArgs a) {
  FitTableOptions& options = a.options;
  if (a.maxExponent) options.fit.maxExponent = *a.maxExponent, options.fit.chooseMaxExponent = false;
  if (a.varyingPrior) options.fit.varyingPrior = *a.varyingPrior, options.fit.chooseVaryingPrior = false;
  if (options.output.empty() && !a.flags.json) options.output = options.table.stem().string() + "_fit.json";
  const FitTableResult result = withProgress(a.flags, options, fitTable);
  printResult(result, a.flags);
  return result.file.fit.usable() ? 0 : 1;
}

}  // namespace

Command addFitCommand(CLI::App& app) {
  auto args = std::make_shared<FitArgs>();
  auto* command = app.add_subcommand("fit", "Fit lobes to a measured BRDF table; reports the fit's held-out error");
  command->footer(kFooter);
  addDataFlags(command, args->options);
  addModelFlags(command, *args);
  addCommonFlags(command, args->flags, Computes::Values, "files, seconds, and the fit document under \"fit\"");
  return [args] { return runFit(*args); };
}

}  // namespace brdfbake::cli
