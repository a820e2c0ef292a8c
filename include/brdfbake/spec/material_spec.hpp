#pragma once
/// @file
/// Materials from JSON ("material" objects of a spec). Each model reads its own keys; unknown keys
/// are errors naming their JSON path.

#include <brdfbake/brdf/material.hpp>
#include <brdfbake/core/files.hpp>
#include <brdfbake/core/json_reader.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace brdfbake {

/// What a material parser may need besides its JSON object.
struct MaterialContext {
  std::filesystem::path baseDirectory;  ///< relative file paths resolve against this (the spec's folder)
  /// If set, every file the material reads is added here with its JSON path (for FilePlan).
  std::vector<FilePlan::Entry>* inputs = nullptr;
  /// If set, notes about the material's input (clamped values, conversions) are added here.
  std::vector<std::string>* notes = nullptr;
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

/// Parses a material object (reads "model", dispatches, calls finish()).
std::shared_ptr<const Material> parseMaterial(const nlohmann::json& value, const std::string& path,
                                              const MaterialContext& context);

}  // namespace brdfbake
