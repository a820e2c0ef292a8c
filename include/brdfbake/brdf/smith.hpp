#pragma once
/// @file
/// Smith's masking-shadowing functions for the Beckmann and GGX distributions of cook_torrance.hpp,
/// as engines and renderers use them (Heitz 2014, "Understanding the Masking-Shadowing Function in
/// Microfacet-Based BRDFs", JCGT 3(2)):
///
/// - Lambda(theta), the Smith auxiliary function of a direction at angle theta to the normal:
///   GGX (Heitz 2014 Eq. 72): Lambda = (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2;
///   Beckmann (Walter et al. 2007 Eq. 25, the exact form of their G1): with a = 1 / (m tan theta),
///   Lambda = (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)).
///   The roughness is the same parameter as the distribution's (GGX alpha, Beckmann m).
/// - G1 = 1 / (1 + Lambda): the masking of one direction (Heitz 2014 Eq. 43).
/// - Separable G2 = G1(v) G1(l) (Heitz 2014 Eq. 98): Blender Cycles' microfacet BSDFs.
/// - Height-correlated G2 = 1 / (1 + Lambda(v) + Lambda(l)) (Heitz 2014 Eq. 99): Filament, Unreal.
/// Both are multiplied by the Heaviside terms chi+(v.h) chi+(l.h) (back-facing microfacets are not seen).
///
/// A BRDF divides G2 by (n.l)(n.v). As n.v -> 0, n.v Lambda(v) tends to a finite limit (GGX:
/// alpha sin(theta) / 2, Beckmann: m sin(theta) / (2 sqrt(pi))), so G2 / ((n.l)(n.v)) stays finite:
/// smithGOverNlNv evaluates it through cosLambda(c) = c Lambda(c), which is finite for c in [0, 1].
/// The V-cavity G of Cook & Torrance 1981 stays in cook_torrance.hpp.

#include <cmath>
#include <numbers>
#include <string_view>

namespace brdfbake {

/// How a Cook-Torrance BRDF shadows and masks its microfacets.
enum class MicrofacetShadowing {
  VCavity,          ///< Cook & Torrance 1981 (Zimmons & Bastos 1999 Eq. 7), the seeds' model
  SmithCorrelated,  ///< Smith, height-correlated (Heitz 2014 Eq. 99)
  SmithSeparable,   ///< Smith, separable (Heitz 2014 Eq. 98)
};

/// "v_cavity", "smith_correlated", "smith_separable".
std::string_view toString(MicrofacetShadowing shadowing);
/// Inverse of toString; throws Error(InvalidArgument) naming the accepted values.
MicrofacetShadowing parseMicrofacetShadowing(std::string_view name);

/// c Lambda(c) for GGX at c = cos theta in [0, 1] (c <= 0 gives the grazing limit alpha / 2):
/// (sqrt(c^2 + alpha^2 (1 - c^2)) - c) / 2, which is Heitz 2014 Eq. 72 times c without the
/// division by c.
template <class T>
T ggxCosLambda(const T& c, const T& alpha) {
  using std::sqrt;
  const T cc = c > T(0) ? (c < T(1) ? c : T(1)) : T(0);
  const T c2 = cc * cc;
  return (sqrt(c2 + alpha * alpha * (T(1) - c2)) - cc) * T(0.5);
}

/// c Lambda(c) for Beckmann of rms slope m at c = cos theta in [0, 1] (c <= 0 gives the grazing
/// limit m / (2 sqrt(pi))): with s = sin theta and a = c / (m s),
/// c Lambda = c (erf(a) - 1) / 2 + m s exp(-a^2) / (2 sqrt(pi)).
template <class T>
T beckmannCosLambda(const T& c, const T& m) {
  using std::erf;
  using std::exp;
  using std::sqrt;
  const T cc = c > T(0) ? (c < T(1) ? c : T(1)) : T(0);
  const T s = sqrt(T(1) - cc * cc);
  if (!(s > T(0))) return T(0);  // normal incidence: no masking
  const T a = cc / (m * s);
  return cc * (erf(a) - T(1)) * T(0.5) + m * s * exp(-a * a) / T(2.0 * std::sqrt(std::numbers::pi));
}

/// Smith's Lambda at c = cos theta in (0, 1]: cosLambda / c.
template <class T>
T smithLambda(const T& c, const T& roughness, bool ggx) {
  const T cl = ggx ? ggxCosLambda(c, roughness) : beckmannCosLambda(c, roughness);
  return cl / c;
}

/// G1 = 1 / (1 + Lambda) at c = cos theta in (0, 1] (Heitz 2014 Eq. 43); 0 for c <= 0.
template <class T>
T smithG1(const T& c, const T& roughness, bool ggx) {
  if (!(c > T(0))) return T(0);
  const T cl = ggx ? ggxCosLambda(c, roughness) : beckmannCosLambda(c, roughness);
  return c / (c + cl);
}

/// G2 / ((n.l)(n.v)) for Smith's shadowing (correlated: Eq. 99; else separable: Eq. 98), finite at
/// grazing: correlated 1 / (nl nv + nl (nv Lambda_v) + nv (nl Lambda_l)), separable
/// 1 / ((nv + nv Lambda_v)(nl + nl Lambda_l)). 0 when nl or nv is negative, when vh <= 0 or
/// lh <= 0 (back-facing microfacet), and when both are grazing (nl = nv = 0).
template <class T>
T smithGOverNlNv(const T& nv, const T& nl, const T& vh, const T& lh, const T& roughness, bool ggx, bool correlated) {
  if (!(nl >= T(0)) || !(nv >= T(0)) || !(vh > T(0)) || !(lh > T(0))) return T(0);
  const T lv = ggx ? ggxCosLambda(nv, roughness) : beckmannCosLambda(nv, roughness);
  const T ll = ggx ? ggxCosLambda(nl, roughness) : beckmannCosLambda(nl, roughness);
  const T denominator = correlated ? T(nl * nv + nl * lv + nv * ll) : T((nv + lv) * (nl + ll));
  if (!(denominator > T(0))) return T(0);
  return T(1) / denominator;
}

}  // namespace brdfbake
