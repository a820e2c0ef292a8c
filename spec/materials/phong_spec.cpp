// "phong" and "blinn_phong" materials.
#include <brdfbake/brdf/phong.hpp>

#include "registry_entries.hpp"

namespace brdfbake::materials {

std::shared_ptr<const Material> parsePhong(JsonObjectReader& m, const MaterialContext&) {
  const Rgb specular = m.color("specular", Rgb::Ones());
  const double exponent = m.number("exponent", 0.0, 1e7, /*exclusiveMinimum=*/true);
  const Rgb diffuse = m.color("diffuse", Rgb::Zero());
  return std::make_shared<PhongMaterial>(specular, exponent, diffuse);
}

std::shared_ptr<const Material> parseBlinnPhong(JsonObjectReader& m, const MaterialContext&) {
  const Rgb specular = m.color("specular", Rgb::Ones());
  const Rgb diffuse = m.color("diffuse", Rgb::Zero());
  const bool direct = m.has("exponent"), converted = m.has("phong_exponent");
  if (direct == converted) {
    throw specError(m.path(), "give either \"exponent\" (the N.H exponent) or \"phong_exponent\" with \"conversion\"");
  }
  if (direct) {
    if (m.has("conversion")) throw specError(m.child("conversion"), "only applies with \"phong_exponent\"");
    return std::make_shared<BlinnPhongMaterial>(specular, m.number("exponent", 0.0, 1e7, true), diffuse);
  }
  const double phongExponent = m.number("phong_exponent", 0.0, 1e7, true);
  const BlinnConversion policy = m.parsed("conversion", parseBlinnConversion, "exact");
  return std::make_shared<BlinnPhongMaterial>(specular, phongExponent, policy, diffuse);
}

}  // namespace brdfbake::materials
