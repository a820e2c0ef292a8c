#pragma once
/// @file
/// Fitting radially symmetric lobes (brdf/lobes.hpp) to a measured table. Method, defaults and
/// their reasons: docs/fitting.md.
///
/// Two methods. FitMethod::Shared (the default): every channel shares each lobe's shape (exponent
/// and Lafortune coefficient c_xy, or a half-vector lobe's exponent); the diffuse terms and weights
/// (a half-vector lobe's C and C_F) of each channel are solved by
/// non-negative least squares on the cosine-weighted log error of fit/held_out.hpp, the shapes by
/// a search around them (variable projection). Varying lobes share their elevation profile (the
/// exponent and a gain on the weights at three nodes) between channels, under a prior
/// (FitOptions::varyingPrior). FitMethod::PerChannel: Ceres per channel, as follows.
///
/// Automatic choices (lobe count, lobe kind, elevation, colour profile) are made by the held-out error of
/// fit/held_out.hpp (estimateHeldOutError), never by the in-sample error: every candidate is fitted
/// on each split, and the lowest HeldOutReport::score (the worse of the off-mirror and elevation
/// ratios) is kept, unless a candidate with fewer parameters is within FitOptions::autoMargin of it.
///
/// PerChannel: each channel is fitted on its own. Per sample i (light wi, view wo, measured f_i) the residual
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
/// separately to three slices of elevation, interpolated. Spectral tables: only every 16th
/// wavelength (and the last) is started so; each other one is fitted in one solve from its
/// neighbouring wavelength's fit, weights scaled by the ratio of the two channels' signals.

#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/fit/held_out.hpp>
#include <brdfbake/measured/measured_table.hpp>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace brdfbake {

/// How channels are fitted (see @file).
enum class FitMethod {
  Shared,      ///< lobe shapes shared by every channel, weights by non-negative least squares
  PerChannel,  ///< every channel on its own with Ceres (cube-root residual, robust loss)
};
/// "shared", "per_channel"; parse throws Error(InvalidArgument) listing the accepted names for others
/// (core/named_values.hpp).
std::string_view toString(FitMethod method);
FitMethod parseFitMethod(std::string_view name);

/// Which lobes FitMethod::Shared fits.
enum class LobeKindChoice {
  Auto,        ///< half-vector, mirror, mixed or Lafortune, then a table, by held-out error
  Mirror,      ///< Phong lobes about the mirrored view (c_xy = -1)
  Lafortune,   ///< Lafortune lobes, c_xy free per lobe (brdf/lobes.hpp)
  HalfVector,  ///< half-vector lobes with a Fresnel weight (halfVectorLobe)
  Mixed,       ///< each lobe a half-vector or a mirror lobe, whichever fits better when it is added
  /// No lobes: a half-difference table (brdf/half_difference_table.hpp) fitted by penalised least
  /// squares on ln f (fit/table_fit.hpp). Auto scores it last, against the lobes chosen, and keeps it
  /// only if its held-out score is lower by autoMargin (it has far more parameters).
  HalfDifference,
};
/// "auto", "mirror", "lafortune", "half_vector", "mixed", "half_difference"; parse throws Error(InvalidArgument)
/// listing the accepted names for others (core/named_values.hpp).
std::string_view toString(LobeKindChoice kind);
LobeKindChoice parseLobeKindChoice(std::string_view name);

/// Which elevation dependence to fit.
enum class ElevationChoice {
  Auto,      ///< constant or varying, by held-out error
  Constant,  ///< LobeElevation::Constant
  Varying,   ///< LobeElevation::Varying
};
/// "auto", "constant", "varying"; parse throws Error(InvalidArgument) listing the accepted names for others
/// (core/named_values.hpp).
std::string_view toString(ElevationChoice choice);
ElevationChoice parseElevationChoice(std::string_view name);

/// Whether FitMethod::Shared fits colour profiles (ColorProfile of brdf/lobes.hpp): the chosen
/// shapes are kept and each channel's weights are solved again with every weight column times the
/// four cubic Bernstein polynomials in theta_d / 90 degrees (non-negative least squares as before).
enum class ColorProfileChoice {
  Auto,             ///< tried after the other choices; kept if it improves on them by colorProfileMargin
  None,             ///< ColorProfile::None
  DifferenceAngle,  ///< ColorProfile::DifferenceAngle (FitMethod::Shared only)
};
/// "auto", "none", "difference_angle"; parse throws Error(InvalidArgument) listing the accepted names for others
/// (core/named_values.hpp).
std::string_view toString(ColorProfileChoice choice);
ColorProfileChoice parseColorProfileChoice(std::string_view name);

/// The robust loss applied to each residual (ceres::CauchyLoss, ceres::HuberLoss, or none).
enum class RobustLoss { Cauchy, Huber, None };
std::string_view toString(RobustLoss loss);
RobustLoss parseRobustLoss(std::string_view name);

/// Largest lobe count fitLobes accepts.
inline constexpr int kMaxFitLobes = 6;

struct FitOptions {
  FitMethod method = FitMethod::Shared;
  /// Lobes per channel, 1..kMaxFitLobes; 0 = auto: by held-out error (see @file), trying 1 to
  /// `maxAutoLobes` and stopping when one more lobe does not lower the score by `autoMargin`.
  int lobes = 0;
  /// Largest count `lobes = 0` tries, 1..kMaxFitLobes.
  int maxAutoLobes = 3;
  ElevationChoice elevation = ElevationChoice::Auto;
  /// FitMethod::Shared: mirror, Lafortune, half-vector or mixed lobes, a table, or auto (by held-out
  /// error; the half-difference table is a candidate when `lobes` is 0). HalfDifference: `lobes` 0,
  /// elevation auto or constant, no colour profile (the table's theta_d dependence is its own).
  LobeKindChoice kind = LobeKindChoice::Auto;
  /// FitMethod::Shared: largest lobe exponent, in [1, 1e5]. 1e4 (a lobe 0.7 degrees wide at half
  /// maximum) is as sharp as the Cornell grid's spacing near the mirror can support.
  double maxExponent = 1e4;
  /// FitMethod::Shared with an auto choice: after the lobe count and kind are chosen, the cap is
  /// lowered to 0.3 and then 0.1 times maxExponent while that lowers the held-out score by
  /// autoMargin (a cap is a regularisation weight; the cap kept is FitResult::options.maxExponent).
  bool chooseMaxExponent = true;
  /// FitMethod::Shared, varying lobes: the prior on their shapes. Each unit of squared offset of
  /// ln n or ln C from its value at the most normal view costs this fraction of the constant fit's
  /// error (docs/fitting.md). >= 0. Without it a lone sharp lobe of blue acrylic bent its exponent
  /// from 1e4 to 960 towards grazing and predicted held-out rows at 3.3x Lambert's error.
  double varyingPrior = 0.01;
  /// FitMethod::Shared with an auto choice that chose varying lobes: the prior is also tried at 0.1
  /// times varyingPrior, and kept if that lowers the held-out score by autoMargin.
  bool chooseVaryingPrior = true;
  /// Colour profiles in theta_d (see ColorProfileChoice). Auto tries them only with a held-out
  /// estimate (FitMethod::Shared, enough rows away from the mirror, and estimateHeldOut or another
  /// auto choice); DifferenceAngle needs FitMethod::Shared.
  ColorProfileChoice colorProfile = ColorProfileChoice::Auto;
  /// ColorProfileChoice::Auto: profiles are kept only if they improve on the model without them by this
  /// fraction, in (0, 1), as HeldOutReport::improvesOn says (the score, or the better of the two ratios
  /// at a score no higher). They quadruple each channel's weights, and on a synthetic table without any colour
  /// shift they lowered the score by 2 % (tests/fit/test_color_profile.cpp); on the colour-shifting
  /// Mystique paint by 10 % (docs/fitting.md).
  double colorProfileMargin = 0.05;
  /// FitMethod::Shared with auto choices: score every candidate with its weights refined as the kept
  /// fit's are (Gauss-Newton steps on the log error). By default candidates are ranked with the
  /// weights the shape search ranks shapes by (linearised at the data), and only the chosen candidate
  /// and the best radially symmetric one are scored again, refined (ModelCandidate::refined): on
  /// the Cornell tables 10 to 25 % faster with 31 wavelengths; 4 of issue 26's 28 held-out figures
  /// moved, two down and two up (docs/fitting.md).
  bool refineCandidates = false;
  /// Auto choices with `kind` Auto and `lobes` 0 (FitMethod::Shared; an explicit kind asks for those
  /// lobes): after the lobes are chosen, also score a half-difference table (LobeKindChoice::HalfDifference),
  /// kept only if its held-out score is below (1 - autoMargin) times theirs (it has far more parameters).
  bool halfDifference = true;
  /// Auto choices: a candidate with more parameters is kept only if its held-out score is below
  /// (1 - autoMargin) times the best score of the candidates with fewer parameters. In (0, 1).
  double autoMargin = 0.01;
  /// Splits of the held-out estimate (auto choices and the report).
  HeldOutOptions heldOut;
  /// Estimate the held-out error of the chosen model (FitResult::heldOut) even when nothing is
  /// chosen automatically (auto choices always estimate it).
  bool estimateHeldOut = true;
  /// PerChannel, in-sample: no longer used for choices (kept for fit.json compatibility).
  double elevationMargin = 0.10;
  RobustLoss loss = RobustLoss::Cauchy;
  /// Scale of the robust loss as a fraction of the channel's largest cube-root target (residuals
  /// beyond it count less and less). > 0.
  double lossScale = 0.2;
  /// Ceres iterations per solve (each lobe count and start is one solve). >= 1.
  int maxIterations = 100;
  /// Ceres' relative function tolerance. In (0, 1).
  double functionTolerance = 1e-7;

  /// Throws Error(InvalidArgument) for values outside the documented ranges.
  void validate() const;
};

/// What Ceres said about one solve.
struct SolverReport {
  std::string termination;  ///< "CONVERGENCE", "NO_CONVERGENCE" (iteration limit), "FAILURE", ...
  bool usable = false;      ///< Summary::IsSolutionUsable() and every parameter finite
  int iterations = 0;
  double seconds = 0.0;  ///< Ceres' total time
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

/// A model fitLobes tried (auto choices), with its held-out estimate.
struct ModelCandidate {
  int lobes = 0;
  LobeElevation elevation = LobeElevation::Constant;
  LobeKindChoice kind = LobeKindChoice::Mirror;  ///< Mirror, Lafortune, HalfVector, Mixed or HalfDifference (lobes 0)
  int parameters = 0;                            ///< free parameters of the model, all channels
  double inSampleError = 0.0;   ///< E of fit/held_out.hpp on every row of the table, fitted on all of them
  double heldOutScore = 0.0;    ///< HeldOutReport::score
  double kfoldRatio = 0.0;      ///< off-mirror k-fold error / Lambert
  double elevationRatio = 0.0;  ///< pooled leave-one-elevation-out error / Lambert
  double seconds = 0.0;         ///< wall time of the held-out estimate (every split's fit)
  double maxExponent = 0.0;     ///< the exponent cap of the shared method (0: not recorded)
  double varyingPrior = 0.0;    ///< the prior on varying shapes of the shared method (0: not recorded)
  ColorProfile colorProfile = ColorProfile::None;
  /// The scores are of split fits whose weights are refined as the kept fit's are (Gauss-Newton
  /// steps on the log error). The shared method ranks candidates with the weights its shape search
  /// uses (linearised at the data, refined = false) and scores the chosen candidate and the best
  /// radially symmetric one again, refined (docs/fitting.md).
  bool refined = true;
  bool chosen = false;

  /// Mirror lobes: radially symmetric about the mirrored view, so they prefilter an environment
  /// (constant: in one pass; varying or colour-profiled: into a stack over elevation, a profile taken
  /// at the lobes' centre, docs/prefilter.md).
  bool radiallySymmetric() const { return kind == LobeKindChoice::Mirror; }
  /// A held-out ratio at or above 1: no better than a Lambertian fit on that measure. Such a
  /// candidate is never chosen while another is not.
  bool worseThanLambert() const { return kfoldRatio >= 1.0 || elevationRatio >= 1.0; }
};

struct FitResult {
  LobeModel model;
  std::vector<ChannelFitStats> channels;
  std::vector<ModelCandidate> candidates;  ///< in the order tried (auto choices only)
  /// Held-out estimate of the chosen model (when FitOptions::estimateHeldOut or a choice was auto).
  std::optional<HeldOutReport> heldOut;
  /// E of fit/held_out.hpp over every row of the table (in-sample).
  double inSampleError = 0.0;
  FitOptions options;    ///< as requested
  double seconds = 0.0;  ///< wall time of the whole fit

  /// True when every channel's final solve is usable.
  bool usable() const;
  /// The radially symmetric candidate of lowest held-out score, refined ones first (nullptr when
  /// none was tried).
  const ModelCandidate* bestRadiallySymmetric() const;
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
FitResult fitLobes(const MeasuredTable& table, const FitOptions& options = {}, const Context& context = {});

/// Statistics of `model` channel `channel` against table channel `channel` (no solve; solver and
/// timing fields left empty).
ChannelFitStats evaluateFit(const LobeModel& model, const MeasuredTable& table, std::size_t channel);

}  // namespace brdfbake
