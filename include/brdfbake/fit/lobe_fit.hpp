#pragma once
/// @file
/// Fitting radially symmetric lobes (brdf/lobes.hpp) to a measured table with Ceres. Method,
/// defaults and their reasons: docs/fitting.md.
///
/// Each channel is fitted on its own. Per sample i (light wi, view wo, measured f_i) the residual
/// is the difference of cube roots of the cosine-weighted values,
///
///     r_i = cbrt(cos theta_i f(wi, wo) + eps) - cbrt(cos theta_i f_i + eps),
///
/// (cos theta_i f is the reflected radiance per unit irradiance, what a map shows; the cube root,
/// sign-preserving, compresses a range of 1e-3 to hundreds of 1/sr into about 0.1 to 8, keeps the
/// RGB files' negative and zero values usable, and is close to perceived lightness; eps = 1e-6 of
/// the channel's largest cos theta_i f_i only keeps the derivative finite where the model is 0),
/// under a robust loss (Cauchy, scale 0.2 of the channel's largest cube-root value) against
/// samples the model cannot represent (dropouts, retro-reflection, grazing off-specular ridges):
/// wide enough that a highlight seen by a handful of samples still counts in full. Ceres'
/// Levenberg-Marquardt trust region solves it with bounds k_d >= 0, C >= 0 and 1 <= n <= 1e5 on
/// every coefficient (varying lobes: on each of their three values, optimised as logarithms).
///
/// Initialisation is greedy: k_d from a low percentile of the data; then each new lobe starts
/// from the best of a grid of exponents 2, 4, ..., 32768 (its weight from a linearised weighted
/// least-squares fit to what the lobes so far leave), the two best starts are refined with every
/// parameter free, and the better result is kept. A varying model with K lobes has three starts,
/// of which the two cheapest are refined: the constant K-lobe model (equal values at every
/// elevation), the varying (K-1)-lobe model plus a greedy lobe, and constant K-lobe models fitted
/// separately to three slices of elevation, interpolated.

#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/measured/measured_table.hpp>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace brdfbake {

/// Which elevation dependence to fit.
enum class ElevationChoice {
  Auto,      ///< constant, unless varying lowers the fit error by at least FitOptions::autoMargin
  Constant,  ///< LobeElevation::Constant
  Varying,   ///< LobeElevation::Varying
};
/// "auto", "constant", "varying"; parse returns std::nullopt for other names.
std::string_view toString(ElevationChoice choice);
std::optional<ElevationChoice> parseElevationChoice(std::string_view name);

/// The robust loss applied to each residual (ceres::CauchyLoss, ceres::HuberLoss, or none).
enum class RobustLoss { Cauchy, Huber, None };
std::string_view toString(RobustLoss loss);
std::optional<RobustLoss> parseRobustLoss(std::string_view name);

/// Largest lobe count fitLobes accepts.
inline constexpr int kMaxFitLobes = 6;

struct FitOptions {
  /// Lobes per channel, 1..kMaxFitLobes; 0 = auto: the smallest count K such that K + 1 lobes lower
  /// the fit error (FitResult's joint robust RMS) by less than `autoMargin`, trying up to
  /// `maxAutoLobes`.
  int lobes = 0;
  /// Largest count `lobes = 0` tries, 1..kMaxFitLobes.
  int maxAutoLobes = 3;
  ElevationChoice elevation = ElevationChoice::Auto;
  /// `lobes = 0`: one more lobe is kept only if it lowers the error by at least this fraction.
  /// 3 %: on 1 %-noise synthetic tables a third lobe gains under 1 %, while the third lobe that
  /// sharpens garnet red's highlights gains 4 %. In (0, 1).
  double autoMargin = 0.03;
  /// ElevationChoice::Auto: varying lobes (three times the parameters) are kept only if they
  /// lower the error by at least this fraction. 10 %: on 1 %-noise tables from constant lobes,
  /// varying ones gain 1 to 6 % by fitting the noise of the few samples that see a sharp
  /// highlight; the real Cornell tables gain 19 to 37 % (docs/fitting.md). In (0, 1).
  double elevationMargin = 0.10;
  RobustLoss loss = RobustLoss::Cauchy;
  /// Scale of the robust loss as a fraction of the channel's largest cube-root target (residuals
  /// beyond it count less and less). > 0.
  double lossScale = 0.2;
  /// Ceres iterations per solve (each lobe count and start is one solve). >= 1.
  int maxIterations = 100;
  /// Ceres' relative function tolerance. In (0, 1).
  double functionTolerance = 1e-7;
  /// Channels fitted in parallel (0 = every core).
  int threads = 0;
  /// Called with the fraction done (0..1), serialised; may be empty.
  std::function<void(double)> progress;

  /// Throws Error(InvalidArgument) for values outside the documented ranges.
  void validate() const;
};

/// What Ceres said about one solve.
struct SolverReport {
  std::string termination;  ///< "CONVERGENCE", "NO_CONVERGENCE" (iteration limit), "FAILURE", ...
  bool usable = false;      ///< Summary::IsSolutionUsable() and every parameter finite
  int iterations = 0;
  double seconds = 0.0;     ///< Ceres' total time
  double initialCost = 0.0, finalCost = 0.0;
  std::string briefReport;  ///< Summary::BriefReport()
};

/// The sample the fit misses most (largest |cube-root residual|).
struct WorstSample {
  std::size_t index = 0;  ///< row in the fitted table
  SampleAngles angles;
  double measured = 0.0;  ///< 1/sr
  double fitted = 0.0;    ///< 1/sr
};

/// Statistics of the chosen model on one channel, over every sample of the table.
struct ChannelFitStats {
  std::string name;
  std::size_t samples = 0;
  /// RMS of cos theta_i (f_fit - f_measured), 1/sr.
  double rmsCosineWeighted = 0.0;
  /// RMS of ln((cos theta_i f_fit + d) / (cos theta_i max(f_measured, 0) + d)), d = 1e-3 1/sr.
  double logRmse = 0.0;
  /// RMS of the residuals r_i (cube-root units, (1/sr)^(1/3)), before the robust loss.
  double cubeRootRmse = 0.0;
  WorstSample worst;
  SolverReport solver;      ///< the last solve of the chosen model
  int totalIterations = 0;  ///< every solve of this channel (lobe counts, starts, elevations)
  double seconds = 0.0;     ///< wall time spent on this channel
};

/// A model fitLobes tried: lobe count, elevation and the joint error over channels: the RMS of
/// the cube-root residuals r_i of every fitted sample of every channel (no robust loss, so a
/// highlight the loss discounts still counts).
struct ModelCandidate {
  int lobes = 0;
  LobeElevation elevation = LobeElevation::Constant;
  double error = 0.0;
  bool chosen = false;
};

struct FitResult {
  LobeModel model;
  std::vector<ChannelFitStats> channels;
  std::vector<ModelCandidate> candidates;  ///< in the order tried
  FitOptions options;                      ///< as requested (progress dropped)
  double seconds = 0.0;                    ///< wall time of the whole fit

  /// True when every channel's final solve is usable.
  bool usable() const;
  /// Lines like Ceres' BriefReport: model, per channel errors, iterations, termination.
  std::string briefReport() const;
};

/// Fits every channel of `table` (its channels as stored: convert with MeasuredTable::toRgb first
/// for RGB). Throws Error(InvalidInput) if the table does not validate (NaN, bad angles) or has
/// no sample with light and view above the horizon, Error(InvalidArgument) for bad options or an
/// explicit model with more parameters than samples (auto only tries models with at most as many
/// parameters as samples). A solve that does not converge is not an exception: see
/// FitResult::usable() and ChannelFitStats::solver. An all-zero channel fits exactly with k_d = 0
/// and zero lobe weights.
FitResult fitLobes(const MeasuredTable& table, const FitOptions& options = {});

/// Statistics of `model` channel `channel` against table channel `channel` (no solve; solver and
/// timing fields left empty).
ChannelFitStats evaluateFit(const LobeModel& model, const MeasuredTable& table, std::size_t channel);

}  // namespace brdfbake
