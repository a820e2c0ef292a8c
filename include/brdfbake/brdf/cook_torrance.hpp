#pragma once
/// @file
/// Cook-Torrance (Cook & Torrance 1981; Zimmons & Bastos 1999 section 7), as a lighting model and as Zimmons & Bastos
/// 1999's sphere-map reflectance model. docs/materials.md explains the choices made here.
///
/// Conventions: all vectors are unit vectors pointing away from the surface (n normal, v towards the
/// viewer, l towards the light, h = normalize(l + v)); the dot products below are cosines:
/// nh = N.H, nv = N.V, nl = N.L, vh = V.H. Roughness is the Beckmann rms slope m, or the GGX alpha
/// (both dimensionless; the 1/e half-width of Beckmann's D is atan(m) in half-vector angle).
/// Angles given in degrees say so. BRDF values are in 1/sr.

#include <brdfbake/brdf/fresnel.hpp>
#include <brdfbake/brdf/material.hpp>
#include <brdfbake/brdf/smith.hpp>

namespace brdfbake {

/// Beckmann microfacet distribution, normalised so that its integral of D(h) (n.h) over the
/// hemisphere of h is 1: D = exp(-tan^2(a) / m^2) / (pi m^2 cos^4(a)), cos(a) = nh.
/// Cook & Torrance 1981 write it without the 1/pi (and put a pi in the BRDF's denominator).
/// 0 for nh <= 0 (and below nh = 1e-6, where it underflows to 0 anyway for m <= 10).
template <class T>
T beckmannD(const T& nh, const T& m) {
  using std::exp;
  if (!(nh > T(1e-6))) return T(0);
  const T c2 = nh < T(1) ? T(nh * nh) : T(1);
  const T m2 = m * m;
  const T tan2 = (T(1) - c2) / c2;
  return exp(-tan2 / m2) / (T(kPi) * m2 * c2 * c2);
}

/// GGX (Trowbridge-Reitz) distribution with width alpha, normalised like beckmannD:
/// D = alpha^2 / (pi (nh^2 (alpha^2 - 1) + 1)^2). 0 for nh <= 0.
template <class T>
T ggxD(const T& nh, const T& alpha) {
  if (!(nh > T(0))) return T(0);
  const T c2 = nh < T(1) ? T(nh * nh) : T(1);
  const T a2 = alpha * alpha;
  const T d = c2 * a2 + (T(1) - c2);  // = nh^2 (alpha^2 - 1) + 1, without cancellation for small alpha
  return a2 / (T(kPi) * d * d);
}

/// Cook-Torrance geometric attenuation (Zimmons & Bastos 1999 Eq. 7):
/// G = min(1, 2 (N.H)(N.V) / (V.H), 2 (N.H)(N.L) / (V.H)); 0 if vh <= 0 or nh <= 0.
template <class T>
T cookTorranceG(const T& nh, const T& nv, const T& nl, const T& vh) {
  if (!(vh > T(0)) || !(nh > T(0))) return T(0);
  const T gm = T(2) * nh * nv / vh, gs = T(2) * nh * nl / vh;
  T g = T(1);
  if (gm < g) g = gm;
  if (gs < g) g = gs;
  return g < T(0) ? T(0) : g;
}

/// G / ((N.L)(N.V)) evaluated without dividing by zero: min(1 / (nl nv), x / max(nl, nv)) with
/// x = 2 nh / vh. Finite wherever the quotient has a finite limit: as nv -> 0 with nl > 0 it tends
/// to x / nl (G cancels the 1/N.V), and likewise for nl -> 0. Returns 0 when nl or nv is negative,
/// nh <= 0 or vh <= 0, and when nl = nv = 0 (light and view both grazing).
template <class T>
T cookTorranceGOverNlNv(const T& nh, const T& nv, const T& nl, const T& vh) {
  if (!(nl >= T(0)) || !(nv >= T(0)) || !(vh > T(0)) || !(nh > T(0))) return T(0);
  const T larger = nl > nv ? nl : nv;
  if (!(larger > T(0))) return T(0);
  const T masked = T(2) * nh / (vh * larger);
  const T product = nl * nv;
  if (product > T(0)) {
    const T unmasked = T(1) / product;
    return unmasked < masked ? unmasked : masked;
  }
  return masked;
}

/// The specular term R_s (per unit Fresnel factor: multiply by F(vh)):
///   `denominator` = 4: the normalised microfacet form D G / (4 (N.L)(N.V)) (Walter et al. 2007),
///   `denominator` = 1: Cook & Torrance 1981, D_1981 G / (pi (N.L)(N.V)) with D_1981 = pi D, i.e.
///   D G / ((N.L)(N.V)), four times the normalised form.
/// `d` is the normalised distribution value at nh.
template <class T>
T cookTorranceSpecular(const T& d, const T& nh, const T& nv, const T& nl, const T& vh, double denominator) {
  return d * cookTorranceGOverNlNv(nh, nv, nl, vh) / T(denominator);
}

enum class MicrofacetDistribution { Beckmann, Ggx };
/// Which R_s: the normalised microfacet form (default) or the 1981 form Zimmons & Bastos 1999 writes.
enum class CookTorranceNormalization { Microfacet, CookTorrance1981 };
/// `Lighting`: directional lights and the full D G F. `Reflectance`: Zimmons & Bastos 1999's sphere-map
/// reflectance model (light along the view vector mirrored about N: H = N, D = D(1), G = 1,
/// N.L = N.V), independent of lights.
enum class CookTorranceMode { Lighting, Reflectance };

/// The roughness range CookTorranceMaterial accepts: down to 1e-6 (D(1) = 1 / (pi m^2) stays far
/// below the float range of a map), up to 10 (D is flat long before).
inline constexpr double kMinRoughness = 1e-6;
inline constexpr double kMaxRoughness = 10.0;

struct CookTorranceParams {
  CookTorranceMode mode = CookTorranceMode::Reflectance;
  MicrofacetDistribution distribution = MicrofacetDistribution::Beckmann;
  double roughness = 0.3;  ///< Beckmann rms slope m, or GGX alpha; in [kMinRoughness, kMaxRoughness]
  FresnelTerm fresnel = FresnelTerm::dielectric(Rgb::Constant(1.5));
  double specularWeight = 1.0;  ///< s in R = s R_s + d R_d, d = 1 - s (Zimmons & Bastos 1999 Eq. 5); in [0, 1]
  Rgb diffuse = Rgb::Zero();    ///< Lambertian albedo rho_d in [0, 1]; R_d = rho_d / pi (lighting only)
  CookTorranceNormalization normalization = CookTorranceNormalization::Microfacet;
  /// G: the V-cavity term (default, cookTorranceG) or Smith's for the distribution (smith.hpp),
  /// height-correlated (Filament, Unreal) or separable (Blender Cycles). Lighting mode only (the
  /// reflectance model has G = 1).
  MicrofacetShadowing shadowing = MicrofacetShadowing::VCavity;
  /// Reflectance mode only: beyond this angle between N and V (degrees, in (0, 90)) the 1/(N.V)^2
  /// scale is held at its value there, while F keeps following the true angle. See reflectance().
  double grazingAngleDegrees = 80.0;
};

/// Cook-Torrance: R = s R_s + d R_d, R_s = D G F / (denominator (N.L)(N.V)), F = F(V.H), G the
/// V-cavity term or Smith's (CookTorranceParams::shadowing).
///
/// `Lighting` mode: shade(g, l) = (s R_s + (1 - s) rho_d / pi) max(0, N.L), the radiance for a
/// directional light of unit irradiance at normal incidence; lights below the horizon (N.L <= 0)
/// give 0. `Reflectance` mode: unlit(g) = reflectance(N.V), no lights.
class CookTorranceMaterial final : public Material {
 public:
  /// Throws Error(InvalidArgument) for out-of-range parameters, and for a non-zero diffuse term in
  /// reflectance mode (a mirror-direction map holds R_s only, Zimmons & Bastos 1999 section 7) or with
  /// specularWeight = 1 (then d = 0 and the diffuse term would be silently ignored).
  explicit CookTorranceMaterial(CookTorranceParams params);

  std::string_view model() const override { return "cook_torrance"; }
  Rgb shade(const ShadingGeometry& g, const Vec3& light) const override;
  Rgb unlit(const ShadingGeometry& g) const override;
  bool usesLights() const override { return params_.mode == CookTorranceMode::Lighting; }
  bool viewIndependent() const override { return false; }
  bool unlitSymmetricAboutView() const override { return true; }  // reflectance(N.V); 0 in lighting mode
  /// Reflectance mode: one lobe per channel about the view, reflectance(n.v) with
  /// n.v = sqrt((1 + r.v) / 2). Lighting mode: nullopt.
  std::optional<std::vector<RadialLobe>> unlitRadialLobes(const Vec3& view) const override;
  /// Lighting mode: shade() as a MicrofacetLobe (F(v.h) folded into its weight; D continued to
  /// n.h <= 0 as D(|n.h|), GGX's finite limit at 0 included). nullopt in reflectance mode, with
  /// Smith shadowing (the lobe's G is the V-cavity term) and for a light opposite the view (then
  /// shade() is 0 everywhere).
  std::optional<MicrofacetLobe> microfacetLobe(const Vec3& light, const Vec3& view) const override;
  /// Lighting mode: the distribution's half-vector lobe and, with s < 1, the diffuse max(0, n.l).
  /// nullopt in reflectance mode (its shade() is 0; it has no light to integrate).
  std::optional<std::vector<ReflectionLobe>> reflectionLobes(const ShadingGeometry& g) const override;

  /// The BRDF s R_s + d R_d (1/sr) for unit vectors n, v, l. 0 if N.L <= 0 or N.V < 0; finite at
  /// N.V = 0 (see cookTorranceGOverNlNv).
  Rgb brdf(const Vec3& normal, const Vec3& view, const Vec3& light) const;
  /// The reflectance-mode value at c = N.V (clamped to [0, 1]):
  ///   s D(1) F(c) / (denominator max(c, c_min)^2),  c_min = cos(grazingAngle),
  /// i.e. s R_s with L = V mirrored about N (H = N, G = 1, N.L = N.V) for c >= c_min, and the
  /// same with the 1/c^2 scale frozen at c_min beyond the grazing angle (F still reaches 1 at
  /// c = 0, so the colour goes to white at the rim). Finite everywhere; its largest value is
  /// s D(1) / (denominator c_min^2), at c = 0.
  Rgb reflectance(double nDotV) const;
  /// The normalised distribution D at nh.
  double distribution(double nh) const;
  /// D(1): 1 / (pi m^2) for Beckmann, 1 / (pi alpha^2) for GGX.
  double peakDistribution() const { return distribution(1.0); }
  /// 4 (normalised form) or 1 (1981 form).
  double denominator() const;
  /// cos of the grazing angle.
  double grazingCos() const { return grazingCos_; }
  /// Half-width of the highlight in half-vector angle (radians): atan(roughness), where Beckmann's
  /// D falls to 1/e of its peak (GGX's to 1/4). Used to check a map samples the lobe finely enough.
  double highlightHalfWidth() const;
  const CookTorranceParams& params() const { return params_; }

 private:
  CookTorranceParams params_;
  double grazingCos_ = 0.0;
};

/// "beckmann", "ggx"; "lighting", "reflectance"; "microfacet", "1981".
std::string_view toString(MicrofacetDistribution distribution);
std::string_view toString(CookTorranceMode mode);
std::string_view toString(CookTorranceNormalization normalization);

/// "beckmann" | "ggx"; throws Error(InvalidArgument) naming the accepted values.
MicrofacetDistribution parseMicrofacetDistribution(std::string_view name);
/// "lighting" | "reflectance".
CookTorranceMode parseCookTorranceMode(std::string_view name);
/// "microfacet" | "1981".
CookTorranceNormalization parseCookTorranceNormalization(std::string_view name);

}  // namespace brdfbake
