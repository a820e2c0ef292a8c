#pragma once
/// @file
/// Real spherical harmonics, orthonormal over the sphere (∫ Y_i Y_j dω = delta_ij), indexed
/// i = l (l + 1) + m for l = 0..order, m = -l..l. Y_l0 = sqrt((2l+1)/(4 pi)) P_l(z); m > 0 carry
/// cos(m phi), m < 0 sin(|m| phi), with phi = atan2(y, x) about +z. Values come from the stable
/// normalised Legendre recurrences, so orders in the hundreds neither overflow nor lose accuracy.

#include <brdfbake/core/color.hpp>
#include <brdfbake/core/math.hpp>

#include <vector>

namespace brdfbake {

/// (order + 1)^2.
inline int shCount(int order) { return (order + 1) * (order + 1); }
/// l (l + 1) + m.
inline int shIndex(int l, int m) { return l * (l + 1) + m; }

/// Writes Y_i(direction) for every i < shCount(order) to `out`. `direction` must be unit length.
void evaluateShBasis(int order, const Vec3& direction, double* out);

/// Coefficients of an RGB function on the sphere up to `order`.
struct ShExpansion {
  int order = 0;
  std::vector<Rgb> coefficients;  ///< shCount(order) entries

  /// Σ_i c_i Y_i(direction); `scratch` must hold shCount(order) doubles.
  Rgb evaluate(const Vec3& direction, double* scratch) const;
  /// Multiplies band l by lambda[l] (Funk-Hecke: convolution with a zonal lobe).
  void convolve(const std::vector<double>& lambda);
};

}  // namespace brdfbake
