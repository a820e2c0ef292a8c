#pragma once
/// @file
/// Choosing the cheapest map that meets an accuracy target ("model no more than a scene needs").

#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/baker.hpp>

#include <string>
#include <vector>

namespace brdfbake {

/// One map configuration.
struct MapConfiguration {
  ParameterizationKind parameterization = ParameterizationKind::Sphere;
  int resolution = 0;
  int samplesPerTexel = 0;
  /// Cost: texels x samples per texel (memory and bake time both follow it).
  long long cost() const;
  std::string describe() const;  ///< "sphere 64^2, 4 samples/texel"
};

struct AutoOptions {
  std::vector<ParameterizationKind> parameterizations{ParameterizationKind::Sphere};
  std::vector<int> resolutions{16, 32, 64, 128, 256, 512, 1024, 2048};
  std::vector<int> samplesPerTexel{1, 4, 16, 64};
  /// Target: RMS lookup error relative to the peak (ErrorStats::rms, or visibleRms for sphere
  /// maps: the directions a renderer looks up), in (0, 1).
  double maxError = 0.01;
  ErrorOptions error;      ///< how errors are measured
  BakeOptions bake;        ///< threads, progress, limits (samplesPerTexel is overridden)

  void validate() const;
};

struct AutoResult {
  MapConfiguration chosen;
  double error = 0.0;      ///< its measured error
  Image image;             ///< the chosen map, baked
  int tried = 0;           ///< configurations baked and measured, the chosen one included
  /// The errors of the cheaper configurations tried (all above maxError).
  std::vector<std::pair<MapConfiguration, double>> rejected;
};

/// The error measure AutoOptions::maxError bounds, for one measurement.
double autoErrorMeasure(const ErrorStats& stats, ParameterizationKind kind);

/// Tries every combination of the options' parameterizations, resolutions and samples in order of
/// increasing cost, and returns the first (so the cheapest) whose measured error meets maxError;
/// every cheaper combination was tried and missed it. Throws Error(InvalidInput) naming the best
/// error reached when none does.
AutoResult chooseConfiguration(const MapFunction& function, const AutoOptions& options);

}  // namespace brdfbake
