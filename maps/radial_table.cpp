#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>
#include <brdfbake/maps/radial_table.hpp>

#include <algorithm>
#include <cmath>

namespace brdfbake {

double RadialTable::atCos(double c) const { return atU(std::sqrt(std::max(0.0, (1.0 - c) * 0.5))); }

RadialTable::RadialTable(const std::function<double(double)>& profile, double tolerance, int maxSize) {
  require(tolerance > 0.0, "table tolerance must be > 0");
  auto f = [&](double u) {
    const double value = profile(1.0 - 2.0 * u * u);  // cos theta = 1 - 2 sin^2(theta/2)
    if (!std::isfinite(value)) throw Error(Error::Kind::Numerical, "radial profile is not finite");
    return value;
  };
  std::vector<double> values;
  int intervals = 256;
  for (int i = 0; i <= intervals; ++i) values.push_back(f(static_cast<double>(i) / intervals));
  while (true) {
    const double peak = std::max(1e-300, *std::max_element(values.begin(), values.end(), [](double a, double b) {
                                   return std::abs(a) < std::abs(b);
                                 }));
    std::vector<double> midpoints(intervals);
    double worst = 0.0;
    for (int i = 0; i < intervals; ++i) {
      midpoints[i] = f((i + 0.5) / intervals);
      worst = std::max(worst, std::abs(midpoints[i] - 0.5 * (values[i] + values[i + 1])));
    }
    relativeError_ = worst / std::abs(peak);
    if (relativeError_ <= tolerance || 2 * intervals + 1 > maxSize) break;
    std::vector<double> refined(2 * intervals + 1);
    for (int i = 0; i < intervals; ++i) {
      refined[2 * i] = values[i];
      refined[2 * i + 1] = midpoints[i];
    }
    refined.back() = values.back();
    values.swap(refined);
    intervals *= 2;
  }
  // Zero what the tolerance cannot tell from zero, so the table has a support the baker can use.
  const double peak =
      *std::max_element(values.begin(), values.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
  const double negligible = 0.1 * tolerance * std::abs(peak);
  int first = -1, last = -1;
  for (int i = 0; i <= intervals; ++i) {
    if (std::abs(values[i]) <= negligible) {
      values[i] = 0.0;
    } else {
      if (first < 0) first = i;
      last = i;
    }
  }
  if (first < 0) {
    minU_ = 1.0, maxU_ = 0.0;  // empty support
  } else {
    // Linear interpolation is non-zero strictly between the neighbours of the first and last non-zero entries.
    minU_ = std::max(0, first - 1) / static_cast<double>(intervals);
    maxU_ = std::min(intervals, last + 1) / static_cast<double>(intervals);
  }
  // dω = 2 pi sin(theta) dtheta = 8 pi u du with u = sin(theta/2): integrate the linear
  // interpolant v0 + (v1 - v0) t over each interval exactly.
  const double h = 1.0 / intervals;
  std::vector<double> cumulative(intervals + 1, 0.0);  // of |f|, for the half-energy angle
  for (int i = 0; i < intervals; ++i) {
    const double u0 = i * h, v0 = values[i], v1 = values[i + 1];
    // ∫_0^h (v0 + (v1 - v0) t/h) (u0 + t) dt
    const double piece = 8.0 * kPi * (v0 * (u0 * h + 0.5 * h * h) + (v1 - v0) * (0.5 * u0 * h + h * h / 3.0));
    energy_ += piece;
    cumulative[i + 1] = cumulative[i] + std::abs(piece);
  }
  if (cumulative.back() > 0.0) {
    const auto half = std::lower_bound(cumulative.begin(), cumulative.end(), 0.5 * cumulative.back());
    const double u = std::min(1.0, static_cast<double>(half - cumulative.begin()) * h);
    halfEnergyAngle_ = 2.0 * std::asin(u);
  }
  values_.assign(values.begin(), values.end());
  scale_ = intervals;
}

}  // namespace brdfbake
