#pragma once
/// @file
/// Fresnel reflectance of smooth interfaces: the dielectric formula of Heidrich 2000 Eq. 13, the exact
/// conductor formula for a complex index n + i k, and the per-channel Fresnel term the material
/// models share (docs/materials.md, "Fresnel").
///
/// Conventions used throughout:
/// - `c` is the cosine of the angle of incidence: the angle between the (micro)facet normal and the
///   view direction, which for a mirror equals the angle to the light. A mirror uses c = N.V; a
///   microfacet model uses c = V.H. Values outside [0, 1] are clamped (c < 0 counts as grazing).
/// - Light arrives from a medium of index 1 (air); `eta` is the relative index of the other side.
///   eta < 1 models light leaving a denser medium, with total internal reflection (F = 1) beyond
///   the critical angle asin(eta).
/// - Light is unpolarised: F is the mean of the s and p reflectances. F is in [0, 1].
/// - The formulas are templated on the scalar so ceres::Jet can reuse them; their branches only
///   select between finite expressions.

#include <brdfbake/brdf/material.hpp>
#include <brdfbake/core/color.hpp>
#include <brdfbake/core/math.hpp>

#include <span>
#include <string_view>
#include <vector>

namespace brdfbake {

namespace detail {
template <class T>
T clampUnit(const T& c) {
  return c < T(0) ? T(0) : (c > T(1) ? T(1) : c);
}
}  // namespace detail

/// Schlick's approximation (Schlick 1994), what Filament and most real-time engines use:
///   F = f0 + (1 - f0) (1 - c)^5,  c clamped to [0, 1].
template <typename T>
T fresnelSchlick(const T& cosTheta, const T& f0) {
  const T m = T(1) - detail::clampUnit(cosTheta);
  const T m2 = m * m;
  return f0 + (T(1) - f0) * (m2 * m2 * m);
}

/// Dielectric Fresnel reflectance, Heidrich 2000 Eq. 13:
///   F = (g - c)^2 / (2 (g + c)^2) [1 + (c (g + c) - 1)^2 / (c (g - c) + 1)^2],
///   g^2 = eta^2 + c^2 - 1.
/// g^2 <= 0 is total internal reflection: F = 1 (g^2 = 0 is the critical angle, where the formula
/// also gives 1). eta = 1 (no interface) gives F = 0 at every angle, grazing included (the formula
/// is 0/0 there). F(1) = ((eta - 1) / (eta + 1))^2 and F(0) = 1 for eta != 1.
/// `eta` must be finite and > 0 (not checked here; FresnelTerm checks).
template <class T>
T fresnelDielectric(const T& cosTheta, const T& eta) {
  using std::sqrt;
  if (eta == T(1)) return T(0);
  const T c = detail::clampUnit(cosTheta);
  const T g2 = eta * eta + c * c - T(1);
  if (!(g2 > T(0))) return T(1);
  const T g = sqrt(g2);
  const T a = (g - c) / (g + c);                            // g + c > 0 here
  const T b = (c * (g + c) - T(1)) / (c * (g - c) + T(1));  // c (g - c) + 1 = c g + 1 - c^2 > 0
  return T(0.5) * a * a * (T(1) + b * b);
}

/// Conductor Fresnel reflectance for the complex index n + i k (n > 0, k >= 0), exact for
/// unpolarised light (Born & Wolf; the a, b form of e.g. Lagarde's "Memo on Fresnel equations"):
///   a^2 + b^2 = sqrt((n^2 - k^2 - s^2)^2 + 4 n^2 k^2),  a^2 = (a^2 + b^2 + n^2 - k^2 - s^2) / 2,
///   R_s = (a^2 + b^2 - 2 a c + c^2) / (a^2 + b^2 + 2 a c + c^2),
///   R_p = R_s (c^2 (a^2 + b^2) - 2 a c s^2 + s^4) / (c^2 (a^2 + b^2) + 2 a c s^2 + s^4),
/// with s^2 = 1 - c^2 (R_p is the textbook tan form multiplied through by c^2, finite at c = 0).
/// F = (R_s + R_p) / 2. F(1) = ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2), F(0) = 1. With k = 0 it equals
/// fresnelDielectric(c, n), total internal reflection included; n = 1, k = 0 gives 0.
template <class T>
T fresnelConductor(const T& cosTheta, const T& n, const T& k) {
  using std::sqrt;
  const T c = detail::clampUnit(cosTheta);
  const T c2 = c * c, s2 = T(1) - c2;
  const T t = n * n - k * k - s2;
  const T ab2 = sqrt(t * t + T(4) * n * n * k * k);
  const T a2 = T(0.5) * (ab2 + t);
  const T a = a2 > T(0) ? T(sqrt(a2)) : T(0);
  const T denS = ab2 + T(2) * a * c + c2;
  if (!(denS > T(0))) return T(0);  // n = 1, k = 0 at grazing: no interface
  const T rs = (ab2 - T(2) * a * c + c2) / denS;
  const T pTerm = c2 * ab2 + s2 * s2;
  const T rp = rs * (pTerm - T(2) * a * c * s2) / (pTerm + T(2) * a * c * s2);
  return T(0.5) * (rs + rp);
}

/// Normal-incidence reflectance of a dielectric: ((eta - 1) / (eta + 1))^2. eta = 1.5 gives 0.04.
template <class T>
T f0FromIor(const T& eta) {
  const T r = (eta - T(1)) / (eta + T(1));
  return r * r;
}

/// The dielectric index with normal-incidence reflectance f0 in [0, 1): (1 + sqrt f0) / (1 - sqrt f0)
/// (the root >= 1 of f0FromIor). f0 = 1 has no finite index (returns +infinity).
double iorFromF0(double f0);

/// Normal-incidence reflectance of a conductor: ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2).
template <class T>
T f0FromConductor(const T& n, const T& k) {
  return ((n - T(1)) * (n - T(1)) + k * k) / ((n + T(1)) * (n + T(1)) + k * k);
}

/// The range of indices (eta, n and k; k from 0) FresnelTerm accepts, in which the formulas above
/// stay finite and accurate (their squares and products of squares stay far from overflow): every
/// real material lies well inside it (docs/limits.md).
inline constexpr double kMinFresnelIndex = 1e-3;
inline constexpr double kMaxFresnelIndex = 1e3;

/// A Fresnel term per RGB channel: F(c) for c = cos of the angle of incidence (see file comment).
/// Immutable and thread-safe.
class FresnelTerm {
 public:
  enum class Kind {
    Dielectric,  ///< Heidrich 2000 Eq. 13 with a per-channel index (also F0 inputs: eta from F0)
    Conductor,   ///< exact conductor formula with per-channel n + i k
    Table,       ///< tabulated over c (from spectral data), linear interpolation
    Schlick,     ///< Schlick's approximation from f0 per channel (fresnelSchlick)
  };

  /// Dielectric of relative index eta per channel. Throws Error(InvalidArgument) unless each
  /// eta is in [kMinFresnelIndex, kMaxFresnelIndex].
  static FresnelTerm dielectric(const Rgb& eta);
  /// From the normal-incidence reflectance f0 in [0, 1] per channel, through
  /// eta = (1 + sqrt f0) / (1 - sqrt f0) and Eq. 13 (the usual way to give a metal's colour without
  /// its complex index). f0 = 1 gives F = 1 at every angle (the eta -> infinity limit); f0 = 0 gives
  /// eta = 1, F = 0 at every angle. Throws Error(InvalidArgument) outside [0, 1].
  static FresnelTerm fromF0(const Rgb& f0);
  /// Schlick's approximation from f0 in [0, 1] per channel: matches engines that use it (Filament),
  /// where fromF0 converts f0 to a real index instead. Throws Error(InvalidArgument) outside [0, 1].
  static FresnelTerm schlick(const Rgb& f0);
  /// Conductor of complex index n + i k per channel. Throws Error(InvalidArgument) unless n is in
  /// [kMinFresnelIndex, kMaxFresnelIndex] and k in [0, kMaxFresnelIndex].
  static FresnelTerm conductor(const Rgb& n, const Rgb& k);
  /// A table of F over c: entry i holds F at c = i / (size - 1). size >= 2, values finite in [0, 1].
  static FresnelTerm table(std::vector<Rgb> valuesOverCos);
  /// A spectral conductor: n(lambda) + i k(lambda) at `wavelengthsNm` (strictly increasing, nm).
  /// For each of 1025 values of c = i / 1024 the reflectance spectrum F(lambda, c) is computed
  /// exactly at the given wavelengths and reduced to linear sRGB through the CIE 1931 colour-matching
  /// functions under D65 (brdf/spectrum.hpp: linear interpolation between samples, held beyond
  /// them), then divided per channel by the RGB of a constant-1 spectrum (so grey spectra stay
  /// exactly grey and F(0) = 1 exactly) and clamped to [0, 1] (out-of-gamut colours). The result is a
  /// Table term. Throws Error(InvalidArgument) for mismatched sizes or invalid values.
  static FresnelTerm spectralConductor(std::span<const double> wavelengthsNm, std::span<const double> n,
                                       std::span<const double> k);
  /// The same for a spectral normal-incidence reflectance f0(lambda) in [0, 1], each wavelength
  /// through eta = (1 + sqrt f0) / (1 - sqrt f0) and Eq. 13.
  static FresnelTerm spectralF0(std::span<const double> wavelengthsNm, std::span<const double> f0);

  /// F per channel at c = cos(angle of incidence); c is clamped to [0, 1].
  Rgb operator()(double cosTheta) const;
  /// F(1), the normal-incidence reflectance.
  Rgb f0() const { return (*this)(1.0); }
  Kind kind() const { return kind_; }
  /// Dielectric: the index per channel (+infinity where f0 = 1). Conductor: n. Schlick: f0.
  const Rgb& eta() const { return eta_; }
  /// Conductor: k (zero otherwise).
  const Rgb& k() const { return k_; }

 private:
  FresnelTerm() = default;
  Kind kind_ = Kind::Dielectric;
  Rgb eta_ = Rgb::Ones(), k_ = Rgb::Zero();
  std::vector<Rgb> table_;
};

/// The 1-D Fresnel texture of Heidrich 2000 section 3.1.1: `size` entries, entry i holding F at the
/// texel centre c_i = (i + 0.5) / size (so a GPU's linear lookup at texture coordinate s = cos theta
/// returns F(cos theta), clamped to the end entries within half a texel of 0 and 1). size >= 1.
std::vector<Rgb> fresnelTable(const FresnelTerm& fresnel, int size);

/// How a renderer combines the Fresnel map with its mirror (L_m) and diffuse (L_d) images
/// (Heidrich 2000 section 3.1.1). The map is the same either way; the choice is recorded in the spec.
enum class FresnelCombine {
  Add,  ///< L = F L_m + L_d
  Mix,  ///< L = F L_m + (1 - F) L_d (a diffuse surface under a clear coating)
};
/// "add" | "mix"; throws Error(InvalidArgument).
FresnelCombine parseFresnelCombine(std::string_view name);
std::string_view toString(FresnelCombine combine);

/// The Fresnel factor as its own map (Heidrich 2000 section 3.1, decomposition): the value for a texel
/// is F(N.V) per channel, for the normal N that texel stands for (n = normalize(r + v)). In a
/// sphere map N.V is sqrt(1 - rho^2) at disc radius rho. Ignores lights; depends on the view.
class FresnelMaterial final : public Material {
 public:
  FresnelMaterial(FresnelTerm fresnel, FresnelCombine combine) : fresnel_(std::move(fresnel)), combine_(combine) {}
  std::string_view model() const override { return "fresnel"; }
  Rgb unlit(const ShadingGeometry& g) const override { return fresnel_(g.normal.dot(g.view)); }
  bool viewIndependent() const override { return false; }
  bool unlitSymmetricAboutView() const override { return true; }
  const FresnelTerm& fresnel() const { return fresnel_; }
  FresnelCombine combine() const { return combine_; }

 private:
  FresnelTerm fresnel_;
  FresnelCombine combine_;
};

}  // namespace brdfbake
