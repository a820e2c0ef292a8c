// One channel of the per-channel Ceres fit (per_channel_cost.hpp): its samples, the model's value and the
// cost function of all its samples.
#include "per_channel_cost.hpp"

#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <type_traits>

namespace brdfbake::detail {

namespace {

// One lobe's value at sample s from its parameters p (the weight's `count` values, then the
// exponent's), through the same formulas as LobeModel. Constant lobes are optimised as C and n
// themselves (bounds C >= 0, 1 <= n <= 1e5); varying lobes as ln C_j and ln n_j (bounds
// 1e-12 <= C_j <= 1e6, 1 <= n_j <= 1e5), the natural scale of their geometric interpolation, with the
// sample's Bernstein weights precomputed.
double lobeValue(const double* p, int count, const FitSample& s) {
  if (!(s.cosToMirror > 0.0)) return 0.0;
  const double weight = count == 1 ? p[0] : geometricBlend(p, s.bernstein.data(), count);
  const double exponent = count == 1 ? p[1] : geometricBlend(p + count, s.bernstein.data(), count);
  return normalizedLobeOfLog(weight, exponent, s.logCosToMirror);
}

// Every sample's residual of one channel in one cost function, with its Jacobian: one block instead of
// one per sample, whose preparing, checking and copying by Ceres was a quarter of the fit's time. The
// residual of sample i is r_i = cbrt(cos theta_i f_i + eps) - target_i under the robust loss rho, applied
// here as Ceres applies it to a block of one residual whose rho'' <= 0 (Cauchy, Huber, none: Ceres'
// Corrector, which leaves out Triggs et al. 2000's curvature term there): the residual sqrt(rho'_i) r_i,
// its Jacobian scaled by sqrt(rho'_i). One more residual, sqrt(sum_i (rho_i - rho'_i r_i^2)) (>= 0 for
// a concave rho with rho(0) = 0) with a zero Jacobian row, makes Ceres' cost half the sum of all squares
// = sum 1/2 rho(r_i^2), as with a loss per block: the same model, gradient and cost as a block per
// sample. A varying lobe's weight and exponent depend on the view's elevation only, so they are
// blended once per elevation of the table (10 on the Cornell grid) with Jets of the lobe's 2 Count
// parameters (lobes share no parameter), not once per sample.
template <int Count>
class ChannelCost final : public ceres::CostFunction {
 public:
  ChannelCost(const ChannelData& data, int lobes, const ceres::LossFunction* loss)
      : data_(data), lobes_(lobes), loss_(loss) {
    set_num_residuals(static_cast<int>(data.samples.size()) + 1);
    mutable_parameter_block_sizes()->push_back(parameterCount(lobes, Count));
    last_.root.resize(data.samples.size());
    last_.scale.resize(data.samples.size());
    last_.residual.resize(data.samples.size());
    std::map<double, std::size_t> index;
    for (const auto& sample : data.samples) {
      const auto [it, added] = index.emplace(sample.u, elevations_.size());
      if (added) elevations_.push_back(sample.bernstein);
      elevationOf_.push_back(it->second);
    }
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    // Trial steps need the residuals only: plain doubles there, Jets where the Jacobian is asked for.
    if (jacobians && jacobians[0])
      return evaluateAs<ceres::Jet<double, 2 * Count>>(parameters[0], residuals, jacobians[0]);
    return evaluateAs<double>(parameters[0], residuals, nullptr);
  }

 private:
  template <class T>
  bool evaluateAs(const double* x, double* residuals, double* jacobian) const {
    constexpr bool withJacobian = !std::is_same_v<T, double>;
    const int size = parameterCount(lobes_, Count);
    const std::size_t elevations = elevations_.size(), samples = data_.samples.size();
    const bool cached = withJacobian && std::equal(x, x + size, last_.x.begin(), last_.x.end());
    if (!cached) last_.x.clear();                            // filled again below if this evaluation succeeds
    const std::vector<T> blended = blendedParameters<T>(x);  // [lobe][elevation] weight, exponent
    double slack = 0.0;
    for (std::size_t i = 0; i < samples; ++i) {
      const FitSample& s = data_.samples[i];
      double* row = withJacobian ? jacobian + i * static_cast<std::size_t>(size) : nullptr;
      double f = diffuseTerm(x[0]);
      if constexpr (withJacobian) row[0] = diffuseTerm(1.0);
      for (int k = 0; k < lobes_; ++k) {
        const std::size_t at = 2 * (static_cast<std::size_t>(k) * elevations + elevationOf_[i]);
        const T value =
            s.cosToMirror > 0.0 ? normalizedLobeOfLog(blended[at], blended[at + 1], s.logCosToMirror) : T(0.0);
        if constexpr (withJacobian) {
          f += value.a;
          std::copy(value.v.data(), value.v.data() + 2 * Count, row + 1 + k * 2 * Count);
        } else {
          f += value;
        }
      }
      if (!cached) {
        last_.root[i] = cubeRoot(s.cosIn * f + data_.eps);
        const double r = last_.root[i] - s.target;
        const Robust robust = robustified(r);
        last_.scale[i] = robust.scale;
        last_.residual[i] = robust.scale * r;
        slack += robust.slack;
        if (!std::isfinite(last_.residual[i])) return false;
      }
      residuals[i] = last_.residual[i];
      if constexpr (withJacobian) {
        const double root = last_.root[i];
        const double scale = last_.scale[i] * s.cosIn / (3.0 * root * root);  // d residual / d f
        double sum = 0.0;                                                     // not finite if an entry is not
        for (int j = 0; j < size; ++j) sum += (row[j] *= scale);
        // A step that overflows is rejected by the solver (not an error): report it as a failed evaluation.
        if (!std::isfinite(sum)) return false;
      }
    }
    residuals[samples] = cached ? last_.slackRoot : std::sqrt(slack);
    if (!std::isfinite(residuals[samples])) return false;
    if constexpr (withJacobian) std::fill_n(jacobian + samples * static_cast<std::size_t>(size), size, 0.0);
    if (!cached) last_.x.assign(x, x + size), last_.slackRoot = residuals[samples];
    return true;
  }

  // Each lobe's weight and exponent at each elevation (as Jets of the lobe's parameters, or values).
  template <class T>
  std::vector<T> blendedParameters(const double* x) const {
    std::vector<T> blended(2 * static_cast<std::size_t>(lobes_) * elevations_.size());
    for (int k = 0; k < lobes_; ++k) {
      const double* p = x + 1 + k * 2 * Count;
      T q[2 * Count];
      for (int j = 0; j < 2 * Count; ++j) {
        if constexpr (std::is_same_v<T, double>) {
          q[j] = p[j];
        } else {
          q[j] = T(p[j], j);
        }
      }
      for (std::size_t e = 0; e < elevations_.size(); ++e) {
        const std::size_t at = 2 * (static_cast<std::size_t>(k) * elevations_.size() + e);
        blended[at] = Count == 1 ? q[0] : geometricBlend(q, elevations_[e].data(), Count);
        blended[at + 1] = Count == 1 ? q[1] : geometricBlend(q + Count, elevations_[e].data(), Count);
      }
    }
    return blended;
  }

  // The factor sqrt(rho'(r^2)) on a residual r and its Jacobian, and rho(r^2) - rho'(r^2) r^2, what
  // the scaled square leaves of rho (1 and 0 without a loss).
  struct Robust {
    double scale = 1.0, slack = 0.0;
  };
  Robust robustified(double r) const {
    if (!loss_) return {};
    double rho[3];
    loss_->Evaluate(r * r, rho);
    return {std::sqrt(rho[1]), std::max(0.0, rho[0] - rho[1] * r * r)};
  }

  const ChannelData& data_;
  int lobes_;
  const ceres::LossFunction* loss_;
  // The last successful evaluation, per sample. Ceres evaluates a trial step's residuals, then, if it
  // takes the step, the Jacobian at the same parameters, which reuses the cube roots and the loss (the
  // loss's logarithm was a sixth of the fit's time). So one ChannelCost serves one Problem, evaluated
  // in sequence (one residual block: Ceres never evaluates it from two threads at once).
  struct Evaluation {
    std::vector<double> x, root, scale, residual;
    double slackRoot = 0.0;
  };
  mutable Evaluation last_;
  std::vector<std::array<double, kVaryingCount>> elevations_;  // Bernstein weights of each elevation
  std::vector<std::size_t> elevationOf_;                       // each sample's elevation
};

}  // namespace

ChannelData channelData(const MeasuredTable& table, std::size_t channel, const LobeModel& range) {
  ChannelData data;
  double maxWeighted = 0.0;
  for (std::size_t i = 0; i < table.size(); ++i) {
    const Vec3 wi = table.incidentDirection(i), wo = table.outgoingDirection(i);
    if (!(wi.z() > 0.0) || !(wo.z() > 0.0)) continue;
    const double f = table.values(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(channel));
    const double cosToMirror = reflect(wo, Vec3(Vec3::UnitZ())).dot(wi);
    FitSample sample{wi.z(),      range.elevationCoordinate(wo.z()),
                     cosToMirror, cosToMirror > 0.0 ? std::log(cosToMirror) : 0.0,
                     0.0,         {}};
    bernsteinWeights(kVaryingCount, sample.u, sample.bernstein.data());
    data.samples.push_back(sample);
    data.measured.push_back(f);
    maxWeighted = std::max(maxWeighted, std::abs(wi.z() * f));
    data.signal += wi.z() * std::max(f, 0.0);
  }
  data.eps = std::max(1e-6 * maxWeighted, 1e-12);
  for (std::size_t i = 0; i < data.samples.size(); ++i) {
    auto& s = data.samples[i];
    s.target = cubeRoot(s.cosIn * data.measured[i] + data.eps);
    data.maxTarget = std::max(data.maxTarget, std::abs(s.target));
  }
  return data;
}

double channelValue(const double* x, int lobes, int count, const FitSample& s) {
  double value = diffuseTerm(x[0]);
  for (int k = 0; k < lobes; ++k) value += lobeValue(x + 1 + k * 2 * count, count, s);
  return value;
}

ceres::CostFunction* makeChannelCost(const ChannelData& data, int lobes, int count, const ceres::LossFunction* loss) {
  if (count == 1) return new ChannelCost<1>(data, lobes, loss);
  if (count == kVaryingCount) return new ChannelCost<kVaryingCount>(data, lobes, loss);
  throw Error(Error::Kind::InvalidArgument, "fit: unsupported coefficient count " + std::to_string(count));
}

}  // namespace brdfbake::detail
