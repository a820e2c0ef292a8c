#pragma once
/// @file
/// Fitting lobes to a measured table (docs/fitting.md): what `brdfbake fit TABLE -o fit.json` does,
/// as one call: read the table (any format, detected by content), convert spectral channels to RGB
/// unless asked for every wavelength, fit (fitLobes), write fit.json and the report chart.

#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/measured/measured_table.hpp>
#include <brdfbake/run/job.hpp>

#include <filesystem>
#include <string>

namespace brdfbake {

struct FitTableOptions {
  std::filesystem::path table;  ///< .astm, .brdf, .binary (MERL), .mat
  TableFormat format = TableFormat::Auto;
  /// How the fit goes (lobes, kind, method, held-out splits...).
  FitOptions fit;
  /// Fit every wavelength of a spectral table as measured, instead of R, G, B.
  bool spectral = false;
  RgbMethod rgb = RgbMethod::Cie1931;  ///< spectral to RGB
  std::filesystem::path output;        ///< fit.json to write (empty: none)
  std::filesystem::path report;        ///< PNG chart of measured against fitted values (empty: none)

  /// Throws Error(InvalidArgument) for bad fit options and a report without gnuplot.
  void validate() const;
};

struct FitTableResult {
  FitFile file;             ///< the fit, as written to fit.json
  std::size_t samples = 0;  ///< rows of the table as read
  std::vector<std::filesystem::path> files;
  std::vector<std::string> notes;  ///< the table's notes (clamped negatives, conversions)
  std::filesystem::path table;

  /// The fit's summary: model, in-sample and held-out errors, the candidates tried, files written.
  std::string briefReport() const;
  /// {"table", "samples", "channels", "seconds", "usable", "files", "notes", "fit": the fit.json document}.
  nlohmann::json toJson() const;
};

/// Reads, fits and writes (see @file); every file checked before the fit. Throws Error as the
/// table readers and fitLobes do. A fit whose solve failed is still written, with "usable": false.
FitTableResult fitTable(const FitTableOptions& options, const Context& context = {});

}  // namespace brdfbake
