// "lobes" materials: a fitted lobe model read from a fit.json (docs/fitting.md).
//   {"model": "lobes", "file": "fit.json", "mode": "reflectance" | "lighting" | "prefiltered"}
// ("mode" defaults to "reflectance", and to "lighting" (the only one accepted) under an environment).
#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/fit/fit_file.hpp>

#include "registry_entries.hpp"

namespace brdfbake::materials {

LobeMaterialMode parseLobeMode(JsonObjectReader& m, bool underEnvironment) {
  const LobeMaterialMode mode = m.parsed("mode", parseLobeMaterialMode, underEnvironment ? "lighting" : "reflectance");
  if (underEnvironment && mode != LobeMaterialMode::Lighting) {
    throw specError(m.child("mode"),
                    "a material lit by an environment is lit through its BRDF: use \"lighting\" (or leave "
                    "\"mode\" out); " +
                        std::string(toString(mode)) +
                        " mode holds one fixed configuration, not light gathered from an environment");
  }
  return mode;
}

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
  const LobeMaterialMode mode = parseLobeMode(m, context.underEnvironment);
  FitFile fit;
  try {
    fit = readFitFile(file);
  } catch (const Error& e) {
    throw specError(m.child("file"), e.what());
  }
  if (fit.fit.model.hasHalfDifference() && mode == LobeMaterialMode::Prefiltered)
    throw specError(m.child("mode"), "a half-difference table (" + printable(file.string()) +
                                         ") has no prefiltered form: use \"lighting\" or \"reflectance\"");
  return std::make_shared<LobeMaterial>(std::move(fit.fit.model), mode, "lobes");
}

}  // namespace brdfbake::materials
