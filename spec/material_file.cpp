// A material read from a file or a JSON object (material_file.hpp).
#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/core/printable.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/io/json_text.hpp>
#include <brdfbake/spec/material_file.hpp>
#include <brdfbake/spec/material_spec.hpp>

#include <cctype>
#include <fstream>
#include <optional>

#include "registry_entries.hpp"

namespace brdfbake {
namespace fs = std::filesystem;

namespace {

// The first character that is not white space is '{': a JSON file, not a table.
bool startsWithBrace(const fs::path& path) {
  requireInputFile(path, "material file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(Error::Kind::Io, printable(path.string()) + ": cannot open");
  for (char c = 0; in.get(c);) {
    if (!std::isspace(static_cast<unsigned char>(c))) return c == '{';
  }
  return false;
}

// The material's JSON as a map's metadata records it: any "file" by its name only.
nlohmann::json described(nlohmann::json object) {
  if (auto file = object.find("file"); file != object.end() && file->is_string())
    *file = fs::path(file->get<std::string>()).filename().string();
  return object;
}

// "<label>: <message>", the message's own leading ": " (an error at the object's root) dropped.
Error labelled(const Error& error, const std::string& label) {
  std::string message = error.what();
  if (message.rfind(": ", 0) == 0) message.erase(0, 2);
  return Error(error.kind(), label + ": " + message);
}

MaterialFile fromTable(const fs::path& path, const Context& context) {
  MaterialFile file;
  file.kind = "table";
  file.inputs.push_back({path, "material"});
  MeasuredTable table = materials::tableForBaking(path, TableFormat::Auto, RgbMethod::Cie1931);
  for (const auto& note : table.notes) file.notes.push_back(printable(path.filename().string()) + ": " + note);
  const DeferredFit fit{std::move(table), materials::fitOptionsForBaking(LobeMaterialMode::Lighting),
                        LobeMaterialMode::Lighting, printable(path.filename().string())};
  file.material = fit.run(context);
  file.description = {{"model", "measured"}, {"file", path.filename().string()}, {"method", "fit"}};
  return file;
}

MaterialFile fromFitFile(const fs::path& path) {
  MaterialFile file;
  file.kind = "fit";
  file.inputs.push_back({path, "material"});
  FitFile fit = readFitFile(path);
  file.material = std::make_shared<LobeMaterial>(std::move(fit.fit.model), LobeMaterialMode::Lighting, "lobes");
  file.description = {{"model", "lobes"}, {"file", path.filename().string()}};
  return file;
}

}  // namespace

MaterialFile parseMaterialObject(const nlohmann::json& object, const fs::path& baseDirectory, const std::string& label,
                                 const Context& context) {
  if (!object.is_object()) {
    throw Error(
        Error::Kind::InvalidInput,
        label + ": a material is one JSON object ({\"model\": \"cook_torrance\", ...}), got " + describe(object));
  }
  if (object.contains("maps")) {
    throw Error(Error::Kind::InvalidInput,
                label +
                    ": a bake spec; a material file holds one material object ({\"model\": \"cook_torrance\", "
                    "...}), a fit.json or a measured table");
  }
  MaterialFile file;
  file.kind = "material";
  std::optional<DeferredFit> deferred;
  MaterialContext materialContext;
  materialContext.baseDirectory = baseDirectory;
  materialContext.inputs = &file.inputs;
  materialContext.notes = &file.notes;
  materialContext.deferredFit = &deferred;
  materialContext.underEnvironment = true;
  try {
    file.material = parseMaterial(object, "", materialContext);
    if (deferred) file.material = deferred->run(context);
  } catch (const Error& error) {
    throw labelled(error, label);
  }
  file.description = described(object);
  return file;
}

MaterialFile loadMaterialFile(const fs::path& path, const Context& context) {
  const std::string name = printable(path.string());
  if (!startsWithBrace(path)) return fromTable(path, context);
  const nlohmann::json document = readJsonFile(path);
  if (isFitFileJson(document)) return fromFitFile(path);
  MaterialFile file = parseMaterialObject(document, path.parent_path(), name, context);
  file.inputs.insert(file.inputs.begin(), {path, "material"});
  return file;
}

}  // namespace brdfbake
