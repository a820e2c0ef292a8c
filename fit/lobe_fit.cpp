#include <brdfbake/core/context.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/named_values.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/fit/lobe_fit.hpp>

#include "per_channel_fit.hpp"
#include "shared_lobe_fit.hpp"
#include "table_fit.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <memory>
#include <numeric>
#include <optional>
#include <sstream>

namespace brdfbake {

std::string_view toString(ElevationChoice choice) {
  switch (choice) {
    case ElevationChoice::Auto:
      return "auto";
    case ElevationChoice::Constant:
      return "constant";
    case ElevationChoice::Varying:
      return "varying";
  }
  return "auto";
}

ElevationChoice parseElevationChoice(std::string_view name) {
  return parseByName(name, std::array{ElevationChoice::Auto, ElevationChoice::Constant, ElevationChoice::Varying},
                     "elevation");
}

std::string_view toString(ColorProfileChoice choice) {
  switch (choice) {
    case ColorProfileChoice::Auto:
      return "auto";
    case ColorProfileChoice::None:
      return "none";
    case ColorProfileChoice::DifferenceAngle:
      return "difference_angle";
  }
  return "auto";
}

ColorProfileChoice parseColorProfileChoice(std::string_view name) {
  return parseByName(
      name, std::array{ColorProfileChoice::Auto, ColorProfileChoice::None, ColorProfileChoice::DifferenceAngle},
      "colour profile");
}

std::string_view toString(RobustLoss loss) {
  switch (loss) {
    case RobustLoss::Cauchy:
      return "cauchy";
    case RobustLoss::Huber:
      return "huber";
    case RobustLoss::None:
      return "none";
  }
  return "cauchy";
}

RobustLoss parseRobustLoss(std::string_view name) {
  return parseByName(name, std::array{RobustLoss::Cauchy, RobustLoss::Huber, RobustLoss::None}, "loss");
}

void FitOptions::validate() const {
  require(lobes >= 0 && lobes <= kMaxFitLobes, "fit: lobes must be 0 (auto) or 1.." + std::to_string(kMaxFitLobes));
  require(maxAutoLobes >= 1 && maxAutoLobes <= kMaxFitLobes,
          "fit: maxAutoLobes must be in 1.." + std::to_string(kMaxFitLobes));
  require(std::isfinite(autoMargin) && autoMargin > 0.0 && autoMargin < 1.0, "fit: autoMargin must be in (0, 1)");
  require(std::isfinite(elevationMargin) && elevationMargin > 0.0 && elevationMargin < 1.0,
          "fit: elevationMargin must be in (0, 1)");
  require(std::isfinite(lossScale) && lossScale > 0.0, "fit: lossScale must be > 0");
  require(maxIterations >= 1, "fit: maxIterations must be >= 1");
  require(std::isfinite(functionTolerance) && functionTolerance > 0.0 && functionTolerance < 1.0,
          "fit: functionTolerance must be in (0, 1)");
  require(std::isfinite(maxExponent) && maxExponent >= kMinLobeExponent && maxExponent <= kMaxLobeExponent,
          "fit: maxExponent must be in [1, 1e5]");
  require(std::isfinite(varyingPrior) && varyingPrior >= 0.0, "fit: varyingPrior must be finite and >= 0");
  require(std::isfinite(colorProfileMargin) && colorProfileMargin > 0.0 && colorProfileMargin < 1.0,
          "fit: colorProfileMargin must be in (0, 1)");
  require(method == FitMethod::Shared || colorProfile != ColorProfileChoice::DifferenceAngle,
          "fit: colour profiles are fitted by the shared method only");
  if (kind == LobeKindChoice::HalfDifference) {
    require(method == FitMethod::Shared, "fit: a half-difference table is fitted by the shared method only");
    require(lobes == 0, "fit: a half-difference table has no lobes (lobes must be auto)");
    require(elevation != ElevationChoice::Varying && colorProfile != ColorProfileChoice::DifferenceAngle,
            "fit: a half-difference table has neither varying lobes nor colour profiles (its theta_d dependence is "
            "its own)");
  }
  heldOut.validate();
}

bool FitResult::usable() const {
  return !channels.empty() &&
         std::all_of(channels.begin(), channels.end(), [](const ChannelFitStats& c) { return c.solver.usable; });
}

const ModelCandidate* FitResult::bestRadiallySymmetric() const {
  // Refined scores first: a ranking score is of other weights than a refined one.
  const auto better = [](const ModelCandidate& a, const ModelCandidate& b) {
    return a.refined != b.refined ? a.refined : a.heldOutScore < b.heldOutScore;
  };
  const ModelCandidate* best = nullptr;
  for (const auto& c : candidates) {
    if (c.radiallySymmetric() && (!best || better(c, *best))) best = &c;
  }
  return best;
}

std::string FitResult::briefReport() const {
  std::ostringstream out;
  std::size_t lobes = model.channels.empty() ? 0 : model.channels[0].lobes.size();
  if (model.hasHalfDifference())
    out << "Fit: a half-difference table, ";
  else
    out << "Lobe fit: " << lobes << " lobe(s), " << toString(model.elevation) << " elevation, ";
  out << (model.colorProfile == ColorProfile::None ? "" : "colour profile in theta_d, ") << channels.size()
      << " channel(s), " << std::fixed << std::setprecision(2) << seconds << " s, "
      << (usable() ? "usable" : "NOT usable") << "\n";
  for (const auto& c : channels) {
    out << "  " << std::left << std::setw(6) << c.name << std::right << std::setprecision(4) << " rms(cos f) "
        << c.rmsCosineWeighted << " 1/sr, log-rmse " << c.logRmse << ", cbrt-rmse " << c.cubeRootRmse << ", "
        << c.solver.iterations << " it (" << c.totalIterations << " total), " << std::setprecision(3) << c.seconds
        << " s, " << c.solver.termination << "\n";
  }
  return out.str();
}

ChannelFitStats evaluateFit(const LobeModel& model, const MeasuredTable& table, std::size_t channel) {
  require(channel < model.channelCount() && channel < table.channelCount(),
          "evaluateFit: no channel " + std::to_string(channel));
  ChannelFitStats stats;
  stats.name = model.channels[channel].name;
  stats.samples = table.size();
  double maxWeighted = 0.0;
  for (std::size_t i = 0; i < table.size(); ++i) {
    const double cosIn = std::max(table.incidentDirection(i).z(), 0.0);
    maxWeighted = std::max(
        maxWeighted, std::abs(cosIn * table.values(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(channel))));
  }
  const double eps = std::max(1e-6 * maxWeighted, 1e-12);
  constexpr double kLogFloor = 1e-3;
  double sumSquared = 0.0, sumLog = 0.0, sumCbrt = 0.0, worst = -1.0;
  for (std::size_t i = 0; i < table.size(); ++i) {
    const Vec3 wi = table.incidentDirection(i), wo = table.outgoingDirection(i);
    const double cosIn = std::max(wi.z(), 0.0);
    const double measured = table.values(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(channel));
    const double fitted = model.evaluate(channel, wi, wo);
    const double d = cosIn * (fitted - measured);
    const double l = std::log((cosIn * fitted + kLogFloor) / (cosIn * std::max(measured, 0.0) + kLogFloor));
    const double r = std::cbrt(cosIn * fitted + eps) - std::cbrt(cosIn * measured + eps);
    sumSquared += d * d;
    sumLog += l * l;
    sumCbrt += r * r;
    if (std::abs(r) > worst) {
      worst = std::abs(r);
      stats.worst = {i, table.angles[i], measured, fitted};
    }
  }
  const double n = std::max<double>(1.0, static_cast<double>(table.size()));
  stats.rmsCosineWeighted = std::sqrt(sumSquared / n);
  stats.logRmse = std::sqrt(sumLog / n);
  stats.cubeRootRmse = std::sqrt(sumCbrt / n);
  return stats;
}

namespace {

using Clock = std::chrono::steady_clock;

// The shared-shape model of `table` (no statistics). `warmStart`: a fit of the same table with
// fewer lobes of this kind, whose shapes the fit keeps.
struct SharedModel {
  LobeModel model;
  int evaluations = 0;
};

SharedModel sharedModel(const MeasuredTable& table, const FitOptions& options, LobeKindChoice kind,
                        const LobeModel* warmStart, std::shared_ptr<detail::ShapeSearches> searches = nullptr,
                        int gaussNewtonSteps = detail::kGaussNewtonSteps) {
  const std::string label = table.label();
  if (table.channelCount() == 0) throw Error(Error::Kind::InvalidInput, label + ": no channels to fit");
  if (kind == LobeKindChoice::HalfDifference) return {detail::fitHalfDifferenceTable(table), 0};
  detail::SharedFitConfig config;
  config.lobes = options.lobes;
  config.mirror = kind == LobeKindChoice::Mirror || kind == LobeKindChoice::Mixed;
  config.lafortune = kind == LobeKindChoice::Lafortune;
  config.halfVector = kind == LobeKindChoice::HalfVector || kind == LobeKindChoice::Mixed;
  config.varying = options.elevation == ElevationChoice::Varying;
  config.maxExponent = options.maxExponent;
  config.varyingPrior = options.varyingPrior;
  config.colorProfile = options.colorProfile == ColorProfileChoice::DifferenceAngle;
  if (warmStart && !warmStart->channels.empty()) config.startLobes = warmStart->channels[0].lobes;
  config.searches = std::move(searches);
  config.gaussNewtonSteps = gaussNewtonSteps;
  const std::size_t usable = detail::usableRows(table);
  if (usable == 0) {
    throw Error(Error::Kind::InvalidInput, label + ": no sample has both directions above the horizon; nothing to fit");
  }
  const std::size_t perChannel =
      (1 + static_cast<std::size_t>(options.lobes) *
               (kind == LobeKindChoice::HalfVector || kind == LobeKindChoice::Mixed ? 2 : 1)) *
      (config.colorProfile ? kColorProfileCount : 1);
  if (usable < perChannel) {
    throw Error(Error::Kind::InvalidArgument, label + ": " + std::to_string(usable) +
                                                  " usable sample(s) cannot determine " + std::to_string(perChannel) +
                                                  " weights per channel");
  }
  auto outcome = detail::fitSharedLobes(table, config, detail::fittedRange(table));
  for (std::size_t c = 0; c < table.channelCount(); ++c) {
    outcome.model.channels[c].name = table.channelName(c);
  }
  outcome.model.validate();
  return {std::move(outcome.model), outcome.evaluations};
}

FitResult fitShared(const MeasuredTable& table, const FitOptions& options, LobeKindChoice kind,
                    const LobeModel* warmStart = nullptr) {
  const auto start = Clock::now();
  SharedModel fitted = sharedModel(table, options, kind, warmStart);
  FitResult result;
  result.options = options;
  result.model = std::move(fitted.model);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  for (std::size_t c = 0; c < table.channelCount(); ++c) {
    ChannelFitStats stats = evaluateFit(result.model, table, c);
    stats.solver.termination = "CONVERGENCE";
    stats.solver.usable = true;
    stats.solver.iterations = fitted.evaluations;
    stats.solver.briefReport =
        kind == LobeKindChoice::HalfDifference
            ? "half-difference table: penalised least squares on ln f"
            : "shared shapes: " + std::to_string(fitted.evaluations) + " shape trials, NNLS weights";
    stats.totalIterations = fitted.evaluations;
    stats.seconds = seconds;
    result.channels.push_back(std::move(stats));
  }
  result.seconds = seconds;
  return result;
}

// One explicit candidate: the options with lobes, elevation and kind fixed.
struct CandidateConfig {
  int lobes = 1;
  LobeElevation elevation = LobeElevation::Constant;
  LobeKindChoice kind = LobeKindChoice::Mirror;  // Mirror, Lafortune or HalfVector
  double maxExponent = 0.0;                      // the shared method's cap; 0 = the options'
  double varyingPrior = -1.0;                    // the shared method's prior; < 0 = the options'
  ColorProfile colorProfile = ColorProfile::None;
};

// The options with the candidate's choices made explicit.
FitOptions explicitOptions(FitOptions options, const CandidateConfig& config) {
  options.lobes = config.lobes;
  options.elevation =
      config.elevation == LobeElevation::Constant ? ElevationChoice::Constant : ElevationChoice::Varying;
  options.kind = config.kind;
  if (config.maxExponent > 0.0) options.maxExponent = config.maxExponent;
  if (config.varyingPrior >= 0.0) options.varyingPrior = config.varyingPrior;
  options.colorProfile = config.colorProfile == ColorProfile::DifferenceAngle ? ColorProfileChoice::DifferenceAngle
                                                                              : ColorProfileChoice::None;
  return options;
}

// One of many fits that run in parallel over splits: one thread, no progress of its own.
Context candidateContext(const Context& context) { return context.withThreads(1).withoutProgress(); }

FitResult fitExplicit(const MeasuredTable& table, const FitOptions& explicitOptions, LobeKindChoice kind,
                      const Context& context) {
  if (explicitOptions.method == FitMethod::Shared) return fitShared(table, explicitOptions, kind);
  return detail::fitPerChannel(table, explicitOptions, context);
}

FitResult fitCandidate(const MeasuredTable& table, const FitOptions& options, const CandidateConfig& config,
                       const Context& context) {
  return fitExplicit(table, explicitOptions(options, config), config.kind, candidateContext(context));
}

// The model alone, for a held-out split (the statistics of a split's fit are never shown).
LobeModel fitCandidateModel(const MeasuredTable& table, const FitOptions& options, const CandidateConfig& config,
                            const Context& context, const LobeModel* start = nullptr,
                            std::shared_ptr<detail::ShapeSearches> searches = nullptr,
                            int gaussNewtonSteps = detail::kGaussNewtonSteps) {
  const FitOptions single = explicitOptions(options, config);
  if (options.method == FitMethod::Shared)
    return sharedModel(table, single, config.kind, start, std::move(searches), gaussNewtonSteps).model;
  return detail::fitPerChannel(table, single, candidateContext(context)).model;
}

int parameterTotal(const CandidateConfig& config, FitMethod method, std::size_t channels) {
  if (config.kind == LobeKindChoice::HalfDifference)
    return detail::kFittedTableShape.coefficientCount() * static_cast<int>(channels);
  const int count = elevationCoefficientCount(config.elevation);
  const int perChannel = 1 + config.lobes * (method == FitMethod::Shared ? 1 : 2 * count);
  // Shared: a Lafortune lobe's n and c_xy, a half-vector lobe's n (and one more weight per channel, C_F);
  // a varying lobe's n and gain at two more nodes.
  const int shapeParameters =
      (config.kind == LobeKindChoice::Lafortune ? 2 : 1) + (config.elevation == LobeElevation::Varying ? 4 : 0);
  const bool fresnelWeights = config.kind == LobeKindChoice::HalfVector || config.kind == LobeKindChoice::Mixed;
  const int extraWeights = fresnelWeights ? config.lobes * static_cast<int>(channels) : 0;
  const int shared = method == FitMethod::Shared ? config.lobes * shapeParameters + extraWeights : 0;
  // A colour profile turns each weight into kColorProfileCount coefficients.
  const int weights = (1 + config.lobes) * static_cast<int>(channels) + extraWeights;
  const int profile = config.colorProfile == ColorProfile::None ? 0 : (kColorProfileCount - 1) * weights;
  return perChannel * static_cast<int>(channels) + shared + profile;
}

// A kind whose score is more than this factor above the best score so far stops adding lobes:
// a mixed sequence on the Cayman table scored 0.87 with two lobes and 0.23 with three (docs/fitting.md).
constexpr double kHopelessScoreFactor = 3.0;

// The Gauss-Newton steps of the split fits that rank the shared method's candidates: none, the
// weights the shape search ranks shapes by (scoreRefined scores the chosen one again with the kept
// fit's, detail::kGaussNewtonSteps). On the seven Cornell tables it changed 4 of the 28 held-out
// figures of issue 26 (two up, two down) and took 65 to 90 % of the time (docs/fitting.md).
constexpr int kRankingGaussNewtonSteps = 0;

LogErrorSum allRowsError(const LobeModel& model, const MeasuredTable& table) {
  std::vector<std::size_t> rows(table.size());
  std::iota(rows.begin(), rows.end(), std::size_t(0));
  return cosineLogError(model, table, rows);
}

}  // namespace

std::string_view toString(FitMethod method) { return method == FitMethod::Shared ? "shared" : "per_channel"; }

FitMethod parseFitMethod(std::string_view name) {
  return parseByName(name, std::array{FitMethod::Shared, FitMethod::PerChannel}, "method");
}

std::string_view toString(LobeKindChoice kind) {
  switch (kind) {
    case LobeKindChoice::Auto:
      return "auto";
    case LobeKindChoice::Mirror:
      return "mirror";
    case LobeKindChoice::Lafortune:
      return "lafortune";
    case LobeKindChoice::HalfVector:
      return "half_vector";
    case LobeKindChoice::Mixed:
      return "mixed";
    case LobeKindChoice::HalfDifference:
      return "half_difference";
  }
  return "auto";
}

LobeKindChoice parseLobeKindChoice(std::string_view name) {
  return parseByName(name,
                     std::array{LobeKindChoice::Auto, LobeKindChoice::Mirror, LobeKindChoice::Lafortune,
                                LobeKindChoice::HalfVector, LobeKindChoice::Mixed, LobeKindChoice::HalfDifference},
                     "lobe kind");
}

namespace {

// The candidates fitLobes may choose between: explicit choices fix a dimension, auto ones span it.
struct CandidateSpace {
  std::vector<int> counts;
  std::vector<LobeKindChoice> kinds;
  std::vector<LobeElevation> elevations;
  ColorProfile colorProfile = ColorProfile::None;  // of every candidate scored first
  bool tryColorProfile = false;                    // then the chosen one with a colour profile
  bool heldOutFeasible = false;                    // enough rows away from the mirror for held-out splits
  bool tryTable = false;                           // last, a half-difference table against the chosen lobes

  // The elevations tried for `kind`: an automatic choice of kind and elevation tries Lafortune lobes
  // constant only (varying ones never won on the Cornell tables and cost a c_xy search, docs/fitting.md).
  std::vector<LobeElevation> elevationsFor(LobeKindChoice kind) const {
    if (kind == LobeKindChoice::Lafortune && kinds.size() > 1 && elevations.size() > 1)
      return {LobeElevation::Constant};
    return elevations;
  }
  std::size_t size() const {
    std::size_t total = 0;
    for (LobeKindChoice kind : kinds) total += counts.size() * elevationsFor(kind).size();
    return total;
  }
};

CandidateSpace candidateSpace(const MeasuredTable& table, const FitOptions& options) {
  const bool shared = options.method == FitMethod::Shared;
  CandidateSpace space;
  if (options.kind == LobeKindChoice::HalfDifference)
    space.counts = {0};
  else if (options.lobes > 0)
    space.counts = {options.lobes};
  else
    for (int k = 1; k <= options.maxAutoLobes; ++k) space.counts.push_back(k);
  if (!shared)
    space.kinds = {LobeKindChoice::Mirror};
  else if (options.kind != LobeKindChoice::Auto)
    space.kinds = {options.kind};
  else
    space.kinds = {LobeKindChoice::HalfVector, LobeKindChoice::Mirror, LobeKindChoice::Mixed,
                   LobeKindChoice::Lafortune};  // likeliest first
  if (options.elevation == ElevationChoice::Constant || options.kind == LobeKindChoice::HalfDifference)
    space.elevations = {LobeElevation::Constant};
  else if (options.elevation == ElevationChoice::Varying)
    space.elevations = {LobeElevation::Varying};
  else
    space.elevations = {LobeElevation::Constant, LobeElevation::Varying};
  // Held-out splits need enough rows away from the mirror (two per fold); without them an auto
  // choice takes the fewest parameters and no estimate is made.
  std::size_t offMirror = 0;
  for (std::size_t i = 0; i < table.size(); ++i)
    offMirror += mirrorOffsetDegrees(table, i) > options.heldOut.minMirrorOffsetDegrees;
  space.heldOutFeasible = offMirror >= 2 * static_cast<std::size_t>(options.heldOut.folds);
  if (options.colorProfile == ColorProfileChoice::DifferenceAngle) space.colorProfile = ColorProfile::DifferenceAngle;
  // With every other choice explicit and no held-out estimate asked for, auto means none.
  space.tryColorProfile = shared && options.colorProfile == ColorProfileChoice::Auto && space.heldOutFeasible &&
                          options.kind != LobeKindChoice::HalfDifference &&
                          (options.estimateHeldOut || space.size() > 1);
  // An explicit kind asks for those lobes (--kind mirror: radially symmetric ones, to prefilter).
  space.tryTable = options.halfDifference && space.heldOutFeasible && options.kind == LobeKindChoice::Auto && shared &&
                   options.lobes == 0 && options.elevation != ElevationChoice::Varying &&
                   options.colorProfile != ColorProfileChoice::DifferenceAngle;
  if (!space.heldOutFeasible) {
    space.counts.resize(1);
    if (space.kinds.size() > 1) space.kinds = {LobeKindChoice::Mirror};  // the fewest parameters
    space.elevations.resize(1);
  }
  return space;
}

// One configuration, every choice made (auto ones without a held-out estimate: the fewest
// parameters), with its held-out estimate when asked for and feasible.
FitResult fitOneConfiguration(const MeasuredTable& table, const FitOptions& options, const CandidateSpace& space,
                              const Context& context) {
  const CandidateConfig config{space.counts[0], space.elevations[0], space.kinds[0], 0.0, -1.0, space.colorProfile};
  const bool heldOut = options.estimateHeldOut && space.heldOutFeasible;
  FitResult result =
      fitExplicit(table, explicitOptions(options, config), config.kind, heldOut ? context.part(0.0, 0.5) : context);
  if (heldOut) {
    result.heldOut = estimateHeldOutError(
        table, [&](const MeasuredTable& training) { return fitCandidateModel(training, options, config, context); },
        options.heldOut, context);
  }
  return result;
}

// A scored candidate: its configuration, held-out report and the fit of each split.
struct TriedCandidate {
  CandidateConfig config;
  HeldOutReport report;
  std::vector<LobeModel> splitFits;
  std::vector<LobeModel> starts;  // each split's warm start (empty: none)
  bool refined = false;           // the splits' weights refined as the kept fit's (SplitFitter::refineFromNowOn)
};
using Tried = std::vector<TriedCandidate>;

// The fits of candidates on the held-out splits. What one candidate's fits of a split found is kept
// for the next ones: the shared method's compass searches (detail::ShapeSearches: mixed lobes repeat
// the half-vector and mirror candidates' searches), the per-channel method's fits
// (detail::PerChannelFits: a K-lobe candidate grows from the (K - 1)-lobe one's fits instead of
// fitting 1 .. K - 1 again).
class SplitFitter {
 public:
  SplitFitter(const HeldOutSplits& splits, const FitOptions& options, const Context& context)
      : splits_(splits), options_(options), context_(context), searches_(splits.size()), perChannel_(splits.size()) {
    for (auto& searches : searches_) searches = detail::makeShapeSearches();
  }

  const FitOptions& options() const { return options_; }
  const Context& context() const { return context_; }

  // Scores `config` on every split; split s's fit starts from starts[s] when given (shared method).
  TriedCandidate score(const CandidateConfig& config, const std::vector<LobeModel>* starts = nullptr) {
    TriedCandidate candidate{config, {}, std::vector<LobeModel>(splits_.size()), {}, refined_};
    if (starts) candidate.starts = *starts;
    candidate.report = splits_.estimate([&](std::size_t s, const MeasuredTable& training) {
      candidate.splitFits[s] = fit(s, training, config, starts ? &(*starts)[s] : nullptr);
      return candidate.splitFits[s];
    });
    return candidate;
  }

  // From here on, split fits refine their weights as the kept fit does. Before, the shared method's
  // split fits keep the weights its shape search ranks shapes by (kRankingGaussNewtonSteps) unless
  // FitOptions::refineCandidates; the per-channel method's are refined from the start.
  void refineFromNowOn() { refined_ = true; }

 private:
  LobeModel fit(std::size_t s, const MeasuredTable& training, const CandidateConfig& config, const LobeModel* start) {
    if (options_.method == FitMethod::Shared) {
      return fitCandidateModel(training, options_, config, context_, start, searches_[s],
                               refined_ ? detail::kGaussNewtonSteps : kRankingGaussNewtonSteps);
    }
    auto& fits = perChannel_[s];  // each split is fitted by one task at a time
    if (!fits) {
      fits = std::make_unique<detail::PerChannelFits>(training, explicitOptions(options_, config),
                                                      candidateContext(context_));
    }
    return fits->model(config.lobes, config.elevation);
  }

  const HeldOutSplits& splits_;
  const FitOptions& options_;
  const Context& context_;
  std::vector<std::shared_ptr<detail::ShapeSearches>> searches_;
  std::vector<std::unique_ptr<detail::PerChannelFits>> perChannel_;
  bool refined_ = options_.method != FitMethod::Shared || options_.refineCandidates;
};

// Per kind, the lobe count grows; at each count the constant candidate is scored, then the varying
// one starting from it (each split's varying fit refines that split's constant fit). A sequence (kind,
// elevation) stops when one more lobe does not lower its score by the margin, or, from two lobes on,
// when its score is more than kHopelessScoreFactor times the best so far. Each split's constant
// K-lobe fit starts from its (K-1)-lobe fit.
Tried scoreCandidates(SplitFitter& fitter, const CandidateSpace& space) {
  const FitOptions& options = fitter.options();
  Tried tried;
  const std::size_t total = space.size();
  std::size_t done = 0;
  double bestScore = HUGE_VAL;
  for (LobeKindChoice kind : space.kinds) {
    struct Sequence {
      LobeElevation elevation;
      bool going = true;
      double previous = HUGE_VAL;
      std::vector<LobeModel> fits;  // the split fits of the last count scored
    };
    std::vector<Sequence> sequences;
    for (LobeElevation elevation : space.elevationsFor(kind))
      sequences.push_back(Sequence{elevation, true, HUGE_VAL, {}});
    // One mixed lobe is a half-vector or a mirror lobe, both scored already when their kinds are.
    const bool mixedAfterBoth = kind == LobeKindChoice::Mixed &&
                                std::count(space.kinds.begin(), space.kinds.end(), LobeKindChoice::HalfVector) &&
                                std::count(space.kinds.begin(), space.kinds.end(), LobeKindChoice::Mirror);
    for (int lobes : space.counts) {
      if (mixedAfterBoth && lobes == 1 && space.counts.size() > 1) continue;
      const std::vector<LobeModel>* constantFits = nullptr;
      for (Sequence& sequence : sequences) {
        if (!sequence.going) continue;
        const bool varying = sequence.elevation == LobeElevation::Varying;
        const std::vector<LobeModel>* starts = varying && constantFits ? constantFits
                                               : sequence.fits.empty() ? nullptr
                                                                       : &sequence.fits;
        tried.push_back(fitter.score({lobes, sequence.elevation, kind, 0.0, -1.0, space.colorProfile}, starts));
        sequence.fits = tried.back().splitFits;
        if (!varying) constantFits = &sequence.fits;
        const double score = tried.back().report.score();
        fitter.context().report(static_cast<double>(++done) / static_cast<double>(total + 1));
        bestScore = std::min(bestScore, score);
        if ((lobes > 1 && score > kHopelessScoreFactor * bestScore) ||
            !(score < (1.0 - options.autoMargin) * sequence.previous))
          sequence.going = false;
        sequence.previous = score;
      }
    }
  }
  return tried;
}

// The fewest parameters whose score is within the margin of every candidate with fewer.
std::size_t fewestParametersWithinMargin(const Tried& tried, const FitOptions& options, std::size_t channels) {
  std::vector<std::size_t> order(tried.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return parameterTotal(tried[a].config, options.method, channels) <
           parameterTotal(tried[b].config, options.method, channels);
  });
  std::size_t best = order.front();
  for (std::size_t i : order) {
    if (tried[i].report.score() < (1.0 - options.autoMargin) * tried[best].report.score()) best = i;
  }
  return best;
}

// The shared method's exponent cap, lowered from the chosen candidate's while that lowers the
// score by the margin (same parameters); returns the index of the candidate kept. Capped fits start
// cold: starting from the uncapped fit, clamped, was cheaper but kept its arrangement of lobes and
// scored worse (garnet red RGB 0.093 against 0.087, docs/fitting.md).
std::size_t lowerExponentCap(SplitFitter& fitter, Tried& tried, std::size_t best) {
  const FitOptions& options = fitter.options();
  if (options.method != FitMethod::Shared || !options.chooseMaxExponent) return best;
  for (double factor : {0.3, 0.1}) {
    CandidateConfig capped = tried[best].config;
    capped.maxExponent = std::max(kMinLobeExponent, factor * options.maxExponent);
    tried.push_back(fitter.score(capped));
    if (!(tried.back().report.score() < (1.0 - options.autoMargin) * tried[best].report.score())) break;
    best = tried.size() - 1;
  }
  return best;
}

// The prior on varying shapes, a regularisation weight like the cap: for a varying choice of the
// shared method, 0.1 times the options' prior is scored too and kept if it lowers the score by the
// margin. A table whose lobes truly vary a lot (tests: a synthetic lobe four times wider at grazing)
// needs the weaker prior to be fitted to its noise; blue acrylic's single highlight samples need the
// stronger one.
std::size_t weakenVaryingPrior(SplitFitter& fitter, Tried& tried, std::size_t best) {
  const FitOptions& options = fitter.options();
  if (options.method != FitMethod::Shared || !options.chooseVaryingPrior ||
      tried[best].config.elevation != LobeElevation::Varying || options.varyingPrior == 0.0)
    return best;
  CandidateConfig weaker = tried[best].config;
  weaker.varyingPrior = 0.1 * options.varyingPrior;
  tried.push_back(fitter.score(weaker));
  return tried.back().report.score() < (1.0 - options.autoMargin) * tried[best].report.score() ? tried.size() - 1
                                                                                               : best;
}

// Colour profiles (ColorProfileChoice::Auto): the chosen candidate with them is scored too, and kept if
// it improves on it by FitOptions::colorProfileMargin (HeldOutReport::improvesOn: the score, or the better
// of the two ratios at a score no higher). Its splits' shapes are the chosen candidate's, whose searches the splits
// keep (detail::ShapeSearches), so it costs the weights' solves.
std::size_t addColorProfile(SplitFitter& fitter, Tried& tried, std::size_t best, const CandidateSpace& space) {
  const FitOptions& options = fitter.options();
  if (!space.tryColorProfile) return best;
  CandidateConfig profiled = tried[best].config;
  profiled.colorProfile = ColorProfile::DifferenceAngle;
  tried.push_back(fitter.score(profiled));
  return tried.back().report.improvesOn(tried[best].report, options.colorProfileMargin) ? tried.size() - 1 : best;
}

// The chosen candidate and the best radially symmetric one (FitResult::bestRadiallySymmetric) scored
// again with their splits' weights refined as the kept fit's, so the held-out errors reported for them
// are those of the fits they stand for. Their fits start as they did and reuse the splits' searches.
void scoreRefined(SplitFitter& fitter, Tried& tried, std::size_t best) {
  fitter.refineFromNowOn();
  std::optional<std::size_t> radial;
  for (std::size_t i = 0; i < tried.size(); ++i) {
    if (tried[i].config.kind != LobeKindChoice::Mirror) continue;
    if (!radial || tried[i].report.score() < tried[*radial].report.score()) radial = i;
  }
  for (std::size_t i = 0; i < tried.size(); ++i) {
    if (tried[i].refined || (i != best && i != radial)) continue;
    const double ranking = tried[i].report.seconds;
    tried[i] = fitter.score(tried[i].config, tried[i].starts.empty() ? nullptr : &tried[i].starts);
    tried[i].report.seconds += ranking;
  }
}

// The half-difference table (FitOptions::halfDifference, CandidateSpace::tryTable), scored after the lobes are
// chosen and refined, kept if its score is below (1 - autoMargin) times theirs, as any candidate with
// more parameters: it has far more than the lobes, and on tables the lobes follow it loses
// (docs/fitting.md).
std::size_t addTable(SplitFitter& fitter, Tried& tried, std::size_t best, const CandidateSpace& space,
                     const HeldOutSplits& splits) {
  if (!space.tryTable) return best;
  for (std::size_t s = 0; s < splits.size(); ++s)  // a small table: too few rows for the table's coefficients
    if (!detail::canFitHalfDifferenceTable(splits.training(s))) return best;
  tried.push_back(
      fitter.score({0, LobeElevation::Constant, LobeKindChoice::HalfDifference, 0.0, -1.0, ColorProfile::None}));
  tried.back().refined = true;  // nothing to refine: the kept fit is the same least squares
  const double margin = 1.0 - fitter.options().autoMargin;
  return tried.back().report.score() < margin * tried[best].report.score() ? tried.size() - 1 : best;
}

// Scores the candidates by held-out error, fits the chosen one to the whole table and lists them all.
FitResult chooseByHeldOutError(const MeasuredTable& table, const FitOptions& options, const CandidateSpace& space,
                               const Context& context) {
  const std::size_t channels = table.channelCount();
  const HeldOutSplits splits(table, options.heldOut, context);
  SplitFitter fitter(splits, options, context);
  Tried tried = scoreCandidates(fitter, space);
  std::size_t best = addColorProfile(
      fitter, tried,
      weakenVaryingPrior(fitter, tried,
                         lowerExponentCap(fitter, tried, fewestParametersWithinMargin(tried, options, channels))),
      space);
  scoreRefined(fitter, tried, best);
  best = addTable(fitter, tried, best, space, splits);
  FitResult result = fitCandidate(table, options, tried[best].config, context);
  for (std::size_t i = 0; i < tried.size(); ++i) {
    const auto& [config, report, fits, starts, refined] = tried[i];
    ModelCandidate c;
    c.lobes = config.lobes;
    c.elevation = config.elevation;
    c.kind = config.kind;
    c.parameters = parameterTotal(config, options.method, channels);
    c.heldOutScore = report.score();
    c.kfoldRatio = report.kfold.ratio();
    c.elevationRatio = report.pooledElevations().ratio();
    c.seconds = report.seconds;
    c.maxExponent = options.method == FitMethod::Shared && config.kind != LobeKindChoice::HalfDifference
                        ? (config.maxExponent > 0.0 ? config.maxExponent : options.maxExponent)
                        : 0.0;
    c.varyingPrior = options.method == FitMethod::Shared && config.elevation == LobeElevation::Varying
                         ? (config.varyingPrior >= 0.0 ? config.varyingPrior : options.varyingPrior)
                         : 0.0;
    c.colorProfile = config.colorProfile;
    c.refined = refined;
    c.chosen = i == best;
    if (c.chosen) c.inSampleError = allRowsError(result.model, table).rms();
    result.candidates.push_back(c);
  }
  result.heldOut = tried[best].report;
  return result;
}

}  // namespace

FitResult fitLobes(const MeasuredTable& table, const FitOptions& options, const Context& context) {
  options.validate();
  table.validate();
  const auto start = Clock::now();
  const CandidateSpace space = candidateSpace(table, options);
  FitResult result = space.size() > 1 || space.tryColorProfile ? chooseByHeldOutError(table, options, space, context)
                                                               : fitOneConfiguration(table, options, space, context);
  result.options = options;
  for (const auto& c : result.candidates) {
    if (c.chosen && c.maxExponent > 0.0) result.options.maxExponent = c.maxExponent;
    if (c.chosen && c.varyingPrior > 0.0) result.options.varyingPrior = c.varyingPrior;
  }
  result.inSampleError = allRowsError(result.model, table).rms();
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  context.report(1.0);
  return result;
}

}  // namespace brdfbake
