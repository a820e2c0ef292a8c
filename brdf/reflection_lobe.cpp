#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/reflection_lobe.hpp>

#include <algorithm>
#include <cmath>

namespace brdfbake {
namespace {

// Half-maximum angle / this = the standard deviation of a Gaussian (sqrt(2 ln 2)).
constexpr double kHalfMaxPerSigma = 1.1774100225154747;

// The unit direction at polar angle acos(cosTheta) and azimuth phi about the unit axis.
Vec3 aboutAxis(const Vec3& axis, double cosTheta, double phi) {
  const Vec3 t = anyPerpendicular(axis), b = axis.cross(t);
  const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
  return (sinTheta * (std::cos(phi) * t + std::sin(phi) * b) + cosTheta * axis).normalized();
}

bool halfVectorShape(ReflectionLobeShape shape) {
  return shape == ReflectionLobeShape::Beckmann || shape == ReflectionLobeShape::Ggx ||
         shape == ReflectionLobeShape::BlinnPhong;
}

// cos of the half vector's angle to the normal drawn with density D(c) c: inverse transforms of
// the distributions' cumulative functions in tan^2 (Beckmann, GGX) or cos (Blinn-Phong).
double halfVectorCos(const ReflectionLobe& lobe, double u) {
  const double p = lobe.parameter;
  switch (lobe.shape) {
    case ReflectionLobeShape::Beckmann: {  // P(tan^2 < x) = 1 - exp(-x / m^2)
      const double tan2 = -p * p * std::log1p(-std::min(u, 1.0 - 1e-16));
      return 1.0 / std::sqrt(1.0 + tan2);
    }
    case ReflectionLobeShape::Ggx: {  // P(tan^2 < x) = x / (alpha^2 + x)
      const double tan2 = p * p * u / std::max(1.0 - u, 1e-16);
      return 1.0 / std::sqrt(1.0 + tan2);
    }
    default:  // P(cos > c) = 1 - c^(N + 2)
      return std::pow(1.0 - u, 1.0 / (p + 2.0));
  }
}

// D(c) c, the half vector's density per steradian of h.
double halfVectorDensity(const ReflectionLobe& lobe, double c) {
  if (!(c > 0.0)) return 0.0;
  switch (lobe.shape) {
    case ReflectionLobeShape::Beckmann:
      return beckmannD(c, lobe.parameter) * c;
    case ReflectionLobeShape::Ggx:
      return ggxD(c, lobe.parameter) * c;
    default:
      return (lobe.parameter + 2.0) / kTwoPi * std::pow(std::min(c, 1.0), lobe.parameter + 1.0);
  }
}

}  // namespace

std::optional<Vec3> sampleReflectionLobe(const ReflectionLobe& lobe, const Vec3& view, double u1, double u2) {
  const double phi = kTwoPi * u2;
  switch (lobe.shape) {
    case ReflectionLobeShape::Cosine:
      return aboutAxis(lobe.axis, std::sqrt(1.0 - u1), phi);
    case ReflectionLobeShape::PowerCosine:
      return aboutAxis(lobe.axis, std::pow(1.0 - u1, 1.0 / (lobe.parameter + 1.0)), phi);
    default:
      break;
  }
  const Vec3 h = aboutAxis(lobe.axis, halfVectorCos(lobe, u1), phi);
  const double vh = view.dot(h);
  if (!(vh > 0.0)) return std::nullopt;
  return Vec3((2.0 * vh * h - view).normalized());
}

double reflectionLobeDensity(const ReflectionLobe& lobe, const Vec3& view, const Vec3& light) {
  const double c = lobe.axis.dot(light);
  switch (lobe.shape) {
    case ReflectionLobeShape::Cosine:
      return c > 0.0 ? c / kPi : 0.0;
    case ReflectionLobeShape::PowerCosine:
      return c > 0.0 ? (lobe.parameter + 1.0) / kTwoPi * std::pow(std::min(c, 1.0), lobe.parameter) : 0.0;
    default:
      break;
  }
  const Vec3 sum = light + view;
  const double norm = sum.norm();
  if (!(norm > 1e-12)) return 0.0;
  const Vec3 h = sum / norm;
  const double vh = view.dot(h);
  if (!(vh > 0.0)) return 0.0;
  return halfVectorDensity(lobe, lobe.axis.dot(h)) / (4.0 * vh);
}

Vec3 reflectionLobePeak(const ReflectionLobe& lobe, const Vec3& view) {
  if (!halfVectorShape(lobe.shape)) return lobe.axis;
  return reflect(view, lobe.axis).normalized();
}

double reflectionLobeWidth(const ReflectionLobe& lobe) {
  const double p = lobe.parameter;
  double width = 1.0;
  switch (lobe.shape) {
    case ReflectionLobeShape::Cosine:
      break;
    case ReflectionLobeShape::PowerCosine:  // cos^N t = 1/2 at the half maximum
      width = p > 0.0 ? std::acos(std::pow(0.5, 1.0 / p)) / kHalfMaxPerSigma : 1.0;
      break;
    case ReflectionLobeShape::Beckmann:  // exp(-tan^2 / m^2) = 1/2: tan = m sqrt(ln 2)
      width = 2.0 * std::atan(p * std::sqrt(std::log(2.0))) / kHalfMaxPerSigma;
      break;
    case ReflectionLobeShape::Ggx:  // (alpha^2 + tan^2)^2 = 2 alpha^4: tan = alpha sqrt(sqrt 2 - 1)
      width = 2.0 * std::atan(p * std::sqrt(std::sqrt(2.0) - 1.0)) / kHalfMaxPerSigma;
      break;
    case ReflectionLobeShape::BlinnPhong:
      width = p > 0.0 ? 2.0 * std::acos(std::pow(0.5, 1.0 / p)) / kHalfMaxPerSigma : 1.0;
      break;
  }
  return std::min(width, 1.0);
}

}  // namespace brdfbake
