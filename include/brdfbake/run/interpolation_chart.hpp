#pragma once
/// @file
/// The error of per-vertex environment lookups (`brdfbake interpolation`), as one call: the sweep
/// of bake/interpolation_error.hpp over triangle sizes and places, and Zimmons 1999's line
/// experiment, with their charts and CSV.

#include <brdfbake/bake/interpolation_error.hpp>
#include <brdfbake/run/job.hpp>

namespace brdfbake {

struct InterpolationOptions {
  std::vector<double> sizesDegrees{1, 2, 5, 10, 20};  ///< in (0, 60]: degrees between vertex normals
  std::vector<double> placesDegrees{0, 10, 20, 30, 40, 50, 60, 70, 75, 80, 85, 88};  ///< in [0, 90)
  Vec3 viewer{-8.3, 1.0, 0.0};                  ///< line experiment: the eye, above the surface (y > 0), |p| <= 1e6
  double segment = 20.0;                        ///< line experiment: vertex spacing, in [0.01, 20]
  std::filesystem::path chart, lineChart, csv;  ///< outputs (each optional): .png/.svg, .png/.svg, CSV

  /// Throws Error(InvalidArgument) naming the value out of range.
  void validate() const;
};

struct InterpolationResult {
  std::vector<InterpolationPoint> sweep;
  LineExperiment line;
  double segment = 20.0;
  std::vector<std::filesystem::path> files;
  std::vector<std::string> notes;

  std::string briefReport() const;  ///< files written, the line experiment's maximum
  nlohmann::json toJson() const;    ///< {"sweep": [...], "line": {...}, "files": [...]}
};

InterpolationResult chartInterpolation(const InterpolationOptions& options, const Context& context = {});

}  // namespace brdfbake
