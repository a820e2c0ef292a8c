#pragma once
// Reference values for reflectance tests, written out independently of the library: Heidrich's
// dielectric Fresnel formula and a microfacet BRDF's directional albedo by quadrature.
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/core/math.hpp>

#include <cmath>

namespace brdfbake::test {

/// The unpolarised Fresnel reflectance of a dielectric of relative index `eta` at cos(incidence)
/// `c`: Eq. 13 of Heidrich 2000 (1 at grazing incidence, c <= 0).
inline double eq13(double c, double eta) {
  if (c <= 0.0) return 1.0;
  const double g = std::sqrt(eta * eta + c * c - 1.0);
  const double a = (g - c) / (g + c), b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
  return 0.5 * a * a * (1.0 + b * b);
}

/// The directional albedo of `m`'s red channel seen from `thetaV` off the normal: the integral of
/// f(l, v) (n.l) over the hemisphere of l, in half-vector coordinates (dw_l = 4 (v.h) dw_h), by the
/// midpoint rule on 1500 theta_h by `phiSteps` phi_h cells.
inline double halfVectorAlbedo(const CookTorranceMaterial& m, double thetaV, int phiSteps) {
  const Vec3 n = Vec3::UnitZ(), v(std::sin(thetaV), 0.0, std::cos(thetaV));
  const int nt = 1500, np = phiSteps;
  const double dt = (kPi / 2) / nt, dp = kTwoPi / np;
  double sum = 0.0;
  for (int i = 0; i < nt; ++i) {
    const double t = (i + 0.5) * dt;
    for (int j = 0; j < np; ++j) {
      const double p = (j + 0.5) * dp;
      const Vec3 h(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
      const double vh = v.dot(h);
      if (vh <= 0) continue;
      const Vec3 l = 2 * vh * h - v;
      if (l.z() <= 0) continue;
      sum += m.brdf(n, v, l)[0] * l.z() * 4 * vh * std::sin(t);
    }
  }
  return sum * dt * dp;
}

}  // namespace brdfbake::test
