#pragma once
/// @file
/// Evaluating a BRDF (a fit.json, a measured table or a material file: spec/brdf_file.hpp) at given
/// directions: what `brdfbake eval` does, as one call.

#include <brdfbake/run/job.hpp>
#include <brdfbake/spec/brdf_file.hpp>

#include <Eigen/Core>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake {

struct EvaluateOptions {
  std::filesystem::path model;             ///< fit.json, measured table or material JSON
  TableFormat format = TableFormat::Auto;  ///< of a table
  /// One pair of directions (local frame, z the normal, both away from the surface; any length
  /// but 0): wi towards the light, wo towards the viewer...
  std::optional<Vec3> wi, wo;
  /// ...or a file of lines "theta_i phi_i theta_s phi_s" (radians, Cornell's convention: theta
  /// from the normal, phi from x towards y); blank and '#' lines are kept as they are.
  std::filesystem::path pairs;

  /// Throws Error(InvalidArgument) unless exactly one of (wi and wo) and `pairs` is given, and
  /// wi, wo are finite and non-zero.
  void validate() const;
};

struct EvaluateResult {
  std::filesystem::path model, pairs;
  std::string kind;  ///< BrdfFile::kind
  std::vector<std::string> channels;
  /// One row per direction pair (with --pairs, one per line of the file: `value` empty for blank
  /// and comment lines, whose `text` is the line itself).
  struct Row {
    int line = 0;  ///< 1-based line of the pairs file, 0 for a single pair
    Vec3 wi = Vec3::Zero(), wo = Vec3::Zero();
    std::optional<Eigen::VectorXd> value;  ///< BRDF per channel, 1/sr
    std::string text;
  };
  std::vector<Row> rows;
  std::vector<std::filesystem::path> files;  ///< none: eval writes nothing
  std::vector<std::string> notes;

  /// One line per row: the values (9 significant digits), or the kept line.
  std::string briefReport() const;
  /// "columns (N channels): NAME ...\n" naming the values' columns when there are more than three
  /// (a spectral table or fit), else "": the tool prints it to stderr, once.
  std::string columnsLine() const;
  /// {"model", "kind", "channels", "wi", "wo", "value"} for one pair; {"model", "kind", "channels",
  /// "pairs", "values": [{"line", "value"}]} for a pairs file.
  nlohmann::json toJson() const;
};

/// Reads the BRDF and evaluates it; a pairs file is read and checked whole (errors name FILE:LINE)
/// before anything is returned. Throws Error(Numerical) if the BRDF gives a non-finite value.
EvaluateResult evaluateBrdf(const EvaluateOptions& options, const Context& context = {});

}  // namespace brdfbake
