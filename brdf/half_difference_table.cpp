#include <brdfbake/brdf/half_difference_table.hpp>
#include <brdfbake/core/error.hpp>

#include <algorithm>

namespace brdfbake {

void HalfDifferenceTableShape::validate() const {
  if (empty()) return;
  require(halfAngleKnots >= 2 && halfAngleKnots <= 64, "half-difference table: 2 to 64 knots in theta_h");
  require(differenceDegree >= 0 && differenceDegree <= kMaxTableDegree,
          "half-difference table: degree in theta_d from 0 to " + std::to_string(kMaxTableDegree));
}

HalfDifferenceBasis HalfDifferenceBasis::at(const HalfDifferenceTableShape& shape, double thetaH, double thetaD) {
  constexpr double kRightAngle = 0.5 * kPi;
  HalfDifferenceBasis basis;
  const int knots = shape.halfAngleKnots;
  const double x = std::sqrt(clampFinite(thetaH, 0.0, kRightAngle) / kRightAngle) * (knots - 1);
  basis.knot = std::min(static_cast<int>(x), knots - 2);
  basis.upperHat = x - basis.knot;
  basis.lowerHat = 1.0 - basis.upperHat;
  basis.degree = shape.differenceDegree;
  bernsteinWeights(basis.degree + 1, clampFinite(thetaD, 0.0, kRightAngle) / kRightAngle, basis.bernstein);
  return basis;
}

double HalfDifferenceBasis::logValue(const std::vector<double>& coefficients) const {
  double sum = 0.0;
  forEachTerm([&](int index, double value) { sum += coefficients[static_cast<std::size_t>(index)] * value; });
  return sum;
}

}  // namespace brdfbake
