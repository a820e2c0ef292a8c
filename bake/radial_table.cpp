#include <brdfbake/bake/radial_table.hpp>
#include <brdfbake/core/error.hpp>

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
    const double peak = std::max(1e-300, *std::max_element(values.begin(), values.end(),
                                                          [](double a, double b) { return std::abs(a) < std::abs(b); }));
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
  values_.assign(values.begin(), values.end());
  scale_ = intervals;
}

}  // namespace brdfbake
