#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/named_values.hpp>

namespace brdfbake {

CookTorranceMaterial::CookTorranceMaterial(CookTorranceParams params) : params_(std::move(params)) {
  const auto& p = params_;
  require(std::isfinite(p.roughness) && p.roughness >= kMinRoughness && p.roughness <= kMaxRoughness,
          "roughness must be in [1e-06, 10], got " + std::to_string(p.roughness));
  require(std::isfinite(p.specularWeight) && p.specularWeight >= 0.0 && p.specularWeight <= 1.0,
          "specular_weight must be in [0, 1], got " + std::to_string(p.specularWeight));
  require(allFinite(p.diffuse) && (p.diffuse >= 0.0).all() && (p.diffuse <= 1.0).all(),
          "diffuse albedo must be in [0, 1]");
  const bool hasDiffuse = (p.diffuse > 0.0).any();
  if (p.mode == CookTorranceMode::Reflectance) {
    require(!hasDiffuse,
            "diffuse must be zero in reflectance mode: a mirror-direction map holds the specular "
            "term R_s only (Zimmons & Bastos 1999 section 7); bake the diffuse part in lighting mode");
    require(std::isfinite(p.grazingAngleDegrees) && p.grazingAngleDegrees > 0.0 && p.grazingAngleDegrees < 90.0,
            "grazing_angle must be in (0, 90) degrees, got " + std::to_string(p.grazingAngleDegrees));
  }
  require(!(hasDiffuse && p.specularWeight >= 1.0),
          "diffuse has no effect with specular_weight 1 (R = s R_s + d R_d with d = 1 - s); lower specular_weight");
  grazingCos_ = std::cos(radians(p.grazingAngleDegrees));
}

double CookTorranceMaterial::distribution(double nh) const {
  return params_.distribution == MicrofacetDistribution::Beckmann ? beckmannD(nh, params_.roughness)
                                                                  : ggxD(nh, params_.roughness);
}

double CookTorranceMaterial::denominator() const {
  return params_.normalization == CookTorranceNormalization::Microfacet ? 4.0 : 1.0;
}

double CookTorranceMaterial::highlightHalfWidth() const { return std::atan(params_.roughness); }

Rgb CookTorranceMaterial::brdf(const Vec3& n, const Vec3& v, const Vec3& l) const {
  const double nl = n.dot(l), nv = n.dot(v);
  if (!(nl > 0.0) || !(nv >= 0.0)) return Rgb::Zero();
  // nl > 0 and nv >= 0 exclude l = -v, so l + v is not zero.
  const Vec3 h = (l + v).normalized();
  const double nh = n.dot(h), vh = v.dot(h);
  double specular = 0.0;
  if (params_.shadowing == MicrofacetShadowing::VCavity) {
    specular = cookTorranceSpecular(distribution(nh), nh, nv, nl, vh, denominator());
  } else if (nh > 0.0) {  // l.h = v.h for h = normalize(l + v)
    const bool ggx = params_.distribution == MicrofacetDistribution::Ggx;
    specular = distribution(nh) *
               smithGOverNlNv(nv, nl, vh, vh, params_.roughness, ggx,
                              params_.shadowing == MicrofacetShadowing::SmithCorrelated) /
               denominator();
  }
  Rgb value = params_.specularWeight * specular * params_.fresnel(vh);
  if (params_.specularWeight < 1.0) value += (1.0 - params_.specularWeight) * params_.diffuse / kPi;
  return value;
}

Rgb CookTorranceMaterial::reflectance(double nDotV) const {
  const double c = clampFinite(nDotV, 0.0, 1.0);
  const double scaleCos = std::max(c, grazingCos_);
  return params_.specularWeight * peakDistribution() * params_.fresnel(c) / (denominator() * scaleCos * scaleCos);
}

Rgb CookTorranceMaterial::shade(const ShadingGeometry& g, const Vec3& light) const {
  if (params_.mode != CookTorranceMode::Lighting) return Rgb::Zero();
  const double nl = g.normal.dot(light);
  if (!(nl > 0.0)) return Rgb::Zero();
  return brdf(g.normal, g.view, light) * nl;
}

Rgb CookTorranceMaterial::unlit(const ShadingGeometry& g) const {
  if (params_.mode != CookTorranceMode::Reflectance) return Rgb::Zero();
  return reflectance(g.normal.dot(g.view));
}

std::optional<std::vector<RadialLobe>> CookTorranceMaterial::unlitRadialLobes(const Vec3& view) const {
  if (params_.mode != CookTorranceMode::Reflectance) return std::nullopt;
  std::vector<RadialLobe> lobes;
  for (int channel = 0; channel < 3; ++channel) {
    Rgb weight = Rgb::Zero();
    weight[channel] = 1.0;
    // r.v = 2 (n.v)^2 - 1 for r = v mirrored about n.
    lobes.push_back({view, weight, [this, channel](double c) {
                       return reflectance(std::sqrt(std::max(0.0, (1.0 + c) * 0.5)))[channel];
                     }});
  }
  return lobes;
}

std::optional<MicrofacetLobe> CookTorranceMaterial::microfacetLobe(const Vec3& light, const Vec3& view) const {
  if (params_.mode != CookTorranceMode::Lighting || params_.shadowing != MicrofacetShadowing::VCavity) {
    return std::nullopt;
  }
  const Vec3 sum = light + view;
  if (!(sum.squaredNorm() > 1e-24)) return std::nullopt;
  MicrofacetLobe lobe;
  lobe.light = light;
  lobe.view = view;
  lobe.halfVector = sum.normalized();  // as brdf() computes h
  lobe.viewDotHalf = view.dot(lobe.halfVector);
  if (!(lobe.viewDotHalf > 0.0)) return std::nullopt;
  const double s = params_.specularWeight;
  lobe.specular = s * params_.fresnel(lobe.viewDotHalf) / denominator();
  lobe.diffuse = s < 1.0 ? Rgb((1.0 - s) * params_.diffuse / kPi) : Rgb::Zero();
  const double m = params_.roughness;
  if (params_.distribution == MicrofacetDistribution::Beckmann) {
    lobe.distribution = [m](double nh) { return beckmannD(std::abs(nh), m); };
  } else {
    lobe.distribution = [m](double nh) { return ggxD(std::max(std::abs(nh), 1e-300), m); };
  }
  return lobe;
}

std::optional<std::vector<ReflectionLobe>> CookTorranceMaterial::reflectionLobes(const ShadingGeometry& g) const {
  if (params_.mode != CookTorranceMode::Lighting) return std::nullopt;
  // Weights: the specular part's share is about s F(n.v) (times the albedo of D G, about 1), the
  // diffuse part's (1 - s) rho_d.
  const auto shape = params_.distribution == MicrofacetDistribution::Beckmann ? ReflectionLobeShape::Beckmann
                                                                              : ReflectionLobeShape::Ggx;
  const double s = params_.specularWeight;
  std::vector<ReflectionLobe> lobes;
  const double specular = s * luminance(params_.fresnel(std::max(0.0, g.normal.dot(g.view))));
  if (specular > 0.0) lobes.push_back({shape, g.normal, params_.roughness, specular});
  if (const double d = (1.0 - s) * luminance(params_.diffuse); d > 0.0 || lobes.empty()) {
    lobes.push_back({ReflectionLobeShape::Cosine, g.normal, 0.0, std::max(d, 1e-3)});
  }
  return lobes;
}

std::string_view toString(MicrofacetDistribution distribution) {
  return distribution == MicrofacetDistribution::Ggx ? "ggx" : "beckmann";
}

std::string_view toString(CookTorranceMode mode) {
  return mode == CookTorranceMode::Lighting ? "lighting" : "reflectance";
}

std::string_view toString(CookTorranceNormalization normalization) {
  return normalization == CookTorranceNormalization::Microfacet ? "microfacet" : "1981";
}

MicrofacetDistribution parseMicrofacetDistribution(std::string_view name) {
  return parseByName(name, std::array{MicrofacetDistribution::Beckmann, MicrofacetDistribution::Ggx}, "distribution");
}

CookTorranceMode parseCookTorranceMode(std::string_view name) {
  return parseByName(name, std::array{CookTorranceMode::Lighting, CookTorranceMode::Reflectance}, "mode");
}

CookTorranceNormalization parseCookTorranceNormalization(std::string_view name) {
  return parseByName(name,
                     std::array{CookTorranceNormalization::Microfacet, CookTorranceNormalization::CookTorrance1981},
                     "normalization");
}

}  // namespace brdfbake
