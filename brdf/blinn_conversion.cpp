#include <brdfbake/brdf/blinn_conversion.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>
#include <brdfbake/core/named_values.hpp>

#include <string>

namespace brdfbake {

std::string_view toString(BlinnConversion policy) {
  switch (policy) {
    case BlinnConversion::Exact:
      return "exact";
    case BlinnConversion::FourN:
      return "4n";
    case BlinnConversion::Fit:
      return "fit";
  }
  return "unknown";
}

BlinnConversion parseBlinnConversion(std::string_view name) {
  return parseByName(name, std::array{BlinnConversion::Exact, BlinnConversion::FourN, BlinnConversion::Fit},
                     "conversion");
}

namespace {

// ∫_0^{pi/2} (cos^n t - cos^m (t/2))^2 sin t dt * 2 pi, by composite Simpson on a grid that
// resolves the lobe (width ~ 1/sqrt(n)).
double lobeDistanceSquared(double n, double m) {
  const int intervals = 2 * static_cast<int>(std::clamp(200.0 * std::sqrt(n + 1.0), 400.0, 200000.0));
  const double h = (kPi / 2) / intervals;
  double sum = 0.0;
  for (int i = 0; i <= intervals; ++i) {
    const double t = i * h;
    const double diff = std::pow(std::cos(t), n) - std::pow(std::cos(t / 2), m);
    const double w = (i == 0 || i == intervals) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w * diff * diff * std::sin(t);
  }
  return kTwoPi * sum * h / 3.0;
}

}  // namespace

double blinnFitExponent(double n) {
  require(std::isfinite(n) && n > 0.0, "Phong exponent must be finite and > 0, got " + std::to_string(n));
  // Golden-section search on log m over [log n, log 16n]; the objective is unimodal there.
  double a = std::log(n), b = std::log(16.0 * n);
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = lobeDistanceSquared(n, std::exp(c)), fd = lobeDistanceSquared(n, std::exp(d));
  while (b - a > 1e-7) {
    if (fc < fd) {
      b = d, d = c, fd = fc;
      c = b - g * (b - a);
      fc = lobeDistanceSquared(n, std::exp(c));
    } else {
      a = c, c = d, fc = fd;
      d = a + g * (b - a);
      fd = lobeDistanceSquared(n, std::exp(d));
    }
  }
  return std::exp(0.5 * (a + b));
}

}  // namespace brdfbake
