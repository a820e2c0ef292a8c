#pragma once
/// @file
/// A radially symmetric profile tabulated finely enough to stand in for the model.

#include <functional>
#include <vector>

namespace brdfbake {

/// Tabulates f(cos theta) over u = sin(theta / 2) in [0, 1], uniformly: u is computed from a
/// direction d and the axis a without trigonometry (u = |d - a| / 2) and resolves sharp peaks at
/// theta = 0 as finely as the rest. The table doubles until linear interpolation is within
/// `tolerance` x max|f| at every midpoint (or `maxSize` entries).
class RadialTable {
 public:
  explicit RadialTable(const std::function<double(double)>& profile, double tolerance = 1e-6,
                       int maxSize = (1 << 20) + 1);

  /// Interpolated value at u (clamped to [0, 1]).
  double atU(double u) const {
    const double f = (u < 0.0 ? 0.0 : (u > 1.0 ? 1.0 : u)) * scale_;
    const auto i = static_cast<std::size_t>(f);
    if (i + 1 >= values_.size()) return values_.back();
    const double w = f - static_cast<double>(i);
    return values_[i] + w * (values_[i + 1] - values_[i]);
  }
  /// Value for the cosine of the angle to the axis.
  double atCos(double c) const;

  int size() const { return static_cast<int>(values_.size()); }
  /// Largest midpoint interpolation error found, relative to max|f|.
  double relativeError() const { return relativeError_; }

 private:
  std::vector<float> values_;
  double scale_ = 0.0;
  double relativeError_ = 0.0;
};

}  // namespace brdfbake
