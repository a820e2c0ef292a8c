#pragma once
/// @file
/// Converting a Phong (R.V) exponent to a Blinn (N.H) exponent (Zimmons & Bastos 1999 section 5.1.1).
///
/// In the plane of incidence R.V = 2 (N.H)^2 - 1, so (R.V)^n = (N.H)^n' with
///   n' = n log(2 (N.H)^2 - 1) / log(N.H).
/// The ratio is 0/0 at N.H = 1 (limit 4) and has no value for N.H <= 1/sqrt 2, where R.V <= 0 and
/// the Phong lobe is zero. The conversion is exact only in the plane of incidence.

#include <cmath>
#include <optional>
#include <string_view>

namespace brdfbake {

/// How a Blinn-Phong map meant to match a Phong one chooses its exponent.
enum class BlinnConversion {
  Exact,  ///< n' = n ratio(N.H) per texel: matches Phong exactly in the plane of incidence
  FourN,  ///< the classic constant n' = 4 n (the ratio's limit at N.H = 1)
  Fit,    ///< the constant n' minimising the L2 difference of the lobes (blinnFitExponent)
};

std::string_view toString(BlinnConversion policy);
/// "exact", "4n", "fit"; throws Error(InvalidArgument).
BlinnConversion parseBlinnConversion(std::string_view name);

/// log(2 x^2 - 1) / log(x) for x in (1/sqrt 2, 1], computed stably with log1p (4 at x = 1);
/// nullopt for x <= 1/sqrt 2 or x > 1 or NaN.
template <class T>
std::optional<T> blinnExponentRatio(const T& nDotH) {
  using std::log1p;
  const T e = T(1) - nDotH;  // x = 1 - e
  if (!(e >= T(0)) || !(nDotH > T(0)) || !(T(2) * nDotH * nDotH - T(1) > T(0))) return std::nullopt;
  if (e == T(0)) return T(4);
  // 2x^2 - 1 = 1 - 2e(2 - e);  log(x) = log1p(-e)
  return T(log1p(-T(2) * e * (T(2) - e)) / log1p(-e));
}

/// The constant Blinn exponent n' minimising  ∫ ((R.V)^n_+ - (N.H)^n')^2 dω  over the hemisphere
/// of view directions for a light along the normal, where R.V = cos theta_v and
/// N.H = cos(theta_v / 2). Found by golden-section search on log n' (it is close to 4n for large
/// n). Throws Error(InvalidArgument) for n <= 0 or non-finite n.
double blinnFitExponent(double phongExponent);

}  // namespace brdfbake
