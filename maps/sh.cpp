#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/sh.hpp>

#include <cmath>

namespace brdfbake {

void evaluateShBasis(int order, const Vec3& d, double* out) {
  const double x = d.x(), y = d.y(), z = d.z();
  // Normalised associated Legendre values without the sin^m(theta) factor, Q_lm, with
  // Y_l0 = Q_l0, Y_l,+-m = sqrt2 Q_lm (Re, Im)(x + i y)^m. Recurrences (all normalised):
  //   Q_00 = 1/sqrt(4 pi), Q_mm = -sqrt((2m+1)/(2m)) Q_{m-1,m-1}, Q_{m+1,m} = sqrt(2m+3) z Q_mm,
  //   Q_lm = a_lm (z Q_{l-1,m} - b_lm Q_{l-2,m}),
  //   a_lm = sqrt((4l^2 - 1)/(l^2 - m^2)), b_lm = sqrt(((l-1)^2 - m^2)/(4(l-1)^2 - 1)).
  const double sqrt2 = std::sqrt(2.0);
  double qmm = 1.0 / std::sqrt(kFourPi);
  double cm = 1.0, sm = 0.0;  // Re and Im of (x + iy)^m
  for (int m = 0; m <= order; ++m) {
    if (m > 0) {
      qmm *= -std::sqrt((2.0 * m + 1.0) / (2.0 * m));
      const double c = cm * x - sm * y, s = cm * y + sm * x;
      cm = c, sm = s;
    }
    const double cosPart = m == 0 ? 1.0 : sqrt2 * cm, sinPart = sqrt2 * sm;
    auto store = [&](int l, double q) {
      if (m == 0) {
        out[shIndex(l, 0)] = q;
      } else {
        out[shIndex(l, m)] = q * cosPart;
        out[shIndex(l, -m)] = q * sinPart;
      }
    };
    double q2 = qmm;  // Q_{l-2,m}
    store(m, qmm);
    if (m == order) break;
    double q1 = std::sqrt(2.0 * m + 3.0) * z * qmm;  // Q_{m+1,m}
    store(m + 1, q1);
    for (int l = m + 2; l <= order; ++l) {
      const double l2 = static_cast<double>(l) * l, m2 = static_cast<double>(m) * m, lm1 = l - 1.0;
      const double a = std::sqrt((4.0 * l2 - 1.0) / (l2 - m2));
      const double b = std::sqrt((lm1 * lm1 - m2) / (4.0 * lm1 * lm1 - 1.0));
      const double q = a * (z * q1 - b * q2);
      store(l, q);
      q2 = q1, q1 = q;
    }
  }
}

Rgb ShExpansion::evaluate(const Vec3& direction, double* scratch) const {
  evaluateShBasis(order, direction, scratch);
  double r = 0.0, g = 0.0, b = 0.0;
  const int n = shCount(order);
  for (int i = 0; i < n; ++i) {
    r += coefficients[i][0] * scratch[i];
    g += coefficients[i][1] * scratch[i];
    b += coefficients[i][2] * scratch[i];
  }
  return {r, g, b};
}

void ShExpansion::convolve(const std::vector<double>& lambda) {
  require(static_cast<int>(lambda.size()) > order, "convolve: need a coefficient per band");
  for (int l = 0; l <= order; ++l)
    for (int m = -l; m <= l; ++m) coefficients[shIndex(l, m)] *= lambda[l];
}

}  // namespace brdfbake
