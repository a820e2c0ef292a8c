#include "registry_entries.hpp"

namespace brdfbake {

const std::vector<MaterialEntry>& materialRegistry() {
  static const std::vector<MaterialEntry> registry{
      {"phong", "Phong: specular max(0, R.V)^exponent plus optional Lambert diffuse", materials::parsePhong},
      {"blinn_phong", "Blinn-Phong: (N.H)^exponent, or converted from phong_exponent (exact | 4n | fit)",
       materials::parseBlinnPhong},
      {"cook_torrance",
       "Cook-Torrance 1981: lighting (D G F, directional lights) or reflectance (sphere-map model, F / (N.V)^2)",
       materials::parseCookTorrance},
      {"fresnel", "Fresnel factor F(N.V) as its own map (decomposition), optional 1-D profile",
       materials::parseFresnel},
      {"colorgram", "Colorgram: rings of colour over the view-normal angle, blurred and twisted",
       materials::parseColorgram},
      {"gooch", "Gooch cool-to-warm shading with a highlight (hand-drawn NPR map)", materials::parseGooch},
      {"silhouette", "Silhouette ring near the rim (NPR), optional constant-width mip chain",
       materials::parseSilhouette},
      {"hatching", "Hatching strokes near silhouettes (NPR)", materials::parseHatching},
      {"measured",
       "Measured BRDF table (Cornell ASTM, pbrt, MERL, MAT): Zimmons & Bastos 1999's mirror-direction map, or fitted "
       "lobes",
       materials::parseMeasured},
      {"lobes", "Radially symmetric lobes fitted by `brdfbake fit` (a fit.json)", materials::parseLobes},
  };
  return registry;
}

std::shared_ptr<const Material> parseMaterial(const nlohmann::json& value, const std::string& path,
                                              const MaterialContext& context) {
  JsonObjectReader reader(value, path);
  const std::string model = reader.string("model");
  for (const auto& entry : materialRegistry()) {
    if (entry.model != model) continue;
    std::shared_ptr<const Material> material;
    try {
      material = entry.parse(reader, context);
    } catch (const Error& e) {
      if (e.kind() == Error::Kind::InvalidInput) throw;
      throw specError(path, e.what());  // library validation, reported at the material's path
    }
    reader.finish();
    return material;
  }
  std::string known;
  for (const auto& entry : materialRegistry()) known += (known.empty() ? "" : ", ") + entry.model;
  throw specError(reader.child("model"), "unknown model '" + printable(model, 40) + "' (known: " + known + ")");
}

}  // namespace brdfbake
