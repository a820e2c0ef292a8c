#pragma once
// Exact integrals of radially symmetric densities over (rectangle ∩ unit disc), by Green's
// theorem. For a density rho(r) on the disc let h(R) = ∫_0^R rho(r) r dr. Then
//   ∫∫_{A ∩ disc} rho dA = ∮ h(r)/r^2 (x dy - y dx)
// over the boundary of A ∩ disc, run counter-clockwise. The boundary consists of chords (parts of
// the rectangle's edges inside the disc) and arcs of the unit circle. On an arc the integrand is
// h(1) dphi; on a straight segment at signed distance d from the origin, x dy - y dx = d ds with
// s the coordinate along the segment, so each density only has to supply
//   chord(d, s0, s1) = ∫_{s0}^{s1} d h(r)/r^2 ds,  r^2 = d^2 + s^2.

#include <brdfbake/core/math.hpp>

#include <algorithm>

namespace brdfbake::detail {

struct RadialDensity {
  double (*chord)(double d, double s0, double s1);
  double arcWeight;  // h(1)
};

/// Area: rho = 1, h = R^2/2.
inline constexpr RadialDensity kAreaDensity{[](double d, double s0, double s1) { return 0.5 * d * (s1 - s0); }, 0.5};

/// Integral of `density` over [x0, x1] x [y0, y1] ∩ unit disc (x0 <= x1, y0 <= y1).
double integrateOverDiscPart(double x0, double x1, double y0, double y1, const RadialDensity& density);

/// Fraction of [x0, x1] x [y0, y1] inside the unit disc; rectangles wholly inside or outside
/// return without integrating.
inline double discCoverage(double x0, double x1, double y0, double y1) {
  const double far = std::max(x0 * x0, x1 * x1) + std::max(y0 * y0, y1 * y1);
  if (far <= 1.0) return 1.0;
  const double cx = std::clamp(0.0, x0, x1), cy = std::clamp(0.0, y0, y1);
  if (cx * cx + cy * cy >= 1.0) return 0.0;
  return integrateOverDiscPart(x0, x1, y0, y1, kAreaDensity) / ((x1 - x0) * (y1 - y0));
}

}  // namespace brdfbake::detail
