#pragma once
/// @file
/// Choosing the cheapest map that meets an accuracy target ("model no more than a scene needs").

#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/bake/radial_profile.hpp>

#include <optional>

#include <string>
#include <vector>

namespace brdfbake {

/// One map configuration.
struct MapConfiguration {
  ParameterizationKind parameterization = ParameterizationKind::Sphere;
  int resolution = 0;
  int samplesPerTexel = 0;
  /// A 1-D radial profile of `resolution` texels instead of a 2-D map (bake/radial_profile.hpp);
  /// `parameterization` is then ignored.
  bool radialProfile = false;
  /// Cost: texels x samples per texel (memory and bake time both follow it).
  long long cost() const;
  long long texels() const;      ///< width x height (N for a profile)
  std::string describe() const;  ///< "sphere 64^2, 4 samples/texel" or "profile 64 texels, 4 samples/texel"
};

struct AutoOptions {
  std::vector<ParameterizationKind> parameterizations{ParameterizationKind::Sphere};
  std::vector<int> resolutions{16, 32, 64, 128, 256, 512, 1024, 2048};
  std::vector<int> samplesPerTexel{1, 4, 16, 64};
  /// Also try 1-D radial profiles (each resolution x samples) when the function has a symmetry
  /// axis (MapFunction::symmetryAxis): a radially symmetric map needs only its profile. With no
  /// parameterizations, only profiles are tried.
  bool allowRadialProfile = false;
  /// Target, relative to the peak, in (0, 1): ErrorStats::bound, the larger of the
  /// value-weighted RMS (highlightRms: the highlight is within this fraction of its peak) and the
  /// RMS over the lookups a renderer makes (visibleRms for sphere maps, else rms). docs/accuracy.md.
  double maxError = 0.01;
  ErrorOptions error;  ///< how errors are measured
  BakeOptions bake;    ///< the bakes' settings (samplesPerTexel is overridden)

  void validate() const;
};

struct AutoResult {
  MapConfiguration chosen;
  double error = 0.0;                          ///< its measured error
  Image image;                                 ///< the chosen map, baked (a profile: N x 1, RadialProfile::toImage)
  std::optional<RadialProfile> radialProfile;  ///< set when a profile was chosen
  int bakes = 0;                               ///< configurations baked in full and measured, the chosen one included
  int estimated = 0;  ///< configurations whose error was estimated (estimateMapError) without a bake
  /// The cheaper configurations looked at and their errors (all above maxError), cheapest first:
  /// estimates, and the measured error of any bake that missed.
  std::vector<std::pair<MapConfiguration, double>> rejected;
};

/// The error measure AutoOptions::maxError bounds, for one measurement: ErrorStats::bound, with
/// the visible-sphere lookups for sphere maps and for profiles about the view (+z).
double autoErrorMeasure(const ErrorStats& stats, ParameterizationKind kind);
double autoErrorMeasure(const ErrorStats& stats, const MapConfiguration& configuration, const Vec3& profileAxis);

/// The cheapest combination (cost, then fewer samples, then the options' order) of the options'
/// parameterizations, resolutions and samples whose error meets maxError, baked.
///
/// Candidates are not baked to be measured: their error is estimated from the texels the error
/// probes read (estimateMapError, estimateProfileError; cost bounded by the probes, not the
/// resolution). Per parameterization and sample count, the resolution is predicted from error ~
/// N^-p (p = 2 for one estimate, bilinear lookups being second order; measured from the last two
/// otherwise) and bracketed until the chosen resolution meets the bound and the next smaller one
/// misses it; a family is only looked at below the cost of the best so far, assuming the error
/// falls as the resolution grows. The choice is then baked and measured (ErrorStats::bound against
/// the same probes); if the bake misses, the next resolution is baked (docs/accuracy.md).
/// Candidates over the context's size limit (kMaxTexels unless allowLarge, memoryBudgetBytes) are left
/// out. Progress goes to `context`, as the fraction of the work done as far as it is known, never
/// decreasing: the search (estimates) fills the first 30 %, each bake most of what is left.
/// Throws Error(InvalidInput) naming the best error reached, and the resolution error ~ N^-2 puts
/// the bound at, when none meets it; Error(Resource) when every candidate is over the budget.
AutoResult chooseConfiguration(const MapFunction& function, const AutoOptions& options, const Context& context = {});

}  // namespace brdfbake
