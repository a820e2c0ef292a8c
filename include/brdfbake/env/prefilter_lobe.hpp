#pragma once
/// @file
/// The lobes an environment is prefiltered with (Heidrich 2000 section 3.2): radially symmetric weights
/// w(cos theta) per unit solid angle about an axis (the reflected direction r, or the normal n for
/// irradiance). A prefiltered map stores  L_o(a) = ∫ w(a . l) L(l) dω(l)  at each axis a.
///
/// Normalisation (docs/prefilter.md):
/// - mirror: the delta lobe; the map is the environment resampled (no integral).
/// - irradiance: w = max(0, c) / pi, so ∫ w dω = 1 and the map holds the radiance-equivalent
///   irradiance E(n)/pi (Eq. 15 without k_d, divided by pi): a constant environment L = 1 gives 1, and a
///   Lambertian surface of albedo k_d reflects k_d times the map. The one irradiance quantity of every
///   output (docs/conventions.md, "Irradiance").
/// - phong:N: w = (N + 1) / (2 pi) max(0, c)^N (Eq. 17 normalised: ∫ w dω = 1; note the factor is
///   N + 1, not the N + 2 of phongNormalization, which also weights by the cosine to the normal).
/// - blinn:N: the Blinn-Phong exponent N' = N converted by the classic policy N' = 4 n
///   (BlinnConversion::FourN), i.e. phong:N/4. Under the n = v = r assumption of prefiltering,
///   the N.H lobe is cos^N(theta/2) ≈ cos^(N/4)(theta) near its peak, which is the same policy.
/// - ggx:R: the split-sum lobe of Karis (2013) and Filament with n = v = r: the weight of light
///   direction l is D(h) max(0, n.l) with h = normalize(r + l), normalised to integrate to 1.
///   R is the perceptual roughness; D uses alpha = R^2 (Filament's linearRoughness).
/// Fitted lobe models (fit.json) are RGB-weighted sums of Phong lobes, not one scalar lobe: they
/// are prefiltered with prefilterLobeModel (prefilter.hpp).

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace brdfbake {

enum class LobeKind { Mirror, Irradiance, Phong, Ggx };

/// The irradiance quantity every output holds (irradiance maps, their mip levels, SH files, the
/// `ibl` job's files): the radiance-equivalent irradiance E/pi, stated as "irradiance_quantity" in
/// each map's "prefilter" metadata and as "quantity" in SH files (docs/conventions.md, "Irradiance").
inline constexpr const char* kIrradianceQuantity = "E/pi";

class PrefilterLobe {
 public:
  /// The delta lobe: plain resampling.
  static PrefilterLobe mirror();
  /// Radiance-equivalent irradiance max(0, n.l) / pi (E/pi), indexed by the normal; integrates to 1.
  static PrefilterLobe irradiance();
  /// Normalised Phong (N + 1)/(2 pi) max(0, c)^N. Throws Error(InvalidArgument) unless
  /// 0 <= exponent <= 1e6 and finite.
  static PrefilterLobe phong(double exponent);
  /// Blinn-Phong exponent converted with N' = 4n: phong(exponent / 4), named "blinn:N".
  static PrefilterLobe blinn(double blinnExponent);
  /// GGX split-sum lobe for perceptual roughness in [0.01, 1] (alpha = roughness^2).
  static PrefilterLobe ggx(double roughness);
  /// Parses "mirror", "irradiance", "phong:N", "blinn:N" or "ggx:ROUGHNESS". Throws
  /// Error(InvalidArgument) naming the accepted forms; "lobes:FILE.json" (FILE relative to
  /// `baseDirectory`) is refused with a message pointing to readFitFile and prefilterLobeModel,
  /// which take fitted lobe models.
  static PrefilterLobe parse(std::string_view text, const std::filesystem::path& baseDirectory = {});

  LobeKind kind() const;
  /// Canonical text, as parse() accepts it: "phong:100", "ggx:0.3", ...
  const std::string& name() const;
  /// One line for people: "normalised Phong, exponent 100".
  std::string description() const;
  bool isMirror() const { return kind() == LobeKind::Mirror; }
  /// True for irradiance: the map is indexed by the normal, not the reflected direction.
  bool indexedByNormal() const { return kind() == LobeKind::Irradiance; }
  /// The Phong exponent (phong, blinn converted), or 0.
  double phongExponent() const;
  /// GGX alpha (= roughness^2), or 0.
  double ggxAlpha() const;
  /// GGX perceptual roughness as given to ggx(), or 0.
  double ggxRoughness() const;

  /// w(c) per steradian for the cosine c of the angle to the axis (exact formula; 0 for mirror).
  double weight(double cosAngle) const;
  /// ∫ w dω over the sphere: 1 for every filtering lobe (irradiance included: E/pi).
  double mass() const;
  /// Angle (radians) about the axis holding half of the mass.
  double halfMassAngle() const;
  /// A Gaussian-equivalent angular width: halfMassAngle / sqrt(2 ln 2) (= 1/sqrt(N) for Phong N).
  double width() const;
  /// The smallest angle theta_c such that at most `fraction` of the mass lies beyond it.
  double tailAngle(double fraction) const;
  /// Inverse CDF of the angle to the axis under w (as a distribution): theta for u in [0, 1].
  double sampleAngle(double u) const;
  /// Funk-Hecke coefficients lambda_l = 2 pi ∫ w(t) P_l(t) dt, l = 0..maxOrder: convolving a
  /// function with the lobe multiplies its band-l spherical harmonics by lambda_l (lambda_0 = mass).
  std::vector<double> zonalCoefficients(int maxOrder) const;

  struct Data;

 private:
  explicit PrefilterLobe(std::shared_ptr<const Data> data) : data_(std::move(data)) {}
  std::shared_ptr<const Data> data_;
};

}  // namespace brdfbake
