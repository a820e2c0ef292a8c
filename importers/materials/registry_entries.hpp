#pragma once
// Parsers of the built-in material models; listed in material_registry.cpp.
#include <brdfbake/importers/material_spec.hpp>

namespace brdfbake::materials {
std::shared_ptr<const Material> parsePhong(JsonObjectReader&, const MaterialContext&);
std::shared_ptr<const Material> parseBlinnPhong(JsonObjectReader&, const MaterialContext&);
}  // namespace brdfbake::materials
