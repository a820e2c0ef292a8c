#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/core/error.hpp>

namespace brdfbake {
namespace {

void checkColor(const Rgb& c, const char* what) {
  require(allFinite(c) && (c >= 0.0).all(), std::string(what) + " must be finite and >= 0");
}
void checkExponent(double n) {
  require(std::isfinite(n) && n >= 0.0, "exponent must be finite and >= 0, got " + std::to_string(n));
}
bool isEye(const Vec3& light, const Vec3& view) { return (light - view).squaredNorm() < 1e-24; }
// n.v as a function of c = r.v (r = 2 (n.v) n - v  =>  r.v = 2 (n.v)^2 - 1).
double normalDotView(double c) { return std::sqrt(std::max(0.0, (1.0 + c) * 0.5)); }

}  // namespace

PhongMaterial::PhongMaterial(const Rgb& specular, double exponent, const Rgb& diffuse)
    : specular_(specular), diffuse_(diffuse), exponent_(exponent) {
  checkColor(specular, "specular");
  checkColor(diffuse, "diffuse");
  checkExponent(exponent);
}

Rgb PhongMaterial::shade(const ShadingGeometry& g, const Vec3& light) const {
  const double nl = g.normal.dot(light);
  return specular_ * phongLobe(g.reflected.dot(light), exponent_) + diffuse_ * std::max(0.0, nl);
}

std::optional<std::vector<RadialLobe>> PhongMaterial::radialLobes(const Vec3& light, const Vec3& view) const {
  const double n = exponent_;
  std::vector<RadialLobe> lobes{{light, specular_, [n](double c) { return phongLobe(c, n); }}};
  if ((diffuse_ != 0.0).any()) {
    if (!isEye(light, view)) return std::nullopt;
    lobes.push_back({view, diffuse_, normalDotView});
  }
  return lobes;
}

std::optional<std::vector<ReflectionLobe>> PhongMaterial::reflectionLobes(const ShadingGeometry& g) const {
  // Weights: each part's reflected share under a white furnace, with the 1/pi of the light colour:
  // ∫ max(0, r.l)^n dω / pi = 2 / (n + 1) and ∫ max(0, n.l) dω / pi = 1.
  std::vector<ReflectionLobe> lobes;
  if (const double s = luminance(specular_); s > 0.0) {
    lobes.push_back(
        {ReflectionLobeShape::PowerCosine, g.reflected.normalized(), exponent_, s * 2.0 / (exponent_ + 1.0)});
  }
  if (const double d = luminance(diffuse_); d > 0.0 || lobes.empty()) {
    lobes.push_back({ReflectionLobeShape::Cosine, g.normal, 0.0, std::max(d, 1e-3)});
  }
  return lobes;
}

BlinnPhongMaterial::BlinnPhongMaterial(const Rgb& specular, double exponent, const Rgb& diffuse)
    : specular_(specular), diffuse_(diffuse), exponent_(exponent) {
  checkColor(specular, "specular");
  checkColor(diffuse, "diffuse");
  checkExponent(exponent);
}

BlinnPhongMaterial::BlinnPhongMaterial(const Rgb& specular, double phongExponent, BlinnConversion policy,
                                       const Rgb& diffuse)
    : BlinnPhongMaterial(specular, phongExponent, diffuse) {
  switch (policy) {
    case BlinnConversion::Exact:
      exact_ = true;
      break;
    case BlinnConversion::FourN:
      exponent_ = 4.0 * phongExponent;
      break;
    case BlinnConversion::Fit:
      exponent_ = phongExponent > 0.0 ? blinnFitExponent(phongExponent) : 0.0;
      break;
  }
}

double BlinnPhongMaterial::lobe(double x) const {
  if (!exact_) return phongLobe(x, exponent_);
  const auto ratio = blinnExponentRatio(std::min(x, 1.0));
  return ratio ? std::pow(std::min(x, 1.0), exponent_ * *ratio) : 0.0;
}

Rgb BlinnPhongMaterial::shade(const ShadingGeometry& g, const Vec3& light) const {
  const double nl = g.normal.dot(light);
  if (!(nl > 0.0)) return Rgb::Zero();
  const Vec3 sum = light + g.view;
  const double norm = sum.norm();
  const double nh = norm > 0.0 ? g.normal.dot(sum) / norm : 0.0;
  return specular_ * lobe(nh) + diffuse_ * nl;
}

std::optional<std::vector<ReflectionLobe>> BlinnPhongMaterial::reflectionLobes(const ShadingGeometry& g) const {
  // (n.h)^N' about r is about cos^(N'/4) of the angle to r (the classic 4n conversion), so its share
  // of a white furnace is about 2 / (N'/4 + 1) with the 1/pi of the light colour.
  const double exponent = exact_ ? 4.0 * exponent_ : exponent_;
  std::vector<ReflectionLobe> lobes;
  if (const double s = luminance(specular_); s > 0.0) {
    lobes.push_back({ReflectionLobeShape::BlinnPhong, g.normal, exponent, s * 8.0 / (exponent + 4.0)});
  }
  if (const double d = luminance(diffuse_); d > 0.0 || lobes.empty()) {
    lobes.push_back({ReflectionLobeShape::Cosine, g.normal, 0.0, std::max(d, 1e-3)});
  }
  return lobes;
}

std::optional<std::vector<RadialLobe>> BlinnPhongMaterial::radialLobes(const Vec3& light, const Vec3& view) const {
  if (!isEye(light, view)) return std::nullopt;
  // Light at the eye: h = v, so n.h = n.l = n.v, a function of r.v alone.
  std::vector<RadialLobe> lobes{{view, specular_, [this](double c) { return lobe(normalDotView(c)); }}};
  if ((diffuse_ != 0.0).any()) lobes.push_back({view, diffuse_, normalDotView});
  return lobes;
}

}  // namespace brdfbake
