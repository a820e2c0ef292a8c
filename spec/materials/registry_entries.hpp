#pragma once
// Parsers of the built-in material models; listed in material_registry.cpp.
#include <brdfbake/brdf/fresnel.hpp>
#include <brdfbake/spec/material_spec.hpp>
#include <brdfbake/spec/spec.hpp>

namespace brdfbake::materials {
std::shared_ptr<const Material> parsePhong(JsonObjectReader&, const MaterialContext&);
std::shared_ptr<const Material> parseBlinnPhong(JsonObjectReader&, const MaterialContext&);
std::shared_ptr<const Material> parseCookTorrance(JsonObjectReader&, const MaterialContext&);
std::shared_ptr<const Material> parseFresnel(JsonObjectReader&, const MaterialContext&);
std::shared_ptr<const Material> parseColorgram(JsonObjectReader&, const MaterialContext&);
std::shared_ptr<const Material> parseGooch(JsonObjectReader&, const MaterialContext&);
std::shared_ptr<const Material> parseSilhouette(JsonObjectReader&, const MaterialContext&);
std::shared_ptr<const Material> parseHatching(JsonObjectReader&, const MaterialContext&);

// The "fresnel" object shared by cook_torrance and fresnel: {"ior": eta}, {"f0": [r, g, b]},
// {"n": [r, g, b], "k": [r, g, b]} or {"spectral": {"wavelengths_nm": [...], "n": [...], "k": [...]}}
// (or "f0": [...] instead of n and k). Reads owner[key] (required) and finishes it.
FresnelTerm parseFresnelTerm(JsonObjectReader& owner, const std::string& key);

// Map-level hooks called by spec.cpp's parseMap after the material and lights are read:
// "mips" and "fresnel_table_output" (map_extras_spec.cpp), and the check that a map samples a narrow
// highlight finely enough (cook_torrance_spec.cpp; throws naming the roughness's JSON path).
void parseMapExtras(JsonObjectReader& map, MapSpec& spec);
// "mip_layout": "files" | "tiled" beside "mips" (in a map, or in its "environment"), checked
// against the output's extension and the resolution (tiledMipProblem).
MipLayout parseMipLayout(JsonObjectReader& object, bool mips, const std::filesystem::path& output, int resolution);
void checkMaterialSampling(const MapSpec& spec);
}  // namespace brdfbake::materials

// "measured" and "lobes" (measured_spec.cpp, lobes_spec.cpp; built with brdfbake::fit, see
// importers/CMakeLists.txt), and their shared helpers: "file" resolved against the spec's folder, and
// "mode" of a lobe material (reflectance | lighting | prefiltered; brdf/lobes.hpp).
namespace brdfbake {
enum class LobeMaterialMode;
}
namespace brdfbake::materials {
std::shared_ptr<const Material> parseMeasured(JsonObjectReader&, const MaterialContext&);
std::shared_ptr<const Material> parseLobes(JsonObjectReader&, const MaterialContext&);
// A measured table as baking takes it: read (format), converted to RGB (rgb), negative values clamped
// to 0 with a note in table.notes. Throws what readTableForFitting throws.
MeasuredTable tableForBaking(const std::filesystem::path& file, TableFormat format, RgbMethod rgb);
// The fit of a measured table for baking in `mode` (no held-out estimate unless a choice needs one; no
// half-difference table for the prefiltered mode, which it cannot take).
FitOptions fitOptionsForBaking(LobeMaterialMode mode);
std::filesystem::path resolveMaterialFile(JsonObjectReader& material, const MaterialContext& context);
// "mode" of a lobe material; under an environment it defaults to, and must be, "lighting".
LobeMaterialMode parseLobeMode(JsonObjectReader& material, bool underEnvironment);
// A material lit by an environment ("material" with "environment"; docs/matcap.md): the environment
// object and the map's "camera" (under_environment_spec.cpp).
void parseEnvironmentLighting(JsonObjectReader& map, MapSpec& spec, const std::filesystem::path& baseDirectory);
}  // namespace brdfbake::materials
