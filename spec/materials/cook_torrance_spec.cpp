// "cook_torrance" material, and the check that a map's footprint samples resolve its highlight.
#include <brdfbake/brdf/cook_torrance.hpp>

#include <sstream>

#include "registry_entries.hpp"

namespace brdfbake::materials {
namespace {

template <class Parse>
auto parseName(JsonObjectReader& m, const std::string& key, Parse parse) {
  return m.parsed(key, parse);
}

// The pixel position of the reflected direction for normal n (clipped to n.v >= 0) seen from v.
MapAddress addressForNormal(const Parameterization& map, Vec3 n, const Vec3& v) {
  if (n.dot(v) < 0.0) {
    n -= n.dot(v) * v;
    n = n.norm() > 1e-12 ? Vec3(n.normalized()) : anyPerpendicular(v);
  }
  const double nv = std::max(0.0, n.dot(v));
  Vec3 r = 2.0 * nv * n - v;
  if (!(r.norm() > 1e-12)) r = -v;
  return map.getAddressFor(r);
}

double pixelDistance(const Parameterization& map, const Vec2& a, const Vec2& b) {
  double dx = std::abs(a.x() - b.x());
  if (map.wrapsHorizontally()) dx = std::min(dx, map.width() - dx);
  return std::hypot(dx, a.y() - b.y());
}

// Extent in pixels of the highlight about the half vector h: the distance between the points at
// +-halfWidth from h along each tangent axis, the smaller of the two axes. Points that land in
// another region (hemisphere, cube face) than the peak are measured from the peak and doubled.
double highlightExtentPixels(const Parameterization& map, const Vec3& h, const Vec3& v, double halfWidth) {
  Vec3 t1 = v - v.dot(h) * h;
  t1 = t1.norm() > 1e-9 ? Vec3(t1.normalized()) : anyPerpendicular(h);
  const Vec3 t2 = h.cross(t1);
  const MapAddress peak = addressForNormal(map, h, v);
  double extent = HUGE_VAL;
  for (const Vec3& axis : {t1, t2}) {
    const MapAddress a = addressForNormal(map, std::cos(halfWidth) * h + std::sin(halfWidth) * axis, v);
    const MapAddress b = addressForNormal(map, std::cos(halfWidth) * h - std::sin(halfWidth) * axis, v);
    const bool inA = a.region == peak.region, inB = b.region == peak.region;
    double d = HUGE_VAL;
    if (inA && inB)
      d = pixelDistance(map, a.pixel, b.pixel);
    else if (inA)
      d = 2.0 * pixelDistance(map, a.pixel, peak.pixel);
    else if (inB)
      d = 2.0 * pixelDistance(map, b.pixel, peak.pixel);
    extent = std::min(extent, d);
  }
  return extent;
}

}  // namespace

std::shared_ptr<const Material> parseCookTorrance(JsonObjectReader& m, const MaterialContext& context) {
  CookTorranceParams p;
  // Under an environment the material is lit through its BRDF: "mode" is optional and must be lighting.
  p.mode = context.underEnvironment && !m.has("mode") ? CookTorranceMode::Lighting
                                                      : parseName(m, "mode", parseCookTorranceMode);
  if (context.underEnvironment && p.mode != CookTorranceMode::Lighting) {
    throw specError(m.child("mode"),
                    "a material lit by an environment is lit through its BRDF: use \"lighting\" (or leave "
                    "\"mode\" out); the reflectance model holds one fixed configuration (light on the mirror "
                    "direction), not light gathered from an environment");
  }
  if (m.has("distribution")) p.distribution = parseName(m, "distribution", parseMicrofacetDistribution);
  p.roughness = m.number("roughness", kMinRoughness, kMaxRoughness);
  p.fresnel = parseFresnelTerm(m, "fresnel");
  p.specularWeight = m.number("specular_weight", 1.0, 0.0, 1.0, false);
  p.diffuse = m.color("diffuse", Rgb::Zero());
  if ((p.diffuse > 1.0).any()) throw specError(m.child("diffuse"), "is an albedo and must be <= 1 per channel");
  if ((p.diffuse > 0.0).any()) {
    if (p.mode == CookTorranceMode::Reflectance) {
      throw specError(m.child("diffuse"),
                      "must be 0 in reflectance mode: the map holds the mirror-direction specular term "
                      "R_s only (Zimmons & Bastos 1999 section 7); bake the diffuse part with \"mode\": \"lighting\"");
    }
    if (p.specularWeight >= 1.0) {
      throw specError(m.child("diffuse"),
                      "has no effect with specular_weight 1 (R = s R_s + d R_d, d = 1 - s); "
                      "lower \"specular_weight\"");
    }
  }
  if (m.has("normalization")) p.normalization = parseName(m, "normalization", parseCookTorranceNormalization);
  if (m.has("shadowing")) {
    p.shadowing = parseName(m, "shadowing", parseMicrofacetShadowing);
    if (p.mode != CookTorranceMode::Lighting && p.shadowing != MicrofacetShadowing::VCavity) {
      throw specError(m.child("shadowing"),
                      "only applies to \"mode\": \"lighting\" (the reflectance model has G = 1: light on the "
                      "mirror direction is neither masked nor shadowed)");
    }
  }
  if (m.has("grazing_angle")) {
    if (p.mode != CookTorranceMode::Reflectance) {
      throw specError(m.child("grazing_angle"),
                      "only applies to \"mode\": \"reflectance\" (lighting mode is finite at "
                      "grazing through G)");
    }
    p.grazingAngleDegrees = m.number("grazing_angle", 0.0, 90.0, true);
    if (!(p.grazingAngleDegrees < 90.0)) {
      throw specError(m.child("grazing_angle"), "must be < 90: at 90 degrees the 1/(N.V)^2 scale is infinite");
    }
  }
  return std::make_shared<CookTorranceMaterial>(std::move(p));
}

void checkMaterialSampling(const MapSpec& spec) {
  const MaterialMapSpec& m = *spec.materialMap();
  const auto* ct = dynamic_cast<const CookTorranceMaterial*>(m.material.get());
  if (!ct || ct->params().mode != CookTorranceMode::Lighting) return;
  // Stratified footprint samples integrate a Gaussian-like lobe almost exactly once their spacing
  // is below its 1/e half-width (relative error ~ 2 exp(-pi^2) ~ 1e-4), i.e. 2 samples across
  // the lobe's full 1/e width; below that the map aliases (missed or single-sample peaks).
  constexpr double kSamplesNeeded = 2.0;
  const auto map = makeParameterization(spec.parameterization, spec.resolution);
  const double halfWidth = ct->highlightHalfWidth();
  for (std::size_t i = 0; i < m.lights.size(); ++i) {
    const Vec3 sum = m.lights[i].direction + spec.view;
    if (!(sum.norm() > 1e-9)) continue;  // light opposite the view: its highlight is not in the map
    const double extent = highlightExtentPixels(*map, sum.normalized(), spec.view, halfWidth);
    const double samplesAcross = extent * std::sqrt(static_cast<double>(spec.samplesPerTexel));
    if (samplesAcross >= kSamplesNeeded) continue;
    const double factor = kSamplesNeeded / std::max(samplesAcross, 1e-9);
    std::ostringstream message;
    message.precision(3);
    message << ct->params().roughness << " makes the highlight of light " << i << " about " << extent
            << " texels across (1/e width of D) in this " << spec.resolution << " " << toString(spec.parameterization)
            << " map, " << samplesAcross << " footprint samples with samples_per_texel " << spec.samplesPerTexel
            << ": fewer than the " << kSamplesNeeded
            << " needed, so the map would alias. Raise \"resolution\" to at least "
            << static_cast<long long>(std::ceil(spec.resolution * factor));
    const double samples = std::ceil(spec.samplesPerTexel * factor * factor);
    if (samples <= 4096) message << " or \"samples_per_texel\" to at least " << static_cast<long long>(samples);
    message << ", raise the roughness, or bake \"mode\": \"reflectance\" (which has no lobe)";
    throw specError(spec.jsonPath + ".material.roughness", message.str());
  }
}

}  // namespace brdfbake::materials
