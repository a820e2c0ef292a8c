#pragma once
/// @file
/// Radially symmetric lobes about the mirrored view direction (Kautz & McCool, Heidrich 2000 section
/// 3.2.3): the model `brdfbake fit` fits to measured tables, and the material that evaluates it.
/// docs/fitting.md describes the model, how it is fitted and the fit.json format.
///
/// For light direction l and view direction v (unit, pointing away from the surface, local frame
/// with z = n the normal), one channel of the model is
///
///     f(l, v) = k_d / pi + sum_k C_k(u) (n_k(u) + 2) / (2 pi) max(0, r_v . l)^n_k(u)    [1/sr]
///
/// with r_v = 2 (n.v) n - v the view direction mirrored about the normal and u = n.v = cos theta,
/// theta the elevation angle of the view direction (equal to that of r_v) from the normal; in the
/// Cornell convention the view is the outgoing direction, so theta = theta_s. (n + 2) / (2 pi) is
/// phongNormalization: C_k is the lobe's cosine-weighted integral about its own axis,
/// integral C (n+2)/(2 pi) (r.l)^n (r.l) dl = C over the hemisphere about r, so at normal incidence
/// (r_v = n, nothing clipped by the horizon) lobe k reflects exactly the fraction C_k of the light.
///
/// A lobe may instead be one of Lafortune et al. 1997's generalised cosine lobes (Eq. 4, with
/// C_x = C_y = c_xy and C_z = 1, the scale C_z^n absorbed by C_k): r_v . l is replaced by
///
///     c_xy (l_x v_x + l_y v_y) + l_z v_z = a . l,   a = (c_xy v_x, c_xy v_y, v_z),
///
/// so the lobe is radially symmetric about the unit axis a / |a| with the amplitude |a|^n (it
/// bakes and prefilters like a Phong lobe about that axis). c_xy = -1 is the Phong lobe above
/// (a = r_v); c_xy = +1 is a lobe about the view itself, back-scatter (retro-reflection);
/// |c_xy| > 1 tilts the axis towards the horizon and makes the lobe grow towards grazing
/// (|a|^2 = c_xy^2 sin^2 theta + cos^2 theta), the off-specular peaks and the Fresnel-like rise
/// of measured paints; |c_xy| < 1 the opposite. The model is reciprocal in l and v for every c_xy.
/// (n + 2) / (2 pi) normalises the lobe exactly only for c_xy = -1.
///
/// A lobe may also be a half-vector lobe (Lobe::halfVector, halfVectorLobe): Cook & Torrance
/// 1982's microfacet form with Blinn 1977's distribution and a Fresnel weight,
/// (C + C_F (1 - l.h)^5) (n + 2) / (2 pi) (n.h)^n / (4 (n.l)(n.v)). In a fixed view it is not
/// radially symmetric about any axis: it is stretched in the plane of incidence towards grazing,
/// as measured lacquers are. It evaluates (lighting and reflectance maps) like the others, but
/// does not prefilter through the radial path.
///
/// C_k and n_k are either constant (LobeElevation::Constant: one 2-D lobe, so an environment can
/// be prefiltered into a single map) or vary smoothly with u (LobeElevation::Varying: a 3-D map).
/// A varying parameter has three positive values p0, p1, p2 and is their weighted geometric mean
/// with quadratic Bernstein weights,
///
///     p(u) = p0^((1 - t)^2) p1^(2 t (1 - t)) p2^(t^2),   t = ln(u / minCos) / ln(maxCos / minCos),
///
/// i.e. ln p is a quadratic polynomial (Bernstein form) in ln cos theta over the elevation range
/// [minCos, maxCos] the model was fitted on: p0 is the value at the most grazing fitted view
/// (u = minCos), p2 at the most normal one (u = maxCos), and t is clamped to [0, 1] so the
/// parameters are held constant beyond the fitted range instead of extrapolated. Why this form:
/// measured lobes grow and sharpen towards grazing by orders of magnitude (Fresnel, and the
/// 1 / cos growth of a BRDF whose lobe keeps its radiance), which is nearly a power of cos theta,
/// linear in ln cos theta; a polynomial in cos theta itself cannot follow it. A geometric mean
/// lies between its smallest and largest value, so bounds on p0..p2 (C > 0, 1 <= n <= 1e5) bound
/// the functions, and equal values give a constant.
///
/// A model may also give each channel a colour profile (ColorProfile::DifferenceAngle): the
/// diffuse term and every lobe weight (a half-vector lobe's C and C_F each) of a channel are
/// multiplied by their own cubic Bernstein polynomial in s = theta_d / 90 degrees,
///
///     P(s) = sum_j p_j binom(3, j) s^j (1 - s)^(3 - j),   p_j >= 0,
///
/// theta_d the angle between the light and the half-vector (Rusinkiewicz 1998's difference angle,
/// cos theta_d = l.h = sqrt((1 + l.v) / 2)), the same for l and v, so the model stays reciprocal.
/// Colour-shifting (interference) paints change colour with theta_d, and the diffuse and haze of
/// measured paints with it (docs/fitting.md). The profile scales weights only, so a fit stays
/// linear in them. On the mirror direction theta_d = theta_v; the prefiltered forms
/// (LobeModel::prefilterFormAt, LobeMaterialMode::Prefiltered) take each lobe's profile there, at
/// its centre.
///
/// A model may also hold a half-difference table (LobeModel::halfDifference, brdf/half_difference_table.hpp):
/// each channel adds exp(sum a_kj hat_k(sqrt(theta_h / 90 degrees)) B_j(theta_d / 90 degrees)), a
/// smooth function of Rusinkiewicz 1998's half and difference angles that `brdfbake fit` chooses
/// where no lobe family follows a table (fitted alone: no diffuse term, no lobes). Such a model is evaluated and baked
/// through its BRDF (lighting and reflectance maps); it has no prefiltered form.
///
/// The formulas are templates on the parameters' scalar so that the fitter differentiates them
/// with ceres::Jet and the material evaluates them in double: one implementation.

#include <brdfbake/brdf/half_difference_table.hpp>
#include <brdfbake/brdf/material.hpp>
#include <brdfbake/brdf/phong.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace brdfbake {

/// Degree of the Bernstein polynomials of LobeElevation::Varying.
inline constexpr int kVaryingDegree = 2;
static_assert(kVaryingDegree + 1 <= 8, "elevationBlend holds at most 8 coefficients");

/// How the lobe parameters depend on the elevation (see @file).
enum class LobeElevation {
  Constant,  ///< C_k, n_k constant: one coefficient each
  Varying,   ///< C_k(u), n_k(u) log-quadratic in ln cos theta (see @file): three values each
};

/// "constant", "varying".
std::string_view toString(LobeElevation elevation);
/// Inverse of toString; throws Error(InvalidArgument) listing the accepted names for others (core/named_values.hpp).
LobeElevation parseLobeElevation(std::string_view name);

/// Coefficients per lobe parameter: 1 (Constant) or 3 (Varying).
constexpr int elevationCoefficientCount(LobeElevation elevation) {
  return elevation == LobeElevation::Constant ? 1 : kVaryingDegree + 1;
}

/// Whether each channel's weights change with the difference angle theta_d (see @file).
enum class ColorProfile {
  None,             ///< weights constant in theta_d
  DifferenceAngle,  ///< diffuse, C and C_F each times a cubic Bernstein polynomial in theta_d / 90 degrees
};
/// "none", "difference_angle".
std::string_view toString(ColorProfile profile);
/// Inverse of toString; throws Error(InvalidArgument) listing the accepted names for others (core/named_values.hpp).
ColorProfile parseColorProfile(std::string_view name);

/// Degree of the Bernstein polynomials of ColorProfile::DifferenceAngle, and their coefficient count.
inline constexpr int kColorProfileDegree = 3;
inline constexpr int kColorProfileCount = kColorProfileDegree + 1;

/// Bounds the fitter enforces and LobeModel::validate checks.
inline constexpr double kMinLobeExponent = 1.0;
inline constexpr double kMaxLobeExponent = 1e5;
/// Largest diffuse term, lobe weight, Fresnel coefficient and colour-profile coefficient: the bound a
/// spec's colours have (io/json_reader.hpp kMaxColor). Products of them stay far from overflow, where
/// 1e308 passed as a weight once crashed the matcap's lobe sampler.
inline constexpr double kMaxLobeWeight = 1e6;

/// A varying lobe parameter from the logarithms of its values and the Bernstein weights at the
/// elevation (see @file): exp(sum_j weights[j] logValues[j]).
template <class T>
T geometricBlend(const T* logValues, const double* weights, int count) {
  using std::exp;
  T logValue = T(0.0);
  for (int j = 0; j < count; ++j) logValue += T(weights[j]) * logValues[j];
  return exp(logValue);
}

/// elevationBlend with the Bernstein weights at t given (bernsteinWeights(count, t, weights)), for
/// many parameters blended at one elevation.
template <class T>
T elevationBlendWith(const T* coefficients, int count, const double* weights) {
  if (count == 1) return coefficients[0];
  using std::log;
  T logs[8];
  for (int j = 0; j < count && j < 8; ++j) logs[j] = log(coefficients[j]);
  return geometricBlend(logs, weights, count);
}

/// A lobe parameter at elevation coordinate t in [0, 1] (LobeModel::elevationCoordinate):
/// `coefficients[0]` when `count` is 1, else geometricBlend of the logarithms of the `count`
/// coefficients (all > 0) with Bernstein weights of degree count - 1.
template <class T>
T elevationBlend(const T* coefficients, int count, double t) {
  if (count == 1) return coefficients[0];
  double weights[8];
  bernsteinWeights(count, t, weights);
  return elevationBlendWith(coefficients, count, weights);
}

/// One normalised lobe at a positive cosine to its axis, given as logCosToAxis = ln cosToAxis:
/// weight (n + 2) / (2 pi) exp(n logCosToAxis). Fits that evaluate fixed directions many times
/// keep the logarithm (one exponential per evaluation, no power).
template <class T>
T normalizedLobeOfLog(const T& weight, const T& exponent, double logCosToAxis) {
  using std::exp;
  return weight * phongNormalization(exponent) * exp(exponent * T(logCosToAxis));
}

/// One normalised lobe: weight (n + 2) / (2 pi) max(0, cosToAxis)^n, in 1/sr for weight in 1.
/// `cosToAxis` is data (a direction), never differentiated.
template <class T>
T normalizedLobe(const T& weight, const T& exponent, double cosToAxis) {
  if (!(cosToAxis > 0.0)) return T(0.0);
  return normalizedLobeOfLog(weight, exponent, std::log(cosToAxis));
}

/// The pair of products a Lafortune lobe depends on (Lafortune et al. 1997, Eq. 4 with C_x = C_y):
/// horizontal = l_x v_x + l_y v_y and vertical = l_z v_z in the local frame (z = normal), i.e.
/// l.v - (n.l)(n.v) and (n.l)(n.v) in any frame.
/// lightZ = n.l and viewZ = n.v serve the half-vector lobes.
struct LobeGeometry {
  double horizontal = 0.0;
  double vertical = 0.0;
  double lightZ = 0.0;
  double viewZ = 0.0;
  /// |l + v|^2 from the vectors (local() and of() set it): near l = -v, its other form 2 (1 + l.v)
  /// keeps none of its digits. A geometry made without it (< 0) takes that form.
  double sumSquared = -1.0;
  /// From unit light and view directions in the local frame.
  static LobeGeometry local(const Vec3& light, const Vec3& view) {
    return {light.x() * view.x() + light.y() * view.y(), light.z() * view.z(), light.z(), view.z(),
            (light + view).squaredNorm()};
  }
  /// From unit normal, light and view in any frame.
  static LobeGeometry of(const Vec3& normal, const Vec3& light, const Vec3& view) {
    const double nl = normal.dot(light), nv = normal.dot(view);
    return {light.dot(view) - nl * nv, nl * nv, nl, nv, (light + view).squaredNorm()};
  }
  /// The lobe's argument c_xy (l_x v_x + l_y v_y) + l_z v_z (see @file). c_xy = -1 gives r_v . l,
  /// the cosine to the mirrored view (Phong); c_xy = +1 gives l . v, a lobe about the view
  /// (retro-reflection).
  double cosine(double cxy) const { return cxy * horizontal + vertical; }
  /// |l + v|^2: sumSquared, or 2 (1 + l.v) for a geometry made without it.
  double lengthSquaredOfSum() const { return sumSquared >= 0.0 ? sumSquared : 2.0 * (1.0 + horizontal + vertical); }
  /// n.h, h = (l + v) / |l + v| the half-vector: (n.l + n.v) / |l + v|, at most 1 (a bound against
  /// rounding); 0 when l = -v.
  double cosHalf() const {
    const double sum = lengthSquaredOfSum();
    return sum > 0.0 ? std::min(1.0, (lightZ + viewZ) / std::sqrt(sum)) : 0.0;
  }
  /// cos theta_d = l.h = |l + v| / 2 = sqrt((1 + l.v) / 2), theta_d the difference angle (Rusinkiewicz 1998).
  double cosDifference() const { return std::sqrt(std::clamp(0.25 * lengthSquaredOfSum(), 0.0, 1.0)); }
  /// theta_d / 90 degrees in [0, 1]: the coordinate of colour profiles (see @file).
  double differenceCoordinate() const { return std::acos(cosDifference()) / (0.5 * std::numbers::pi); }
  /// theta_d / 90 degrees on the mirror direction seen at view cosine u: theta_d = theta_v there.
  static double mirrorDifferenceCoordinate(double u) {
    return std::acos(std::clamp(u, 0.0, 1.0)) / (0.5 * std::numbers::pi);
  }
  /// Schlick's (1994) Fresnel shape (1 - l.h)^5, l.h = cosDifference().
  double schlick() const { return std::pow(1.0 - cosDifference(), 5.0); }
};

/// The half-difference table's basis (brdf/half_difference_table.hpp) at the geometry's theta_h
/// (the half-vector's angle to the normal) and theta_d (cosDifference()'s angle).
inline HalfDifferenceBasis halfDifferenceBasis(const HalfDifferenceTableShape& shape, const LobeGeometry& g) {
  return HalfDifferenceBasis::at(shape, std::acos(g.cosHalf()), std::acos(g.cosDifference()));
}

/// A lobe about the half-vector (Lobe::halfVector; docs/fitting.md): Cook & Torrance 1981's
/// microfacet form with Blinn 1977's normalised distribution D = (n + 2) / (2 pi) (n.h)^n
/// (integral of D (n.h) over the hemisphere of h = 1), Schlick's (1994) Fresnel shape with free
/// weights and no shadowing term,
///
///     f = (C + C_F (1 - l.h)^5) D(h) / (4 (n.l) (n.v))     [1/sr]
///
/// 0 when n.l <= 0 or n.v <= 0. Reciprocal; in a fixed view it is stretched in the plane of
/// incidence towards grazing (h moves half as fast as l there) and grows as 1 / (n.l n.v).
template <class T>
T halfVectorLobe(const T& weight, const T& fresnelWeight, const T& exponent, const LobeGeometry& g) {
  if (!(g.lightZ > 0.0) || !(g.viewZ > 0.0)) return T(0.0);
  return normalizedLobe(weight + fresnelWeight * T(g.schlick()), exponent, g.cosHalf()) *
         T(0.25 / (g.lightZ * g.viewZ));
}

/// A colour profile's factor from the Bernstein weights at s (bernsteinWeights(kColorProfileCount, s,
/// weights), s in [0, 1]): sum_j p_j B_j(s) over its kColorProfileCount coefficients; 1 for an empty
/// profile (none). For many profiles at one theta_d, the weights computed once.
inline double colorProfileFactorWith(const std::vector<double>& profile, const double* weights) {
  if (profile.empty()) return 1.0;
  double factor = 0.0;
  for (int j = 0; j < kColorProfileCount && j < static_cast<int>(profile.size()); ++j)
    factor += profile[j] * weights[j];
  return factor;
}

/// A colour profile's factor at s (see @file), s clamped to [0, 1]: colorProfileFactorWith the
/// Bernstein weights at s; 1 for an empty profile (none).
inline double colorProfileFactor(const std::vector<double>& profile, double s) {
  if (profile.empty()) return 1.0;
  double weights[kColorProfileCount];
  bernsteinWeights(kColorProfileCount, std::clamp(s, 0.0, 1.0), weights);
  return colorProfileFactorWith(profile, weights);
}

/// The diffuse term of a lobe model, diffuse / pi in 1/sr (`diffuse` is an albedo).
template <class T>
T diffuseTerm(const T& diffuse) {
  return diffuse * T(1.0 / std::numbers::pi);
}

/// Most lobes a LobeModel channel holds.
inline constexpr int kMaxModelLobes = 16;

/// Largest |c_xy| LobeModel::validate accepts, and the largest growth |a|^n (a the unscaled
/// Lafortune axis of @file, |a| <= max(1, |c_xy|)) it accepts: n ln max(1, |c_xy|) <= kMaxLobeGrowthLog.
inline constexpr double kMaxLobeCxy = 8.0;
inline constexpr double kMaxLobeGrowthLog = 50.0;

/// One lobe of one channel: weight C (dimensionless; >= 0, and > 0 for Varying) and exponent n (in
/// [1, 1e5]), each elevationCoefficientCount() values (see @file).
struct Lobe {
  std::vector<double> weight;
  std::vector<double> exponent;
  /// Lafortune's horizontal coefficient c_xy (see @file), constant over elevation: -1 (the
  /// default) is the Phong lobe about the mirrored view, +1 a lobe about the view (back-scatter),
  /// |c_xy| > 1 a lobe that grows towards grazing. |c_xy| <= kMaxLobeCxy.
  double cxy = -1.0;
  /// A lobe about the half-vector (halfVectorLobe) instead: weight C, exponent n, `fresnel` C_F;
  /// cxy stays -1 (unused). Constant over elevation, so `weight` and `exponent` hold one value each
  /// in a Constant model (a Varying model blends them as for other lobes).
  bool halfVector = false;
  /// C_F of a half-vector lobe (>= 0); 0 for other lobes.
  double fresnel = 0.0;
  /// ColorProfile::DifferenceAngle: the colour profile of the weight and of C_F (half-vector lobes;
  /// empty for others), kColorProfileCount coefficients >= 0 each (see @file); empty for None.
  std::vector<double> weightProfile{};
  std::vector<double> fresnelProfile{};
  /// True for the Phong lobe about the mirrored view (c_xy = -1).
  bool aboutMirror() const { return cxy == -1.0 && !halfVector; }
};

/// One channel of a lobe model: Lambertian albedo k_d (>= 0; the term is k_d / pi) and the lobes.
struct LobeChannel {
  std::string name;  ///< "R", "550nm", ...
  double diffuse = 0.0;
  std::vector<Lobe> lobes;
  /// ColorProfile::DifferenceAngle: the diffuse term's colour profile (see @file); empty for None.
  std::vector<double> diffuseProfile{};
  /// The coefficients a_kj of the channel's half-difference table (LobeModel::halfDifference's
  /// coefficientCount, index k (D + 1) + j, |a_kj| <= kMaxTableLogValue); empty without a table.
  std::vector<double> halfDifferenceCoefficients{};
};

/// A fitted (or hand-written) lobe model: per channel, the same elevation dependence.
struct LobeModel {
  LobeElevation elevation = LobeElevation::Constant;
  /// Elevation range of a Varying model (see @file): cosines of the most grazing and the most
  /// normal fitted view, 0 < minCos <= maxCos <= 1. Irrelevant for Constant.
  double minCos = 0.1;
  double maxCos = 1.0;
  std::vector<LobeChannel> channels;
  /// Spectral models: the wavelength (nm) of each channel, strictly increasing; else empty.
  std::vector<double> wavelengthsNm;
  /// Whether each channel's weights follow a colour profile in theta_d (see @file).
  ColorProfile colorProfile = ColorProfile::None;
  /// The shape of every channel's half-difference table (see @file); empty (no table) by default.
  HalfDifferenceTableShape halfDifference{};

  std::size_t channelCount() const { return channels.size(); }
  /// Throws Error(InvalidArgument) naming the channel and lobe for: no channels, a coefficient
  /// count other than elevationCoefficientCount(elevation), negative or non-finite weights or
  /// diffuse (zero weights of Varying lobes too), exponents outside [1, 1e5], a bad elevation
  /// range, wavelengths of the wrong count, or colour profiles that do not match colorProfile
  /// (kColorProfileCount coefficients, finite and >= 0, for the diffuse term, every weight and every
  /// half-vector lobe's C_F; none elsewhere), or half-difference coefficients that do not match
  /// `halfDifference` (a model with them has no diffuse term, no lobes, no colour profile and constant elevation).
  void validate() const;

  /// The elevation coordinate of the view cosine u: t = ln(u / minCos) / ln(maxCos / minCos)
  /// clamped to [0, 1] (0 at or beyond the most grazing fitted view; 0 when minCos = maxCos).
  double elevationCoordinate(double u) const;
  /// True when a lobe's weight or shape changes with the view elevation: Varying lobes, or colour
  /// profiles (which the prefiltered forms take at theta_d = theta_v). Such a model prefilters an
  /// environment into a stack of maps over elevation (env/prefilter_stack.hpp), not one map.
  bool variesWithView() const { return elevation == LobeElevation::Varying || colorProfile != ColorProfile::None; }
  /// C_k(u) of a lobe times its colour profile on the mirror direction (theta_d = theta_v), and
  /// n_k(u) (u is clamped).
  double weight(std::size_t channel, std::size_t lobe, double u) const;
  double exponent(std::size_t channel, std::size_t lobe, double u) const;
  /// C_F of a half-vector lobe times its colour profile on the mirror direction (0 for other lobes).
  double fresnel(std::size_t channel, std::size_t lobe, double u) const;
  /// The model frozen at view cosine u: a Constant model with C_k(u) and n_k(u) of every lobe and
  /// the same channels, diffuse terms, colour profiles and wavelengths (a Constant model is returned
  /// unchanged). At views of cosine u it evaluates as this model. A parameter whose three values are
  /// equal keeps that value exactly (no exp(log) rounding).
  LobeModel atElevation(double u) const;
  /// What a prefiltered map of views at cosine u holds: atElevation(u) with the diffuse terms, C_k and
  /// C_F times their colour profiles at theta_d = theta_v (the lobes' centre) and no profiles left, so
  /// variesWithView() is false (a model that does not vary with the view is returned unchanged).
  LobeModel prefilterFormAt(double u) const;

  /// The BRDF (1/sr) of one channel for light `wi` and view `wo` (unit, local frame, z = normal);
  /// 0 when either is at or below the horizon (z <= 0).
  double evaluate(std::size_t channel, const Vec3& wi, const Vec3& wo) const;
  /// Every channel.
  Eigen::VectorXd evaluate(const Vec3& wi, const Vec3& wo) const;
  /// The BRDF on the mirror direction (wi = wo mirrored about the normal) seen at elevation
  /// cosine u: k_d / pi + sum_k C_k(u) (n_k(u) + 2) / (2 pi) for mirror lobes (a Lafortune lobe
  /// contributes at its argument c_xy (u^2 - 1) + u^2). Heidrich 2000's reflectance map profile.
  double mirrorValue(std::size_t channel, double u) const;
  /// True when every lobe is a Phong lobe about the mirrored view (c_xy = -1) and there is no table.
  bool allAboutMirror() const;
  /// True when the model holds a half-difference table (see @file).
  bool hasHalfDifference() const { return !halfDifference.empty(); }

  /// The 3 x channelCount() matrix taking channel values to linear sRGB: identity for channels R,
  /// G, B; the CIE 1931 / D65 weights (SpectrumToRgb) for spectral models; a column of ones for
  /// one channel. Throws Error(InvalidArgument) for other layouts.
  Eigen::Matrix<double, 3, Eigen::Dynamic> rgbWeights() const;
};

/// What LobeMaterial puts in a map.
enum class LobeMaterialMode {
  /// Heidrich 2000's reflectance map (Zimmons & Bastos 1999 section 8): no lights; unlit(g) is the BRDF on the mirror
  /// direction at the texel's elevation, mirrorValue(n.v), like cook_torrance's reflectance mode.
  Reflectance,
  /// Directional lights: shade(g, l) = f(l, v) max(0, n.l), the radiance for a light of unit
  /// irradiance at normal incidence (as Phong and Cook-Torrance's lighting mode).
  Lighting,
  /// Kautz & McCool's prefiltered form (Heidrich 2000 Eq. 19): shade(g, l) = sum_k C_k(u) (n_k + 2) /
  /// (2 pi) max(0, r.l)^n_k, the lobes alone (no k_d, no cosine: the renderer multiplies by n.r_v).
  /// For a Constant model of mirror lobes it depends on r alone and is a sum of radial lobes about
  /// l; a Lafortune lobe (c_xy != -1) uses its own argument and makes the map view-dependent.
  Prefiltered,
};

/// "reflectance", "lighting", "prefiltered".
std::string_view toString(LobeMaterialMode mode);
/// Inverse of toString; throws Error(InvalidArgument) listing the accepted names for others (core/named_values.hpp).
LobeMaterialMode parseLobeMaterialMode(std::string_view name);

/// A Material evaluating a LobeModel, channels converted to linear sRGB by LobeModel::rgbWeights.
class LobeMaterial final : public Material {
 public:
  /// Validates the model (Error(InvalidArgument); also for LobeMaterialMode::Prefiltered of a model
  /// with a table, which has no prefiltered form). `modelName` is what model() reports ("lobes",
  /// "measured").
  LobeMaterial(LobeModel model, LobeMaterialMode mode, std::string modelName = "lobes");

  std::string_view model() const override { return modelName_; }
  Rgb shade(const ShadingGeometry& g, const Vec3& light) const override;
  Rgb unlit(const ShadingGeometry& g) const override;
  bool usesLights() const override { return mode_ != LobeMaterialMode::Reflectance; }
  bool viewIndependent() const override;
  bool unlitSymmetricAboutView() const override { return true; }  // mirrorRgb(N.V); 0 unless reflectance mode
  std::optional<std::vector<RadialLobe>> radialLobes(const Vec3& light, const Vec3& view) const override;
  /// Lighting mode: every lobe at the view's elevation (Phong lobes about the mirrored view as
  /// power cosines, Lafortune lobes about their axes, half-vector lobes as Blinn-Phong shapes) and
  /// the diffuse term, weighted by C (|a|^n for Lafortune) times the channel's luminance, lobes of one
  /// shape and axis with exponents within a factor 1.5 merged; a half-difference table as a diffuse
  /// part and a Blinn-Phong lobe of its highlight's width. nullopt in the other modes.
  std::optional<std::vector<ReflectionLobe>> reflectionLobes(const ShadingGeometry& g) const override;

  /// The BRDF in linear sRGB (1/sr) for unit normal, view and light: 0 when n.l <= 0 or n.v <= 0.
  Rgb brdf(const Vec3& normal, const Vec3& view, const Vec3& light) const;
  /// mirrorValue of every channel at u = n.v, in linear sRGB.
  Rgb mirrorRgb(double nDotV) const;

  const LobeModel& lobeModel() const { return model_; }
  LobeMaterialMode mode() const { return mode_; }

 private:
  Rgb toRgb(const Eigen::VectorXd& channels) const;
  LobeModel model_;
  LobeMaterialMode mode_;
  std::string modelName_;
  Eigen::Matrix<double, 3, Eigen::Dynamic> rgbWeights_;
  bool sharedShapes_ = false;  // every channel has the same lobe shapes (checked once, not per point)
};

}  // namespace brdfbake
