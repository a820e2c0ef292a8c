#pragma once
/// @file
/// Time against accuracy for every map of a spec, with the Pareto front (docs/charts.md): what
/// `brdfbake chart SPEC.json -o chart.png` does, as one call. Material maps are baked over
/// parameterization x resolution x samples per texel and their bilinear lookups measured against
/// the exact model (the error `auto` bounds: ErrorStats::bound); prefiltered environment maps are
/// made over parameterization x resolution x method and measured against the reference prefilter
/// on random texels (or lookups).

#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/run/job.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace brdfbake {

struct ChartOptions {
  std::filesystem::path spec;
  std::vector<int> resolutions{32, 64, 128, 256, 512};  ///< material maps
  std::vector<int> environmentResolutions{16, 32, 64};  ///< environment maps (they also pay the reference)
  std::vector<int> samplesPerTexel{1, 4, 16};           ///< material maps
  std::vector<ParameterizationKind> parameterizations{ParameterizationKind::Sphere, ParameterizationKind::Paraboloid,
                                                      ParameterizationKind::Cube, ParameterizationKind::LatLong};
  std::vector<PrefilterMethod> methods{PrefilterMethod::Auto, PrefilterMethod::SphericalHarmonics,
                                       PrefilterMethod::Direct, PrefilterMethod::Importance};
  double maxError = 0.0;        ///< environment maps: the bound methods are set for; 0 = each map's max_error
  int subset = 256;             ///< environment maps: random texels (and lookups) compared with the reference
  int lookups = 20000;          ///< material maps: random directions per error measurement
  bool lookupError = false;     ///< environment maps: chart the error of bilinear lookups, not of texels
  std::filesystem::path chart;  ///< .png or .svg, one panel per map (empty: none)
  std::filesystem::path csv;    ///< the points as CSV (empty: none)

  void validate() const;
};

/// One configuration made and measured.
struct ChartPoint {
  std::string map, parameterization;
  std::string method = "bake";  ///< "bake" for material maps; auto, sh, direct, importance, reference
  std::string detail;           ///< the setting the prefilter chose ("order 16 on a 88x44 grid")
  int resolution = 0, samples = 0;
  long long texels = 0;
  double seconds = 0.0;
  double rms = 0.0, max = 0.0, visibleRms = 0.0;
  /// Material maps only (-1: none): ErrorStats' value-weighted RMS and maximum, and the bound
  /// (ErrorStats::bound) charted.
  double highlightRms = -1.0, highlightMax = -1.0, bound = -1.0;
  /// Environment maps only (-1: none).
  double estimate = -1.0;  ///< the prefilter's own error estimate
  double lookupRms = -1.0, lookupMax = -1.0;
  double referenceSeconds = -1.0;  ///< the reference over the whole map, scaled from the subset
  bool metBound = true;
  bool environment = false;
  bool pareto = false;  ///< no other point of its map beats it in both time and charted error
};

/// A map or configuration that could not be charted, and why.
struct ChartSkip {
  std::string map, parameterization, method, note;
  int resolution = 0;
};

struct ChartResult {
  std::vector<ChartPoint> points;
  std::vector<ChartSkip> skipped;
  std::filesystem::path chart;  ///< the picture the points are drawn in (empty: none)
  int panels = 0;
  std::vector<std::filesystem::path> files;
  std::vector<std::string> notes;

  std::string briefReport() const;  ///< skipped combinations, files written
  nlohmann::json toJson() const;    ///< the points, then the skipped ones ("skipped": true)
};

ChartResult chartSpec(const ChartOptions& options, const Context& context = {});

}  // namespace brdfbake
