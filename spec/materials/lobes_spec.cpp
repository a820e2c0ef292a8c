// "lobes" materials: a fitted lobe model read from a fit.json (docs/fitting.md).
//   {"model": "lobes", "file": "fit.json", "mode": "reflectance" | "lighting" | "prefiltered"}
#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/fit/fit_file.hpp>

#include "registry_entries.hpp"

namespace brdfbake::materials {

LobeMaterialMode parseLobeMode(JsonObjectReader& m) { return m.parsed("mode", parseLobeMaterialMode, "reflectance"); }

std::filesystem::path resolveMaterialFile(JsonObjectReader& m, const MaterialContext& context) {
  const std::string file = m.string("file");
  if (file.empty()) throw specError(m.child("file"), "must not be empty");
  const std::filesystem::path path(file);
  const std::filesystem::path resolved = path.is_absolute() ? path : context.baseDirectory / path;
  if (context.inputs) context.inputs->push_back({resolved, m.child("file")});
  return resolved;
}

std::shared_ptr<const Material> parseLobes(JsonObjectReader& m, const MaterialContext& context) {
  const std::filesystem::path file = resolveMaterialFile(m, context);
  const LobeMaterialMode mode = parseLobeMode(m);
  FitFile fit;
  try {
    fit = readFitFile(file);
  } catch (const Error& e) {
    throw specError(m.child("file"), e.what());
  }
  return std::make_shared<LobeMaterial>(std::move(fit.fit.model), mode, "lobes");
}

}  // namespace brdfbake::materials
