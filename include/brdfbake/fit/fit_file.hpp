#pragma once
/// @file
/// fit.json: a fitted lobe model with its fit statistics, as `brdfbake fit` writes it and the
/// "lobes" material, `brdfbake eval` and the benches read it. Format (docs/fitting.md, "fit.json"),
/// version 1:
///
///     {"format": "brdfbake.lobe_fit", "version": 1, "generator": "brdfbake 0.1.0",
///      "source": {"file", "format", "samples", "channels", "notes": [...]},           optional
///      "model": {"description", "elevation": "constant" | "varying",
///                "elevation_range": {"min_cos", "max_cos"}, "lobes": K,
///                "wavelengths_nm": [...],                                              optional key
///                "half_difference": {"half_angle_knots": K, "difference_degree": D}},  optional key
///      "fit": {"residual", "loss", "loss_scale", "auto_margin", "elevation_margin", "requested_lobes",
///              "requested_elevation", "seconds", "usable", "candidates": [...]},       optional
///      "channels": [{"name", "diffuse", "lobes": [{"weight": [...], "exponent": [...]}],
///                    "half_difference": [K (D + 1) numbers, with model.half_difference only],
///                    "stats": {"samples", "rms_cosine_weighted", "log_rmse", "cube_root_rmse",
///                              "worst_sample": {"index", "theta_i", "phi_i", "theta_s",
///                                               "phi_s", "measured", "fitted"},
///                              "iterations", "total_iterations", "seconds", "termination",
///                              "usable", "brief_report"}}]}                             stats optional
///
/// Units: BRDF values 1/sr, angles radians, weights dimensionless, seconds of wall time. "weight"
/// and "exponent" hold one value (constant) or three (varying: the values p0, p1, p2 of
/// brdf/lobes.hpp); "half_difference" the coefficients a_kj of brdf/half_difference_table.hpp at k (D + 1) + j.
/// Optional parts may be left out of hand-written files; everything present is validated.

#include <brdfbake/fit/lobe_fit.hpp>

#include <brdfbake/io/json_reader.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace brdfbake {

inline constexpr int kFitFileVersion = 1;
inline constexpr const char* kFitFileFormat = "brdfbake.lobe_fit";

/// Where the fitted data came from.
struct FitSource {
  std::string file;    ///< the table's file name, no folder ("" if in memory)
  std::string format;  ///< "astm", "pbrt", "merl", "mat", "synthetic", ...
  std::size_t samples = 0;
  std::string channels;  ///< how the fitted channels were made, e.g. "rgb: CIE 1931 from 31 spectral channels"
  std::vector<std::string> notes;  ///< the table's notes
};

struct FitFile {
  FitSource source;
  /// The model and statistics. Read back: `fit.channels` is empty when the file has no "stats",
  /// `fit.candidates` when it has no "fit"; `fit.options` holds what "fit" says (defaults without).
  FitResult fit;
  bool hasSource = true;   ///< false when read from a file without "source"
  bool hasFitInfo = true;  ///< false when read from a file without "fit"
};

/// One line describing the model formula for `elevation` (the file's model.description).
std::string lobeModelDescription(LobeElevation elevation, ColorProfile colorProfile = ColorProfile::None);
/// The same for a model that is a half-difference table (LobeModel::halfDifference).
std::string halfDifferenceTableDescription();

/// The JSON document, keys in the order of @file. Throws Error(Numerical) if some number is not
/// finite (never written).
nlohmann::ordered_json fitFileToJson(const FitFile& file);

/// True if `document` says it is a fit file (an object whose "format" is kFitFileFormat).
bool isFitFileJson(const nlohmann::json& document);

/// Parses and validates a document. Errors are Error(InvalidInput) "<label>: <json path>: ...",
/// e.g. "fit.json: channels[0].lobes[1].exponent[2]: must be <= 100000, got 2e+05"; unknown keys
/// are rejected. A version other than kFitFileVersion is an error naming both versions.
FitFile fitFileFromJson(const nlohmann::json& document, const std::string& label = "fit");

/// Writes the document (2-space indented), atomically: a temporary file in the same folder renamed
/// over `path`. Throws Error(Io) if it cannot.
void writeFitFile(const std::filesystem::path& path, const FitFile& file);

/// Reads a fit file. Throws Error(Io) if unreadable, Error(InvalidInput) with line and column for
/// JSON syntax errors, and the errors of fitFileFromJson (labelled with the file name).
FitFile readFitFile(const std::filesystem::path& path);

}  // namespace brdfbake
