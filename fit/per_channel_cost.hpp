#pragma once
// Internal to fit/: one channel of the per-channel Ceres fit (docs/fitting.md, "Per-channel fits with
// Ceres"): its fitted samples, the model's value at a sample from the optimiser's parameters, and the
// cost function of all its samples.
#include <brdfbake/fit/lobe_fit.hpp>
#include <brdfbake/measured/measured_table.hpp>

#include <array>
#include <cstddef>
#include <vector>

namespace ceres {
class CostFunction;
class LossFunction;
}  // namespace ceres

namespace brdfbake::detail {

inline constexpr int kVaryingCount = elevationCoefficientCount(LobeElevation::Varying);

// Per-sample quantities the residual needs; the geometry is data, never differentiated.
struct FitSample {
  double cosIn;           // cos theta_i, the cosine weight
  double u;               // elevation coordinate of the view (outgoing) direction (LobeModel::elevationCoordinate)
  double cosToMirror;     // r_v . l
  double logCosToMirror;  // ln(r_v . l) where r_v . l > 0
  double target;          // cbrt(cos theta_i f_measured + eps)
  std::array<double, kVaryingCount> bernstein;  // Bernstein weights at u
};

// One channel's fitted samples (light and view above the horizon).
struct ChannelData {
  std::vector<FitSample> samples;
  std::vector<double> measured;  // f_i of the fitted samples
  double eps = 0.0;
  double maxTarget = 0.0;
  double signal = 0.0;  // sum of cos theta_i max(f_i, 0): how bright the channel is
};

// The fitted samples of channel `channel` of `table`; `range` gives the elevation coordinate (fittedRange).
ChannelData channelData(const MeasuredTable& table, std::size_t channel, const LobeModel& range);

// Layout of the parameter block: [k_d, lobe 0: weight coefficients, exponent coefficients, lobe 1: ...].
constexpr int parameterCount(int lobes, int count) { return 1 + lobes * 2 * count; }

// The channel's BRDF at sample s from the optimiser's parameters x (see parameterCount): k_d / pi plus
// each lobe, constant lobes as C and n themselves, varying ones as ln C_j and ln n_j (`count` = 1 or
// kVaryingCount coefficients per lobe parameter).
double channelValue(const double* x, int lobes, int count, const FitSample& s);

// The cost function of every sample of `data` for `lobes` lobes of `count` coefficients, the robust
// loss `loss` (Cauchy, Huber or none: rho'' <= 0) applied inside (per_channel_cost.cpp); one residual
// block of samples + 1 residuals over one parameter block of parameterCount(lobes, count), whose
// Ceres cost is sum_i 1/2 rho(r_i^2). Keeps references to `data` and `loss`; evaluate it from one
// thread at a time. Throws Error(InvalidArgument) for another `count`.
ceres::CostFunction* makeChannelCost(const ChannelData& data, int lobes, int count, const ceres::LossFunction* loss);

}  // namespace brdfbake::detail
