#include <brdfbake/core/error.hpp>
#include <brdfbake/core/named_values.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/core/run_options.hpp>
#include <brdfbake/fit/lobe_fit.hpp>

#include "shared_lobe_fit.hpp"

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <memory>
#include <mutex>
#include <numeric>
#include <optional>
#include <sstream>
#include <utility>

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
  requireThreadCount(threads, "fit: threads");
  require(std::isfinite(maxExponent) && maxExponent >= kMinLobeExponent && maxExponent <= kMaxLobeExponent,
          "fit: maxExponent must be in [1, 1e5]");
  heldOut.validate();
}

bool FitResult::usable() const {
  return !channels.empty() &&
         std::all_of(channels.begin(), channels.end(), [](const ChannelFitStats& c) { return c.solver.usable; });
}

std::string FitResult::briefReport() const {
  std::ostringstream out;
  std::size_t lobes = model.channels.empty() ? 0 : model.channels[0].lobes.size();
  out << "Lobe fit: " << lobes << " lobe(s), " << toString(model.elevation) << " elevation, " << channels.size()
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

namespace {

using Clock = std::chrono::steady_clock;

constexpr int kVaryingCount = elevationCoefficientCount(LobeElevation::Varying);

// Per-sample quantities the residual needs; the geometry is data, never differentiated.
struct FitSample {
  double cosIn;        // cos theta_i, the cosine weight
  double u;            // elevation coordinate of the view (outgoing) direction (LobeModel::elevationCoordinate)
  double cosToMirror;  // r_v . l
  double target;       // cbrt(cos theta_i f_measured + eps)
  std::array<double, kVaryingCount> bernstein;  // Bernstein weights at u
};

struct ChannelData {
  std::vector<FitSample> samples;
  std::vector<double> measured;  // f_i of the fitted samples
  double eps = 0.0;
  double maxTarget = 0.0;
};

// Layout of the parameter block: [k_d, lobe 0: weight coefficients, exponent coefficients, lobe 1: ...].
int parameterCount(int lobes, int count) { return 1 + lobes * 2 * count; }

// Smallest weight coefficient of a varying lobe (they are interpolated geometrically, so > 0).
constexpr double kMinVaryingWeight = 1e-12;
// Largest one, so that exp() of the logarithm cannot overflow (a lobe weight of 1e6 is far beyond
// any physical reflectance).
constexpr double kMaxVaryingWeight = 1e6;

// The model from the optimiser's parameters, through the same formulas as LobeModel. Constant
// lobes are optimised as C and n themselves (bounds C >= 0, 1 <= n <= 1e5); varying lobes as
// ln C_j and ln n_j (bounds 1e-12 <= C_j <= 1e6, 1 <= n_j <= 1e5), the natural scale of their
// geometric interpolation, with the sample's Bernstein weights precomputed.
template <class T>
T channelValue(const T* x, int lobes, int count, const FitSample& s) {
  T weights[kMaxFitLobes], exponents[kMaxFitLobes];
  for (int k = 0; k < lobes; ++k) {
    const T* p = x + 1 + k * 2 * count;
    weights[k] = count == 1 ? p[0] : geometricBlend(p, s.bernstein.data(), count);
    exponents[k] = count == 1 ? p[1] : geometricBlend(p + count, s.bernstein.data(), count);
  }
  double cosToAxis[kMaxFitLobes];
  std::fill(cosToAxis, cosToAxis + kMaxFitLobes, s.cosToMirror);
  return lobeSum(x[0], weights, exponents, lobes, cosToAxis);
}

struct CubeRootResidual {
  const FitSample* sample;
  int lobes;
  int count;
  double eps;

  template <class T>
  bool operator()(const T* parameters, T* residual) const {
    const T f = channelValue(parameters, lobes, count, *sample);
    using std::cbrt;
    residual[0] = cbrt(T(sample->cosIn) * f + T(eps)) - T(sample->target);
    // A step that overflows is rejected by the solver (not an error): report it as a failed evaluation.
    return ceres::isfinite(residual[0]);
  }
};

// A fixed-size autodiff cost for a parameter block of `size` values (Jets of exactly that size:
// one pass per evaluation). Sizes are 1 + 2K (constant) and 1 + 2 K kVaryingCount (varying).
template <int N>
ceres::CostFunction* fixedCost(const CubeRootResidual& residual) {
  return new ceres::AutoDiffCostFunction<CubeRootResidual, 1, N>(new CubeRootResidual(residual));
}

template <int... Sizes>
ceres::CostFunction* costForSize(const CubeRootResidual& residual, int size, std::integer_sequence<int, Sizes...>) {
  ceres::CostFunction* cost = nullptr;
  ((size == Sizes ? (cost = fixedCost<Sizes>(residual), true) : false) || ...);
  return cost;
}

// Every size parameterCount() takes for 1..kMaxFitLobes lobes, constant and varying.
using ParameterCounts = std::integer_sequence<int, 3, 5, 7, 9, 11, 13, 19, 25, 31, 37>;
static_assert(kMaxFitLobes == 6 && kVaryingCount == 3, "update ParameterCounts");

ceres::CostFunction* makeCost(const CubeRootResidual& residual, int size) {
  ceres::CostFunction* cost = costForSize(residual, size, ParameterCounts{});
  if (!cost) throw Error(Error::Kind::InvalidArgument, "fit: unsupported parameter count " + std::to_string(size));
  return cost;
}

double modelValue(const std::vector<double>& x, int lobes, int count, const FitSample& s) {
  return channelValue(x.data(), lobes, count, s);
}

// sum_i 1/2 rho(r_i^2), Ceres' cost of parameters x.
double robustCost(const ChannelData& data, const std::vector<double>& x, int lobes, int count,
                  const ceres::LossFunction* loss, double eps) {
  double cost = 0.0;
  for (const auto& s : data.samples) {
    const double r = std::cbrt(s.cosIn * modelValue(x, lobes, count, s) + eps) - s.target;
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
    for (std::size_t i = 0; i < samples.size(); ++i) current[i] = modelValue(x, existing, count, samples[i]);
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
    const int size = parameterCount(lobes, count);
    ceres::Problem::Options problemOptions;
    problemOptions.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problemOptions);
    for (const auto& sample : data_.samples) {
      problem.AddResidualBlock(makeCost(CubeRootResidual{&sample, lobes, count, data_.eps}, size), loss_.get(),
                               x.data());
    }
    // Bounds (see channelValue); the start is moved inside them first.
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
    solverOptions.linear_solver_type = ceres::DENSE_QR;
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

// The fitted samples of one channel: light and view above the horizon. `range` gives the
// elevation coordinate.
ChannelData channelData(const MeasuredTable& table, std::size_t channel, const LobeModel& range) {
  ChannelData data;
  double maxWeighted = 0.0;
  for (std::size_t i = 0; i < table.size(); ++i) {
    const Vec3 wi = table.incidentDirection(i), wo = table.outgoingDirection(i);
    if (!(wi.z() > 0.0) || !(wo.z() > 0.0)) continue;
    const double f = table.values(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(channel));
    FitSample sample{wi.z(), range.elevationCoordinate(wo.z()), reflect(wo, Vec3(Vec3::UnitZ())).dot(wi), 0.0, {}};
    bernsteinWeights(kVaryingCount, sample.u, sample.bernstein.data());
    data.samples.push_back(sample);
    data.measured.push_back(f);
    maxWeighted = std::max(maxWeighted, std::abs(wi.z() * f));
  }
  data.eps = std::max(1e-6 * maxWeighted, 1e-12);
  for (std::size_t i = 0; i < data.samples.size(); ++i) {
    auto& s = data.samples[i];
    s.target = std::cbrt(s.cosIn * data.measured[i] + data.eps);
    data.maxTarget = std::max(data.maxTarget, std::abs(s.target));
  }
  return data;
}

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

// The elevation range of the fitted views: the varying polynomials span exactly this range.
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
  PerChannelSequences(const MeasuredTable& table, const FitOptions& options, const LobeModel& range, int maxLobes)
      : options_(options), maxLobes_(maxLobes), channels_(table.channelCount()) {
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
      std::vector<Candidate> current(channels_);
      arena.execute([&] {
        tbb::parallel_for(std::size_t(0), channels_, [&](std::size_t c) {
          current[c] = fitOne(elevation, lobes, c);
          progress.step();
        });
      });
      const double error = jointError(current, samples_);
      fitted_[index(elevation)].push_back(std::move(current));
      if (autoLobes && lobes > 1 && !(error < (1.0 - options_.autoMargin) * previousError))
        break;  // 0 -> 0 is no improvement
      chosen = lobes;
      previousError = error;
    }
    return chosen;
  }

 private:
  static std::size_t index(LobeElevation elevation) { return elevation == LobeElevation::Constant ? 0 : 1; }

  Candidate fitOne(LobeElevation elevation, int lobes, std::size_t c) {
    const auto& constant = fitted_[0];
    if (elevation == LobeElevation::Constant) {
      return fitters_[c]->fitConstant(lobes, lobes > 1 ? &constant[lobes - 2][c] : nullptr);
    }
    const Candidate* start = static_cast<int>(constant.size()) >= lobes ? &constant[lobes - 1][c] : nullptr;
    const Candidate* previous = lobes > 1 ? &fitted_[1][lobes - 2][c] : nullptr;
    return fitters_[c]->fitVarying(lobes, start, previous);
  }

  const FitOptions& options_;
  int maxLobes_;
  std::size_t channels_, samples_ = 0;
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

// The Ceres per-channel fit (FitMethod::PerChannel) of one explicit lobe count and elevation (the
// in-sample greedy sequence still grows K from 1).
FitResult fitPerChannel(const MeasuredTable& table, const FitOptions& options) {
  const auto start = Clock::now();
  const std::string label = table.sourceFile.empty() ? std::string("table") : table.sourceFile;
  const std::size_t channels = table.channelCount();
  if (channels == 0) throw Error(Error::Kind::InvalidInput, label + ": no channels to fit");
  const LobeModel range = fittedRange(table);
  const int maxLobes = options.lobes == 0 ? options.maxAutoLobes : options.lobes;
  PerChannelSequences sequences(table, options, range, maxLobes);
  checkDeterminable(sequences, options, maxLobes, label);

  const bool tryVarying = options.elevation != ElevationChoice::Constant;
  ProgressCounter progress(options.progress, channels * static_cast<std::size_t>(maxLobes) * (tryVarying ? 2 : 1));
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
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
  const int count = elevationCoefficientCount(elevation);
  FitResult result;
  result.options = options;
  result.options.progress = nullptr;
  result.model.elevation = elevation;
  result.model.minCos = range.minCos;
  result.model.maxCos = range.maxCos;
  if (table.kind == ChannelKind::Spectral) result.model.wavelengthsNm = table.wavelengthsNm;
  for (std::size_t c = 0; c < channels; ++c) {
    const std::string name = c < table.channelNames.size() ? table.channelNames[c] : std::to_string(c);
    result.model.channels.push_back(toChannel(chosen[c].x, lobes, count, name));
  }
  result.model.validate();
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

// The shared-shape model of `table` (no statistics). `warmStart`: a fit of the same table with
// fewer lobes of this kind, whose shapes the fit keeps.
struct SharedModel {
  LobeModel model;
  int evaluations = 0;
};

SharedModel sharedModel(const MeasuredTable& table, const FitOptions& options, LobeKindChoice kind,
                        const LobeModel* warmStart) {
  const std::string label = table.sourceFile.empty() ? std::string("table") : table.sourceFile;
  if (table.channelCount() == 0) throw Error(Error::Kind::InvalidInput, label + ": no channels to fit");
  detail::SharedFitConfig config;
  config.lobes = options.lobes;
  config.mirror = kind == LobeKindChoice::Mirror;
  config.lafortune = kind == LobeKindChoice::Lafortune;
  config.halfVector = kind == LobeKindChoice::HalfVector;
  config.maxExponent = options.maxExponent;
  if (warmStart && !warmStart->channels.empty()) config.startLobes = warmStart->channels[0].lobes;
  std::size_t usable = 0;
  for (std::size_t i = 0; i < table.size(); ++i) {
    if (table.incidentDirection(i).z() > 0.0 && table.outgoingDirection(i).z() > 0.0) ++usable;
  }
  if (usable == 0) {
    throw Error(Error::Kind::InvalidInput, label + ": no sample has both directions above the horizon; nothing to fit");
  }
  const std::size_t perChannel =
      1 + static_cast<std::size_t>(options.lobes) * (kind == LobeKindChoice::HalfVector ? 2 : 1);
  if (usable < perChannel) {
    throw Error(Error::Kind::InvalidArgument, label + ": " + std::to_string(usable) +
                                                  " usable sample(s) cannot determine " + std::to_string(perChannel) +
                                                  " weights per channel");
  }
  auto outcome = detail::fitSharedLobes(table, config, fittedRange(table));
  for (std::size_t c = 0; c < table.channelCount(); ++c) {
    outcome.model.channels[c].name = c < table.channelNames.size() ? table.channelNames[c] : std::to_string(c);
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
  result.options.progress = nullptr;
  result.model = std::move(fitted.model);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  for (std::size_t c = 0; c < table.channelCount(); ++c) {
    ChannelFitStats stats = evaluateFit(result.model, table, c);
    stats.solver.termination = "CONVERGENCE";
    stats.solver.usable = true;
    stats.solver.iterations = fitted.evaluations;
    stats.solver.briefReport = "shared shapes: " + std::to_string(fitted.evaluations) + " shape trials, NNLS weights";
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
};

// The options with the candidate's choices made explicit.
FitOptions explicitOptions(FitOptions options, const CandidateConfig& config) {
  options.lobes = config.lobes;
  options.elevation =
      config.elevation == LobeElevation::Constant ? ElevationChoice::Constant : ElevationChoice::Varying;
  options.kind = config.kind;
  if (config.maxExponent > 0.0) options.maxExponent = config.maxExponent;
  return options;
}

// The same, for one of many fits that run in parallel over splits.
FitOptions candidateOptions(const FitOptions& options, const CandidateConfig& config) {
  FitOptions single = explicitOptions(options, config);
  single.threads = 1;
  single.progress = nullptr;
  return single;
}

FitResult fitExplicit(const MeasuredTable& table, const FitOptions& explicitOptions, LobeKindChoice kind) {
  if (explicitOptions.method == FitMethod::Shared) return fitShared(table, explicitOptions, kind);
  return fitPerChannel(table, explicitOptions);
}

FitResult fitCandidate(const MeasuredTable& table, const FitOptions& options, const CandidateConfig& config) {
  return fitExplicit(table, candidateOptions(options, config), config.kind);
}

// The model alone, for a held-out split (the statistics of a split's fit are never shown).
LobeModel fitCandidateModel(const MeasuredTable& table, const FitOptions& options, const CandidateConfig& config,
                            const LobeModel* start = nullptr) {
  const FitOptions single = candidateOptions(options, config);
  if (options.method == FitMethod::Shared) return sharedModel(table, single, config.kind, start).model;
  return fitPerChannel(table, single).model;
}

int parameterTotal(const CandidateConfig& config, FitMethod method, std::size_t channels) {
  const int count = elevationCoefficientCount(config.elevation);
  const int perChannel = 1 + config.lobes * (method == FitMethod::Shared ? 1 : 2 * count);
  // Shared: a Lafortune lobe's n and c_xy, a half-vector lobe's n (and one more weight per channel, C_F).
  const int shapeParameters = config.kind == LobeKindChoice::Lafortune ? 2 : 1;
  const int extraWeights = config.kind == LobeKindChoice::HalfVector ? config.lobes * static_cast<int>(channels) : 0;
  const int shared = method == FitMethod::Shared ? config.lobes * shapeParameters + extraWeights : 0;
  return perChannel * static_cast<int>(channels) + shared;
}

// A kind whose score is more than this factor above the best score so far stops adding lobes:
// on the Cornell tables no lobe lowered a score by more than 1.9x (docs/fitting.md).
constexpr double kHopelessScoreFactor = 2.0;

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
  }
  return "auto";
}

LobeKindChoice parseLobeKindChoice(std::string_view name) {
  return parseByName(
      name,
      std::array{LobeKindChoice::Auto, LobeKindChoice::Mirror, LobeKindChoice::Lafortune, LobeKindChoice::HalfVector},
      "lobe kind");
}

namespace {

// The candidates fitLobes may choose between: explicit choices fix a dimension, auto ones span it.
struct CandidateSpace {
  std::vector<int> counts;
  std::vector<LobeKindChoice> kinds;
  std::vector<LobeElevation> elevations;
  bool heldOutFeasible = false;  // enough rows away from the mirror for held-out splits

  std::size_t size() const { return counts.size() * kinds.size() * elevations.size(); }
};

CandidateSpace candidateSpace(const MeasuredTable& table, const FitOptions& options) {
  const bool shared = options.method == FitMethod::Shared;
  CandidateSpace space;
  if (options.lobes > 0)
    space.counts = {options.lobes};
  else
    for (int k = 1; k <= options.maxAutoLobes; ++k) space.counts.push_back(k);
  if (!shared)
    space.kinds = {LobeKindChoice::Mirror};
  else if (options.kind != LobeKindChoice::Auto)
    space.kinds = {options.kind};
  else
    space.kinds = {LobeKindChoice::HalfVector, LobeKindChoice::Lafortune, LobeKindChoice::Mirror};  // likeliest first
  if (shared || options.elevation == ElevationChoice::Constant)
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
  if (!space.heldOutFeasible) {
    space.counts.resize(1);
    if (space.kinds.size() > 1) space.kinds = {LobeKindChoice::Mirror};  // the fewest parameters
    space.elevations.resize(1);
  }
  return space;
}

// One configuration, every choice made (auto ones without a held-out estimate: the fewest
// parameters), with its held-out estimate when asked for and feasible.
FitResult fitOneConfiguration(const MeasuredTable& table, const FitOptions& options, const CandidateSpace& space) {
  const CandidateConfig config{space.counts[0], space.elevations[0], space.kinds[0]};
  FitResult result = fitExplicit(table, explicitOptions(options, config), config.kind);
  if (options.estimateHeldOut && space.heldOutFeasible) {
    result.heldOut = estimateHeldOutError(
        table, [&](const MeasuredTable& training) { return fitCandidateModel(training, options, config); },
        options.heldOut);
  }
  return result;
}

// A scored candidate: its configuration, held-out report and the fit of each split.
struct TriedCandidate {
  CandidateConfig config;
  HeldOutReport report;
  std::vector<LobeModel> splitFits;
};
using Tried = std::vector<TriedCandidate>;

// Scores `config` on every split; split s's fit starts from starts[s] when given.
TriedCandidate scoreCandidate(const HeldOutSplits& splits, const FitOptions& options, const CandidateConfig& config,
                              const std::vector<LobeModel>* starts = nullptr) {
  TriedCandidate candidate{config, {}, std::vector<LobeModel>(splits.size())};
  candidate.report = splits.estimate([&](std::size_t s, const MeasuredTable& training) {
    candidate.splitFits[s] = fitCandidateModel(training, options, config, starts ? &(*starts)[s] : nullptr);
    return candidate.splitFits[s];
  });
  return candidate;
}

// Every (kind, elevation) sequence grows the lobe count while the held-out score falls by the
// margin; a kind scoring more than kHopelessScoreFactor times the best so far stops there. Each
// split's K-lobe fit starts from its (K-1)-lobe fit.
Tried scoreCandidates(const HeldOutSplits& splits, const FitOptions& options, const CandidateSpace& space) {
  Tried tried;
  const std::size_t total = space.size();
  std::size_t done = 0;
  double bestScore = HUGE_VAL;
  for (LobeKindChoice kind : space.kinds) {
    for (LobeElevation elevation : space.elevations) {
      double previous = HUGE_VAL;
      std::vector<LobeModel> fewer;  // the split fits of one lobe fewer
      for (int lobes : space.counts) {
        tried.push_back(scoreCandidate(splits, options, {lobes, elevation, kind}, fewer.empty() ? nullptr : &fewer));
        fewer = tried.back().splitFits;
        const double score = tried.back().report.score();
        if (options.progress) options.progress(static_cast<double>(++done) / static_cast<double>(total + 1));
        bestScore = std::min(bestScore, score);
        if (score > kHopelessScoreFactor * bestScore) break;
        if (!(score < (1.0 - options.autoMargin) * previous)) break;
        previous = score;
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
std::size_t lowerExponentCap(const HeldOutSplits& splits, const FitOptions& options, Tried& tried, std::size_t best) {
  if (options.method != FitMethod::Shared || !options.chooseMaxExponent) return best;
  for (double factor : {0.3, 0.1}) {
    CandidateConfig capped = tried[best].config;
    capped.maxExponent = std::max(kMinLobeExponent, factor * options.maxExponent);
    tried.push_back(scoreCandidate(splits, options, capped));
    if (!(tried.back().report.score() < (1.0 - options.autoMargin) * tried[best].report.score())) break;
    best = tried.size() - 1;
  }
  return best;
}

// Scores the candidates by held-out error, fits the chosen one to the whole table and lists them all.
FitResult chooseByHeldOutError(const MeasuredTable& table, const FitOptions& options, const CandidateSpace& space) {
  const std::size_t channels = table.channelCount();
  const HeldOutSplits splits(table, options.heldOut);
  Tried tried = scoreCandidates(splits, options, space);
  const std::size_t best =
      lowerExponentCap(splits, options, tried, fewestParametersWithinMargin(tried, options, channels));
  FitResult result = fitCandidate(table, options, tried[best].config);
  for (std::size_t i = 0; i < tried.size(); ++i) {
    const auto& [config, report, fits] = tried[i];
    ModelCandidate c;
    c.lobes = config.lobes;
    c.elevation = config.elevation;
    c.kind = config.kind;
    c.parameters = parameterTotal(config, options.method, channels);
    c.heldOutScore = report.score();
    c.kfoldRatio = report.kfold.ratio();
    c.elevationRatio = report.pooledElevations().ratio();
    c.seconds = report.seconds;
    c.maxExponent = options.method == FitMethod::Shared
                        ? (config.maxExponent > 0.0 ? config.maxExponent : options.maxExponent)
                        : 0.0;
    c.chosen = i == best;
    if (c.chosen) c.inSampleError = allRowsError(result.model, table).rms();
    result.candidates.push_back(c);
  }
  result.heldOut = tried[best].report;
  return result;
}

}  // namespace

FitResult fitLobes(const MeasuredTable& table, const FitOptions& options) {
  options.validate();
  table.validate();
  const auto start = Clock::now();
  if (options.method == FitMethod::Shared && options.elevation == ElevationChoice::Varying) {
    throw Error(Error::Kind::InvalidArgument,
                "fit: the shared method fits constant lobes (Lafortune lobes vary with elevation); use the per_channel "
                "method for varying ones");
  }
  const CandidateSpace space = candidateSpace(table, options);
  FitResult result =
      space.size() > 1 ? chooseByHeldOutError(table, options, space) : fitOneConfiguration(table, options, space);
  result.options = options;
  result.options.progress = nullptr;
  for (const auto& c : result.candidates) {
    if (c.chosen && c.maxExponent > 0.0) result.options.maxExponent = c.maxExponent;
  }
  result.inSampleError = allRowsError(result.model, table).rms();
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (options.progress) options.progress(1.0);
  return result;
}

}  // namespace brdfbake
