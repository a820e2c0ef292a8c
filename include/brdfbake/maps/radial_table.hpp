#pragma once
/// @file
/// A radially symmetric profile tabulated finely enough to stand in for the model.

#include <algorithm>
#include <cstddef>
#include <functional>
#include <vector>

namespace brdfbake {

/// Tabulates f(cos theta) over u = sin(theta / 2) in [0, 1], uniformly: u is computed from a
/// direction d and the axis a without trigonometry (u = |d - a| / 2) and resolves sharp peaks at
/// theta = 0 as finely as the rest. The table doubles until linear interpolation is within
/// `tolerance` x max|f| at every midpoint (or `maxSize` entries). Values below tolerance/10 x
/// max|f| are set to zero, which gives the table a support [minU, maxU] outside which it is
/// exactly zero: the baker skips texels that lie wholly outside it.
class RadialTable {
 public:
  explicit RadialTable(const std::function<double(double)>& profile, double tolerance = 1e-6,
                       int maxSize = (1 << 20) + 1);

  /// A read-only view for hot loops: plain pointer and bounds held in registers.
  struct View {
    const float* values;
    double scale;       // intervals
    long lastInterval;  // intervals - 1
    double operator()(double u) const {
      const double f = std::min(std::max(u, 0.0), 1.0) * scale;
      const long i = std::min(static_cast<long>(f), lastInterval);
      const double w = f - static_cast<double>(i);
      return values[i] + w * (values[i + 1] - values[i]);
    }
  };
  View view() const { return {values_.data(), scale_, static_cast<long>(values_.size()) - 2}; }

  /// Interpolated value at u (clamped to [0, 1]).
  double atU(double u) const { return view()(u); }
  /// Value for the cosine of the angle to the axis.
  double atCos(double c) const;

  int size() const { return static_cast<int>(values_.size()); }
  /// The support in u = sin(theta/2): the table is exactly zero for u outside [minU, maxU]
  /// (minU > maxU when it is zero everywhere).
  double minU() const { return minU_; }
  double maxU() const { return maxU_; }
  /// ∫ f dω over the sphere (sr), exact for the table's piecewise-linear interpolant.
  double energy() const { return energy_; }
  /// Angle from the axis (radians) within which half of |f|'s integral lies.
  double halfEnergyAngle() const { return halfEnergyAngle_; }
  /// Largest midpoint interpolation error found, relative to max|f|.
  double relativeError() const { return relativeError_; }

 private:
  std::vector<float> values_;
  double scale_ = 0.0;
  double relativeError_ = 0.0;
  double minU_ = 0.0, maxU_ = 0.0;
  double energy_ = 0.0, halfEnergyAngle_ = 0.0;
};

}  // namespace brdfbake
