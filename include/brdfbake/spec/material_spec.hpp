#pragma once
/// @file
/// Materials from JSON ("material" objects of a spec). Each model reads its own keys; unknown keys
/// are errors naming their JSON path.

#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/brdf/material.hpp>
#include <brdfbake/fit/lobe_fit.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/json_reader.hpp>
#include <brdfbake/measured/measured_table.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake {

/// A "measured" material with "method": "fit": its table is read and checked while the spec is
/// parsed; the fit itself (seconds of Ceres) runs when the map is made, with progress
/// (MapSpec::prepare).
struct DeferredFit {
  MeasuredTable table;  ///< RGB, negative values clamped
  FitOptions options;
  LobeMaterialMode mode = LobeMaterialMode::Reflectance;
  std::string jsonPath;  ///< of the material object, for messages ("maps[0].material")

  /// Runs the fit (on `context`) and returns the material. Throws Error(InvalidInput)
  /// naming `jsonPath` when the fit fails or does not converge to a usable result.
  std::shared_ptr<const Material> run(const Context& context = {}) const;
};

/// What a material parser may need besides its JSON object.
struct MaterialContext {
  std::filesystem::path baseDirectory;  ///< relative file paths resolve against this (the spec's folder)
  /// If set, every file the material reads is added here with its JSON path (for FilePlan).
  std::vector<FilePlan::Entry>* inputs = nullptr;
  /// If set, notes about the material's input (clamped values, conversions) are added here.
  std::vector<std::string>* notes = nullptr;
  /// If set, a material whose making takes long (a "measured" fit) is not made: the parser stores
  /// what it needs here and returns null. If null, it is made at once.
  std::optional<DeferredFit>* deferredFit = nullptr;
  /// The material is lit by an environment (docs/matcap.md): models with a "mode" default to
  /// "lighting" (cook_torrance's becomes optional) and refuse the others, which have no light to
  /// integrate.
  bool underEnvironment = false;
};

using MaterialParser =
    std::function<std::shared_ptr<const Material>(JsonObjectReader& material, const MaterialContext& context)>;

struct MaterialEntry {
  std::string model;    ///< the "model" value
  std::string summary;  ///< one line for --help and error messages
  MaterialParser parse;
};

/// Every material model a spec can name.
const std::vector<MaterialEntry>& materialRegistry();

/// Parses a material object (reads "model", dispatches, calls finish()). Returns null only when
/// the material was deferred into `context.deferredFit`.
std::shared_ptr<const Material> parseMaterial(const nlohmann::json& value, const std::string& path,
                                              const MaterialContext& context);

}  // namespace brdfbake
