#include <brdfbake/bake/map_function.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/maps/image.hpp>

namespace brdfbake {
namespace {
Vec3 unitOrThrow(const Vec3& v, const char* what) {
  const double norm = v.norm();
  require(std::isfinite(norm) && norm > 0.0, std::string(what) + " must be a finite non-zero vector");
  return v / norm;
}
}  // namespace

MaterialMapFunction::MaterialMapFunction(std::shared_ptr<const Material> material, std::vector<DirectionalLight> lights,
                                         const Vec3& view)
    : material_(std::move(material)), lights_(std::move(lights)), view_(unitOrThrow(view, "view direction")) {
  require(material_ != nullptr, "material must not be null");
  for (auto& light : lights_) {
    light.direction = unitOrThrow(light.direction, "light direction");
    require(allFinite(light.color) && (light.color >= 0.0).all(), "light colour must be finite and >= 0");
  }
}

Rgb MaterialMapFunction::evaluate(const Vec3& direction) const {
  const ShadingGeometry g = geometryForReflection(direction, view_);
  Rgb value = material_->unlit(g);
  for (const auto& light : lights_) value += light.color * material_->shade(g, light.direction);
  return value;
}

std::optional<std::vector<RadialLobe>> MaterialMapFunction::radialLobes() const {
  // Unlit materials: their own lobes, if any. A lit material with an unlit part is not
  // expressed as lobes; such materials bake through the general path.
  if (!material_->usesLights()) return material_->unlitRadialLobes(view_);
  std::vector<RadialLobe> all;
  for (const auto& light : lights_) {
    auto lobes = material_->radialLobes(light.direction, view_);
    if (!lobes) return std::nullopt;
    for (auto& lobe : *lobes) {
      lobe.weight *= light.color;
      all.push_back(std::move(lobe));
    }
  }
  return all;
}

std::optional<std::vector<MicrofacetLobe>> MaterialMapFunction::microfacetLobes() const {
  if (!material_->usesLights()) return std::nullopt;
  std::vector<MicrofacetLobe> all;
  for (const auto& light : lights_) {
    auto lobe = material_->microfacetLobe(light.direction, view_);
    if (!lobe) return std::nullopt;
    lobe->specular *= light.color;
    lobe->diffuse *= light.color;
    all.push_back(std::move(*lobe));
  }
  return all;
}

std::optional<Vec3> MapFunction::symmetryAxis() const {
  const auto lobes = radialLobes();
  if (!lobes || lobes->empty()) return std::nullopt;
  const Vec3 axis = lobes->front().axis.normalized();
  for (const auto& lobe : *lobes) {
    if ((lobe.axis.normalized() - axis).norm() > 1e-12) return std::nullopt;
  }
  return axis;
}

std::optional<Vec3> MaterialMapFunction::symmetryAxis() const {
  if (!material_->usesLights()) {
    if (material_->unlitSymmetricAboutView()) return view_;
    return std::nullopt;
  }
  return MapFunction::symmetryAxis();
}

Rgb ImageMapFunction::evaluate(const Vec3& direction) const {
  return sampleBilinear(image_, map_, direction).head<3>();
}

}  // namespace brdfbake
