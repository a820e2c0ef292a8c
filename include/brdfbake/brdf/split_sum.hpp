#pragma once
/// @file
/// The terms of the split-sum approximation of image-based lighting for GGX (Karis 2013, "Real Shading
/// in Unreal Engine 4", the environment BRDF; Filament's DFG), templated on the scalar.
///
/// With Schlick's Fresnel F = f0 (1 - Fc) + f90 Fc, Fc = (1 - v.h)^5, the directional albedo of the
/// specular GGX BRDF f = D(h) V(v, l) F(v.h) (V = G2 / (4 (n.l)(n.v)), Smith height-correlated
/// masking-shadowing, Heitz 2014 Eq. 99) splits into two numbers that depend on n.v and the roughness
/// only:
///
///   DFG1 = ∫ (1 - Fc) D V (n.l) dω_l,   DFG2 = ∫ Fc D V (n.l) dω_l,   E_spec = f0 DFG1 + f90 DFG2
///
/// (Filament's DFV().x and .y, Karis's "scale" and "bias" with f90 = 1). The multiple-scattering form
/// (Filament's DFV_Multiscatter) stores instead
///
///   DFG1 = ∫ Fc D V (n.l) dω_l,   DFG2 = ∫ D V (n.l) dω_l,   E_spec = mix(DFG1, DFG2, f0),
///
/// the second being the single-scattering albedo of a white (F = 1) surface, from which a renderer
/// compensates the energy lost to multiple scattering (Fdez-Agüera 2019; Filament's energy compensation).
///
/// Roughness: alpha = R^2 for the perceptual roughness R (Filament's linearRoughness). Vectors: n the
/// normal, v towards the viewer, l towards the light, h = normalize(v + l).

#include <cmath>
#include <numbers>

namespace brdfbake {

/// The GGX (Trowbridge-Reitz) normal distribution at cos theta_h = nh (Walter et al. 2007 Eq. 33):
/// alpha^2 / (pi ((nh^2)(alpha^2 - 1) + 1)^2); 0 for nh <= 0.
template <class T>
T ggxDistribution(const T& nh, const T& alpha) {
  if (!(nh > T(0))) return T(0);
  const T a2 = alpha * alpha;
  const T f = nh * nh * (a2 - T(1)) + T(1);
  return a2 / (T(std::numbers::pi) * f * f);
}

/// Smith's height-correlated visibility V = G2 / (4 (n.l)(n.v)) for GGX (Heitz 2014 Eq. 99 with
/// Lambda of Eq. 72), in the form that stays finite at grazing (Filament's V_SmithGGXCorrelated):
///   V = 0.5 / (nv sqrt(nl^2 (1 - alpha^2) + alpha^2) + nl sqrt(nv^2 (1 - alpha^2) + alpha^2)).
/// 0 when nl or nv is <= 0.
template <class T>
T ggxSmithCorrelatedVisibility(const T& nv, const T& nl, const T& alpha) {
  using std::sqrt;
  if (!(nv > T(0)) || !(nl > T(0))) return T(0);
  const T a2 = alpha * alpha;
  const T lambdaV = nl * sqrt(nv * nv * (T(1) - a2) + a2);
  const T lambdaL = nv * sqrt(nl * nl * (T(1) - a2) + a2);
  return T(0.5) / (lambdaV + lambdaL);
}

/// Schlick's Fresnel weight Fc = (1 - c)^5 at c = v.h, clamped to [0, 1].
template <class T>
T schlickWeight(const T& c) {
  const T x = T(1) - (c < T(0) ? T(0) : (c > T(1) ? T(1) : c));
  const T x2 = x * x;
  return x2 * x2 * x;
}

/// The split-sum integrand at one light direction: D(h) V(v, l) (n.l) for the cosines n.v, n.l, n.h
/// and v.h; the caller weights it by (1 - Fc), Fc or 1 (see @file). 0 below the horizon.
template <class T>
T ggxSpecularCosine(const T& nv, const T& nl, const T& nh, const T& alpha) {
  if (!(nl > T(0)) || !(nv > T(0))) return T(0);
  return ggxDistribution(nh, alpha) * ggxSmithCorrelatedVisibility(nv, nl, alpha) * nl;
}

}  // namespace brdfbake
