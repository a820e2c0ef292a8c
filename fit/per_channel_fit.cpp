// The per-channel Ceres fit (FitMethod::PerChannel, docs/fitting.md "Per-channel fits with Ceres"): each
// channel's cube-root residual as a Ceres problem, its starts (greedy new lobes, elevation slices), the
// sequences K = 1, 2, ... of constant and varying lobes, and the choice of K and of the elevation.
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/fit/lobe_fit.hpp>

#include "per_channel_cost.hpp"
#include "per_channel_fit.hpp"

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>
#include <utility>

namespace brdfbake::detail {

namespace {

using Clock = std::chrono::steady_clock;

// A channel starts from its neighbour's fit only if their signals differ by at most this factor.
constexpr double kMaxNeighbourRatio = 10.0;

// Smallest weight coefficient of a varying lobe (they are interpolated geometrically, so > 0).
constexpr double kMinVaryingWeight = 1e-12;
// Largest one, so that exp() of the logarithm cannot overflow (a lobe weight of 1e6 is far beyond
// any physical reflectance).
constexpr double kMaxVaryingWeight = 1e6;

// sum_i 1/2 rho(r_i^2), Ceres' cost of parameters x.
double robustCost(const ChannelData& data, const std::vector<double>& x, int lobes, int count,
                  const ceres::LossFunction* loss, double eps) {
  double cost = 0.0;
  for (const auto& s : data.samples) {
    const double r = cubeRoot(s.cosIn * channelValue(x.data(), lobes, count, s) + eps) - s.target;
    double rho[3] = {r * r, 1.0, 0.0};
    if (loss) loss->Evaluate(r * r, rho);
    cost += 0.5 * rho[0];
  }
  return cost;
}

// One channel's state for one candidate model.
struct Candidate {
  std::vector<double> x;
  double cost = HUGE_VAL;     // Ceres' cost: sum 1/2 rho(r_i^2)
  double squares = HUGE_VAL;  // sum r_i^2, the plain squared cube-root residuals
  SolverReport report;
  bool valid = false;
};

class ChannelFitter {
 public:
  ChannelFitter(ChannelData data, const FitOptions& options) : data_(std::move(data)), options_(options) {
    const double scale = std::max(options.lossScale * data_.maxTarget, 1e-12);
    switch (options.loss) {
      case RobustLoss::Cauchy:
        loss_ = std::make_unique<ceres::CauchyLoss>(scale);
        break;
      case RobustLoss::Huber:
        loss_ = std::make_unique<ceres::HuberLoss>(scale);
        break;
      case RobustLoss::None:
        break;
    }
  }

  std::size_t sampleCount() const { return data_.samples.size(); }
  int totalIterations = 0;
  double seconds = 0.0;

  // Greedy: the best (lobes-1)-lobe constant model plus a new lobe from a grid of starts.
  Candidate fitConstant(int lobes, const Candidate* previous) {
    const auto start = Clock::now();
    std::vector<double> base;
    if (previous && previous->valid) {
      base = previous->x;
    } else {
      base = {initialDiffuse()};
      for (int k = 1; k < lobes; ++k) base = withBestNewLobe(base, k, 1).front();
    }
    Candidate best;
    for (auto& x : withBestNewLobe(base, lobes - 1, 2)) {
      Candidate c = solve(std::move(x), lobes, 1);
      if (!best.valid || (c.valid && c.cost < best.cost)) best = std::move(c);
    }
    seconds += std::chrono::duration<double>(Clock::now() - start).count();
    return best;
  }

  // Varying: from the constant model with the same count (equal Bernstein coefficients), or
  // greedily from the varying model with one lobe fewer.
  Candidate fitVarying(int lobes, const Candidate* constant, const Candidate* previousVarying) {
    const auto start = Clock::now();
    std::vector<std::vector<double>> starts;
    if (constant && constant->valid) starts.push_back(expandToVarying(constant->x, lobes));
    if (previousVarying && previousVarying->valid)
      starts.push_back(withBestNewLobe(previousVarying->x, lobes - 1, 1, kVaryingCount).front());
    if (auto sliced = sliceStart(lobes)) starts.push_back(std::move(*sliced));
    if (starts.empty()) starts.push_back(expandToVarying(fitConstant(lobes, nullptr).x, lobes));
    // Refine the two starts of lowest cost.
    std::vector<std::pair<double, std::size_t>> order;
    for (std::size_t i = 0; i < starts.size(); ++i) {
      order.emplace_back(robustCost(data_, starts[i], lobes, kVaryingCount, loss_.get(), data_.eps), i);
    }
    std::sort(order.begin(), order.end());
    Candidate best;
    for (std::size_t r = 0; r < order.size() && r < 2; ++r) {
      Candidate c = solve(std::move(starts[order[r].second]), lobes, kVaryingCount);
      if (!best.valid || (c.valid && c.cost < best.cost)) best = std::move(c);
    }
    seconds += std::chrono::duration<double>(Clock::now() - start).count();
    return best;
  }

  // One solve from another channel's fit of the same model, its k_d and weights scaled by the
  // ratio of the channels' signals (a neighbouring wavelength: the same shapes, another brightness).
  // Empty when the channels differ by more than kMaxNeighbourRatio in signal (a dark or nearly dark
  // channel, whose neighbour's fit is no start for it): then fit from the channel's own starts.
  std::optional<Candidate> fitFrom(const Candidate& neighbour, double neighbourSignal, int lobes, int count) {
    const double ratio = data_.signal / neighbourSignal;
    if (!neighbour.valid || !(ratio >= 1.0 / kMaxNeighbourRatio && ratio <= kMaxNeighbourRatio)) return std::nullopt;
    const auto start = Clock::now();
    std::vector<double> x = neighbour.x;
    x[0] *= ratio;
    for (int k = 0; k < lobes; ++k) {
      for (int j = 0; j < count; ++j) {
        double& weight = x[static_cast<std::size_t>(1 + k * 2 * count + j)];
        weight = count > 1 ? weight + std::log(ratio) : weight * ratio;  // varying weights are logarithms
      }
    }
    Candidate fitted = solve(std::move(x), lobes, count);
    seconds += std::chrono::duration<double>(Clock::now() - start).count();
    return fitted;
  }

  double signal() const { return data_.signal; }

 private:
  // A start for a varying model from the data itself: constant models fitted separately to three
  // slices of elevation (t in [0, 1/3), [1/3, 2/3), [2/3, 1]), their values at each slice's mean t
  // interpolated by the geometric Bernstein form (lobes matched broadest to sharpest).
  std::optional<std::vector<double>> sliceStart(int lobes) {
    constexpr int kSlices = 3;
    static_assert(kSlices == kVaryingCount, "one slice per control value");
    if (slices_.empty()) {
      // The slices' fitters persist, so that their K-lobe fits grow greedily from their (K-1)-lobe fits.
      for (int s = 0; s < kSlices; ++s) {
        ChannelData slice;
        slice.eps = data_.eps;
        slice.maxTarget = data_.maxTarget;
        double sumT = 0.0;
        for (std::size_t i = 0; i < data_.samples.size(); ++i) {
          const double t = data_.samples[i].u;
          if (std::min(static_cast<int>(t * kSlices), kSlices - 1) != s) continue;
          slice.samples.push_back(data_.samples[i]);
          slice.measured.push_back(data_.measured[i]);
          sumT += t;
        }
        const double meanT = slice.samples.empty() ? 0.0 : sumT / static_cast<double>(slice.samples.size());
        for (int j = 0; j < kSlices; ++j) {
          sliceBasis_(s, j) = (j == 1 ? 2.0 : 1.0) * std::pow(meanT, j) * std::pow(1.0 - meanT, 2 - j);
        }
        slices_.push_back(std::make_unique<ChannelFitter>(std::move(slice), options_));
        sliceFits_.emplace_back();
      }
    }
    std::array<std::vector<double>, kSlices> fits;
    for (int s = 0; s < kSlices; ++s) {
      ChannelFitter& fitter = *slices_[static_cast<std::size_t>(s)];
      if (fitter.sampleCount() < static_cast<std::size_t>(4 * parameterCount(lobes, 1))) return std::nullopt;
      Candidate& c = sliceFits_[static_cast<std::size_t>(s)];
      const int before = fitter.totalIterations;
      for (int k = c.valid ? static_cast<int>(c.x.size() / 2) + 1 : 1; k <= lobes; ++k) {
        c = fitter.fitConstant(k, k > 1 ? &c : nullptr);
        if (!c.valid) return std::nullopt;
      }
      totalIterations += fitter.totalIterations - before;
      // Broadest lobe first in every slice.
      std::vector<std::pair<double, double>> sorted;
      for (int k = 0; k < lobes; ++k)
        sorted.emplace_back(c.x[static_cast<std::size_t>(2 + 2 * k)], c.x[static_cast<std::size_t>(1 + 2 * k)]);
      std::sort(sorted.begin(), sorted.end());
      fits[s] = {c.x[0]};
      for (const auto& [n, w] : sorted) fits[s].insert(fits[s].end(), {w, n});
    }
    const auto solver = sliceBasis_.colPivHouseholderQr();
    std::vector<double> x{(fits[0][0] + fits[1][0] + fits[2][0]) / 3.0};
    for (int k = 0; k < lobes; ++k) {
      for (int p = 0; p < 2; ++p) {
        Eigen::Vector3d logs;
        for (int s = 0; s < kSlices; ++s) {
          const double v = fits[s][static_cast<std::size_t>(1 + 2 * k + p)];
          logs[s] = p == 0 ? std::log(std::max(v, kMinVaryingWeight))
                           : std::log(std::clamp(v, kMinLobeExponent, kMaxLobeExponent));
        }
        const Eigen::Vector3d control = solver.solve(logs);
        for (int j = 0; j < kSlices; ++j) {
          x.push_back(p == 0 ? std::clamp(control[j], std::log(kMinVaryingWeight), std::log(kMaxVaryingWeight))
                             : std::clamp(control[j], 0.0, std::log(kMaxLobeExponent)));
        }
      }
    }
    if (!std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); })) return std::nullopt;
    return x;
  }

  double initialDiffuse() const {
    // pi times the 25th percentile of the measured values: the floor the lobes stand on.
    std::vector<double> values;
    values.reserve(data_.measured.size());
    for (double f : data_.measured) values.push_back(std::max(f, 0.0));
    if (values.empty()) return 0.0;
    const auto nth = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 4);
    std::nth_element(values.begin(), nth, values.end());
    return kPi * *nth;
  }

  // Equal values at every elevation, as logarithms.
  static std::vector<double> expandToVarying(const std::vector<double>& constant, int lobes) {
    std::vector<double> x{constant[0]};
    for (int k = 0; k < lobes; ++k) {
      x.insert(x.end(), kVaryingCount, std::log(std::max(constant[1 + 2 * k], kMinVaryingWeight)));
      x.insert(x.end(), kVaryingCount, std::log(std::clamp(constant[2 + 2 * k], kMinLobeExponent, kMaxLobeExponent)));
    }
    return x;
  }

  // The `keep` best starts for lobe number `existing` (0-based) added to x: exponents 2..32768,
  // weight from a linearised weighted least-squares fit to the remaining signal.
  std::vector<std::vector<double>> withBestNewLobe(const std::vector<double>& x, int existing, std::size_t keep,
                                                   int count = 1) const {
    const auto& samples = data_.samples;
    std::vector<double> current(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) current[i] = channelValue(x.data(), existing, count, samples[i]);
    // Weights of the linearised cube-root residual: (cos d cbrt(y)/dy)^2, y floored at 1e-3 of the peak.
    const double floor = std::max(1e-3 * data_.maxTarget * data_.maxTarget * data_.maxTarget, 1e-300);
    std::vector<std::pair<double, std::vector<double>>> scored;
    for (int e = 1; e <= 15; ++e) {
      const double n = std::ldexp(1.0, e);
      double num = 0.0, den = 0.0;
      for (std::size_t i = 0; i < samples.size(); ++i) {
        const double b = normalizedLobe(1.0, n, samples[i].cosToMirror);
        if (b == 0.0) continue;
        const double y = std::max(std::abs(samples[i].cosIn * data_.measured[i]), floor);
        const double w = samples[i].cosIn * samples[i].cosIn / std::cbrt(y * y * y * y);
        num += w * b * (data_.measured[i] - current[i]);
        den += w * b * b;
      }
      const double weight = den > 0.0 ? std::max(num / den, 0.0) : 0.0;
      for (double factor : {0.3, 1.0, 3.0}) {
        std::vector<double> candidate = x;
        const bool logs = count > 1;
        candidate.insert(candidate.end(), static_cast<std::size_t>(count),
                         logs ? std::log(std::max(weight * factor, kMinVaryingWeight)) : weight * factor);
        candidate.insert(candidate.end(), static_cast<std::size_t>(count), logs ? std::log(n) : n);
        const double cost = robustCost(data_, candidate, existing + 1, count, loss_.get(), data_.eps);
        scored.emplace_back(cost, std::move(candidate));
      }
    }
    std::stable_sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    // Keep starts with different exponents (the three weight factors of one exponent are near-duplicates).
    std::vector<std::vector<double>> best;
    std::vector<double> exponents;
    for (auto& [cost, candidate] : scored) {
      const double n = candidate.back();  // the exponent (or its logarithm) of the new lobe
      if (std::find(exponents.begin(), exponents.end(), n) != exponents.end()) continue;
      exponents.push_back(n);
      best.push_back(std::move(candidate));
      if (best.size() == keep) break;
    }
    return best;
  }

  Candidate solve(std::vector<double> x, int lobes, int count) {
    Candidate result;
    ceres::Problem problem;
    problem.AddResidualBlock(makeChannelCost(data_, lobes, count, loss_.get()), nullptr, x.data());
    // Bounds (see lobeValue in per_channel_cost.cpp); the start is moved inside them first.
    auto bound = [&](int index, double lower, double upper) {
      problem.SetParameterLowerBound(x.data(), index, lower);
      if (upper < HUGE_VAL) problem.SetParameterUpperBound(x.data(), index, upper);
      auto& value = x[static_cast<std::size_t>(index)];
      value = std::clamp(value, lower, upper);
    };
    bound(0, 0.0, HUGE_VAL);
    const bool logs = count > 1;
    for (int k = 0; k < lobes; ++k) {
      for (int j = 0; j < count; ++j) {
        const int w = 1 + k * 2 * count + j, n = w + count;
        bound(w, logs ? std::log(kMinVaryingWeight) : 0.0, logs ? std::log(kMaxVaryingWeight) : HUGE_VAL);
        bound(n, logs ? std::log(kMinLobeExponent) : kMinLobeExponent,
              logs ? std::log(kMaxLobeExponent) : kMaxLobeExponent);
      }
    }
    ceres::Solver::Options solverOptions;
    solverOptions.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    solverOptions.max_num_iterations = options_.maxIterations;
    solverOptions.function_tolerance = options_.functionTolerance;
    solverOptions.parameter_tolerance = 1e-8;
    solverOptions.gradient_tolerance = 1e-12;
    solverOptions.logging_type = ceres::SILENT;
    solverOptions.minimizer_progress_to_stdout = false;
    solverOptions.num_threads = 1;
    ceres::Solver::Summary summary;
    ceres::Solve(solverOptions, &problem, &summary);

    result.report.termination = ceres::TerminationTypeToString(summary.termination_type);
    result.report.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
    result.report.seconds = summary.total_time_in_seconds;
    result.report.initialCost = summary.initial_cost;
    result.report.finalCost = summary.final_cost;
    result.report.briefReport = summary.BriefReport();
    const bool finite =
        std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); }) && std::isfinite(summary.final_cost);
    result.report.usable = summary.IsSolutionUsable() && finite;
    totalIterations += result.report.iterations;
    result.valid = finite;
    result.cost = finite ? summary.final_cost : HUGE_VAL;
    result.squares = finite ? 2.0 * robustCost(data_, x, lobes, count, nullptr, data_.eps) : HUGE_VAL;
    result.x = std::move(x);
    return result;
  }

  ChannelData data_;
  const FitOptions& options_;
  std::unique_ptr<ceres::LossFunction> loss_;
  // sliceStart's per-slice fitters, their latest fits and the Bernstein weights at their mean t.
  std::vector<std::unique_ptr<ChannelFitter>> slices_;
  std::vector<Candidate> sliceFits_;
  Eigen::Matrix3d sliceBasis_ = Eigen::Matrix3d::Zero();
};

LobeChannel toChannel(const std::vector<double>& x, int lobes, int count, std::string name) {
  LobeChannel channel;
  channel.name = std::move(name);
  channel.diffuse = std::max(0.0, x[0]);
  for (int k = 0; k < lobes; ++k) {
    const auto* p = x.data() + 1 + k * 2 * count;
    Lobe lobe;
    lobe.weight.assign(p, p + count);
    lobe.exponent.assign(p + count, p + 2 * count);
    if (count > 1) {  // optimised as logarithms
      for (double& w : lobe.weight) w = std::max(std::exp(w), kMinVaryingWeight);
      for (double& n : lobe.exponent) n = std::exp(n);
    }
    for (double& w : lobe.weight) w = std::max(0.0, w);
    for (double& n : lobe.exponent) n = std::clamp(n, kMinLobeExponent, kMaxLobeExponent);
    channel.lobes.push_back(std::move(lobe));
  }
  // Broadest lobe first: a canonical order (lobes are interchangeable in the model).
  std::stable_sort(channel.lobes.begin(), channel.lobes.end(), [](const Lobe& a, const Lobe& b) {
    return std::accumulate(a.exponent.begin(), a.exponent.end(), 0.0) <
           std::accumulate(b.exponent.begin(), b.exponent.end(), 0.0);
  });
  return channel;
}

}  // namespace

// The fitted views' elevation range (per_channel_fit.hpp).
LobeModel fittedRange(const MeasuredTable& table) {
  LobeModel range;
  range.minCos = 1.0;
  range.maxCos = 0.0;
  for (std::size_t i = 0; i < table.size(); ++i) {
    const double u = table.outgoingDirection(i).z(), cosIn = table.incidentDirection(i).z();
    if (!(u > 0.0) || !(cosIn > 0.0)) continue;
    range.minCos = std::min(range.minCos, u);
    range.maxCos = std::max(range.maxCos, u);
  }
  // Views within 1 degree of the horizon do not widen the range (ln cos theta diverges there).
  range.minCos = clampFinite(range.minCos, std::cos(radians(89.0)), 1.0);
  range.maxCos = std::max(range.minCos, clampFinite(range.maxCos, 0.0, 1.0));
  return range;
}

namespace {

// The error auto choices compare: RMS of the plain cube-root residuals over every channel (the
// robust loss shapes the fit, but a highlight it discounts still counts here).
double jointError(const std::vector<Candidate>& perChannel, std::size_t samples) {
  double squares = 0.0;
  for (const auto& c : perChannel) squares += c.valid ? c.squares : HUGE_VAL;
  return std::sqrt(squares / static_cast<double>(samples * perChannel.size()));
}

// The per-channel Ceres fits of K = 1, 2, ... lobes of each elevation, every channel in parallel,
// each K starting from the fits of K - 1 (and a varying K from the constant K).
class PerChannelSequences {
 public:
  PerChannelSequences(const MeasuredTable& table, const FitOptions& options, const LobeModel& range, int maxLobes,
                      const Context& context)
      : options_(options),
        context_(context),
        maxLobes_(maxLobes),
        channels_(table.channelCount()),
        warmStart_(table.kind == ChannelKind::Spectral) {
    for (std::size_t c = 0; c < channels_; ++c) {
      fitters_.push_back(std::make_unique<ChannelFitter>(channelData(table, c, range), options));
    }
    samples_ = fitters_.empty() ? 0 : fitters_[0]->sampleCount();
  }

  std::size_t samples() const { return samples_; }
  const ChannelFitter& fitter(std::size_t c) const { return *fitters_[c]; }
  /// True if the samples determine `lobes` lobes of `elevation` (no more parameters than samples).
  bool fits(int lobes, LobeElevation elevation) const {
    return static_cast<std::size_t>(parameterCount(lobes, elevationCoefficientCount(elevation))) <= samples_;
  }
  /// The fits of `lobes` lobes of `elevation`, per channel (run() made them).
  const std::vector<Candidate>& fitted(LobeElevation elevation, int lobes) const {
    return fitted_[index(elevation)][static_cast<std::size_t>(lobes - 1)];
  }

  /// Fits K = 1, 2, ... of one elevation; returns the chosen K (0 if none could be fitted). With
  /// auto lobes, K - 1 is kept unless K lowered the error by at least the margin.
  int run(LobeElevation elevation, ProgressCounter& progress, tbb::task_arena& arena) {
    const bool autoLobes = options_.lobes == 0;
    int chosen = 0;
    double previousError = 0.0;
    for (int lobes = 1; lobes <= maxLobes_; ++lobes) {
      if (!fits(lobes, elevation)) break;
      const double error = jointError(fitNext(elevation, &progress, arena), samples_);
      if (autoLobes && lobes > 1 && !(error < (1.0 - options_.autoMargin) * previousError))
        break;  // 0 -> 0 is no improvement
      chosen = lobes;
      previousError = error;
    }
    return chosen;
  }

  /// Fits the sequence of `elevation` up to `lobes` lobes (a varying K after the constant K it
  /// starts from), keeping what is fitted already.
  void extend(LobeElevation elevation, int lobes, tbb::task_arena& arena) {
    if (elevation == LobeElevation::Varying) extend(LobeElevation::Constant, lobes, arena);
    while (static_cast<int>(fitted_[index(elevation)].size()) < lobes) fitNext(elevation, nullptr, arena);
  }

 private:
  static std::size_t index(LobeElevation elevation) { return elevation == LobeElevation::Constant ? 0 : 1; }

  // Fits one more lobe than the sequence of `elevation` has, every channel in parallel.
  const std::vector<Candidate>& fitNext(LobeElevation elevation, ProgressCounter* progress, tbb::task_arena& arena) {
    auto& sequence = fitted_[index(elevation)];
    const int lobes = static_cast<int>(sequence.size()) + 1;
    std::vector<Candidate> current(channels_);
    // Anchors first, from their own starts; then the others in rounds by their distance from the
    // nearest anchor, each from its neighbour one channel closer to it, fitted in the round before.
    for (std::size_t round = 0; round <= kAnchorStride / 2; ++round) {
      arena.execute([&] {
        tbb::parallel_for(std::size_t(0), channels_, [&](std::size_t c) {
          if (toAnchor(c).first != round) return;
          context_.checkCancelled();
          current[c] = round == 0 ? fitOne(elevation, lobes, c) : fitFromNeighbour(current, elevation, lobes, c);
          if (progress) progress->step();
        });
      });
    }
    sequence.push_back(std::move(current));
    return sequence.back();
  }

  // Spectral tables: neighbouring wavelengths reflect alike, so every kAnchorStride-th channel (and
  // the last) is fitted from its own starts (2 solves per lobe count, and the slices' fits for varying
  // lobes) and each other one in one solve from its neighbour's fit (docs/fitting.md, "Per-channel
  // fits with Ceres"). Other tables: every channel from its own starts.
  static constexpr std::size_t kAnchorStride = 16;

  // The distance of channel c from its nearest anchor (0: an anchor) and its neighbour one channel
  // closer to it.
  std::pair<std::size_t, std::size_t> toAnchor(std::size_t c) const {
    if (!warmStart_ || c + 1 == channels_) return {0, c};
    const std::size_t below = c - c % kAnchorStride, above = std::min(below + kAnchorStride, channels_ - 1);
    if (c - below <= above - c) return {c - below, c == below ? c : c - 1};
    return {above - c, c + 1};
  }

  Candidate fitOne(LobeElevation elevation, int lobes, std::size_t c) {
    const auto& constant = fitted_[0];
    if (elevation == LobeElevation::Constant) {
      return fitters_[c]->fitConstant(lobes, lobes > 1 ? &constant[lobes - 2][c] : nullptr);
    }
    const Candidate* start = static_cast<int>(constant.size()) >= lobes ? &constant[lobes - 1][c] : nullptr;
    const Candidate* previous = lobes > 1 ? &fitted_[1][lobes - 2][c] : nullptr;
    return fitters_[c]->fitVarying(lobes, start, previous);
  }

  Candidate fitFromNeighbour(const std::vector<Candidate>& current, LobeElevation elevation, int lobes, std::size_t c) {
    const std::size_t neighbour = toAnchor(c).second;
    const int count = elevationCoefficientCount(elevation);
    if (auto fitted = fitters_[c]->fitFrom(current[neighbour], fitters_[neighbour]->signal(), lobes, count)) {
      if (fitted->valid) return std::move(*fitted);
    }
    return fitOne(elevation, lobes, c);
  }

  const FitOptions& options_;
  Context context_;
  int maxLobes_;
  std::size_t channels_, samples_ = 0;
  bool warmStart_;  // spectral: channels between anchors start from a neighbour's fit (toAnchor)
  std::vector<std::unique_ptr<ChannelFitter>> fitters_;
  std::vector<std::vector<Candidate>> fitted_[2];  // [elevation][K - 1][channel]
};

// Throws unless the usable samples determine the model asked for (and at least one constant lobe).
void checkDeterminable(const PerChannelSequences& sequences, const FitOptions& options, int maxLobes,
                       const std::string& label) {
  const std::size_t samples = sequences.samples();
  if (samples == 0) {
    throw Error(Error::Kind::InvalidInput, label + ": no sample has both directions above the horizon; nothing to fit");
  }
  if (!sequences.fits(1, LobeElevation::Constant)) {
    throw Error(Error::Kind::InvalidInput, label + ": " + std::to_string(samples) +
                                               " usable sample(s) cannot determine a lobe model (at least " +
                                               std::to_string(parameterCount(1, 1)) + " needed)");
  }
  if (options.lobes == 0) return;
  for (LobeElevation e : {LobeElevation::Constant, LobeElevation::Varying}) {
    const bool requested =
        options.elevation == (e == LobeElevation::Constant ? ElevationChoice::Constant : ElevationChoice::Varying);
    if (requested && !sequences.fits(maxLobes, e)) {
      throw Error(Error::Kind::InvalidArgument,
                  label + ": " + std::to_string(samples) + " usable samples cannot determine " +
                      std::to_string(parameterCount(maxLobes, elevationCoefficientCount(e))) + " parameters (" +
                      std::to_string(maxLobes) + " " + std::string(toString(e)) + " lobe(s))");
    }
  }
}

// The elevation and lobe count fitPerChannel returns: the one asked for, or with auto elevation
// varying lobes only if they beat the constant ones by the margin.
std::pair<LobeElevation, int> chooseElevation(const PerChannelSequences& sequences, const FitOptions& options,
                                              int constantLobes, int varyingLobes) {
  if (options.elevation == ElevationChoice::Varying) return {LobeElevation::Varying, varyingLobes};
  if (options.elevation == ElevationChoice::Auto && varyingLobes > 0) {
    const double constantError =
        jointError(sequences.fitted(LobeElevation::Constant, constantLobes), sequences.samples());
    const double varyingError = jointError(sequences.fitted(LobeElevation::Varying, varyingLobes), sequences.samples());
    if (varyingError < (1.0 - options.elevationMargin) * constantError) return {LobeElevation::Varying, varyingLobes};
  }
  return {LobeElevation::Constant, constantLobes};
}

}  // namespace

namespace {

// The model of one fit per channel, with the table's elevation range, channel names and wavelengths.
LobeModel toModel(const std::vector<Candidate>& chosen, LobeElevation elevation, int lobes, const LobeModel& range,
                  const MeasuredTable& table) {
  const int count = elevationCoefficientCount(elevation);
  LobeModel model;
  model.elevation = elevation;
  model.minCos = range.minCos;
  model.maxCos = range.maxCos;
  if (table.kind == ChannelKind::Spectral) model.wavelengthsNm = table.wavelengthsNm;
  for (std::size_t c = 0; c < chosen.size(); ++c) {
    const std::string name = table.channelName(c);
    model.channels.push_back(toChannel(chosen[c].x, lobes, count, name));
  }
  model.validate();
  return model;
}

}  // namespace

// The Ceres per-channel fit of one explicit lobe count and elevation (per_channel_fit.hpp).
FitResult fitPerChannel(const MeasuredTable& table, const FitOptions& options, const Context& context) {
  const auto start = Clock::now();
  const std::string label = table.label();
  const std::size_t channels = table.channelCount();
  if (channels == 0) throw Error(Error::Kind::InvalidInput, label + ": no channels to fit");
  const LobeModel range = fittedRange(table);
  const int maxLobes = options.lobes == 0 ? options.maxAutoLobes : options.lobes;
  PerChannelSequences sequences(table, options, range, maxLobes, context);
  checkDeterminable(sequences, options, maxLobes, label);

  const bool tryVarying = options.elevation != ElevationChoice::Constant;
  ProgressCounter progress(context.progress(), channels * static_cast<std::size_t>(maxLobes) * (tryVarying ? 2 : 1));
  tbb::task_arena arena(context.arenaThreads());
  // Constant models always: varying ones start from them.
  const int constantLobes = sequences.run(LobeElevation::Constant, progress, arena);
  const int varyingLobes = tryVarying ? sequences.run(LobeElevation::Varying, progress, arena) : 0;
  const auto [elevation, lobes] = chooseElevation(sequences, options, constantLobes, varyingLobes);
  if (lobes == 0) {
    throw Error(Error::Kind::InvalidInput, label + ": " + std::to_string(sequences.samples()) +
                                               " usable samples cannot determine a " +
                                               std::string(toString(elevation)) + " lobe model");
  }

  const auto& chosen = sequences.fitted(elevation, lobes);
  FitResult result;
  result.options = options;
  result.model = toModel(chosen, elevation, lobes, range, table);
  for (std::size_t c = 0; c < channels; ++c) {
    ChannelFitStats stats = evaluateFit(result.model, table, c);
    stats.solver = chosen[c].report;
    stats.solver.usable = stats.solver.usable && chosen[c].valid;
    stats.totalIterations = sequences.fitter(c).totalIterations;
    stats.seconds = sequences.fitter(c).seconds;
    result.channels.push_back(std::move(stats));
  }
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

struct PerChannelFits::State {
  State(const MeasuredTable& fitted, const FitOptions& fitOptions, const Context& context)
      : table(&fitted),
        options(fitOptions),
        range(fittedRange(fitted)),
        sequences(fitted, options, range, options.maxAutoLobes, context),
        arena(context.arenaThreads()) {}
  const MeasuredTable* table;
  FitOptions options;  // the sequences keep a reference to it
  LobeModel range;
  PerChannelSequences sequences;
  tbb::task_arena arena;
};

PerChannelFits::PerChannelFits(const MeasuredTable& table, const FitOptions& options, const Context& context) {
  if (table.channelCount() == 0) throw Error(Error::Kind::InvalidInput, table.label() + ": no channels to fit");
  state_ = std::make_unique<State>(table, options, context);
}

PerChannelFits::~PerChannelFits() = default;

LobeModel PerChannelFits::model(int lobes, LobeElevation elevation) {
  FitOptions asked = state_->options;
  asked.lobes = lobes;
  asked.elevation = elevation == LobeElevation::Constant ? ElevationChoice::Constant : ElevationChoice::Varying;
  checkDeterminable(state_->sequences, asked, lobes, state_->table->label());
  state_->sequences.extend(elevation, lobes, state_->arena);
  return toModel(state_->sequences.fitted(elevation, lobes), elevation, lobes, state_->range, *state_->table);
}

}  // namespace brdfbake::detail
