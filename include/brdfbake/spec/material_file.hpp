#pragma once
/// @file
/// A material read from a file, whatever the file holds: what `brdfbake matcap MATERIAL ...` and the
/// Python module take for a material given by its path.
///
///   - a JSON file holding one material object ({"model": "cook_torrance", ...}, as a spec's
///     "material": docs/materials.md; a relative "file" in it resolves against the file's folder);
///   - a fit.json of `brdfbake fit` (the fitted lobes, "model": "lobes");
///   - a measured table (.astm, .brdf, .binary, .mat): lobes are fitted to it first (docs/fitting.md;
///     RGB by CIE 1931, negative values clamped), which takes seconds.

#include <brdfbake/brdf/material.hpp>
#include <brdfbake/core/context.hpp>
#include <brdfbake/io/files.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace brdfbake {

struct MaterialFile {
  std::shared_ptr<const Material> material;
  std::string kind;                     ///< "material", "fit" or "table"
  std::vector<FilePlan::Entry> inputs;  ///< every file read (the file, and a fit or table a material names)
  std::vector<std::string> notes;       ///< e.g. negative measured values clamped
  /// How the material is recorded in a map's metadata: {"model": ..., "file": FILE NAME} (the file's
  /// name only: no folder of the machine that made it).
  nlohmann::json description;
};

/// Reads the material in `path` for lighting (the mode every material lit by an environment or by
/// lights through its BRDF takes: "lighting" for lobes and Cook-Torrance; hand-designed maps are
/// refused). A measured table is fitted on `context` (progress, cancellation). Throws Error(Io) for
/// an unreadable file, Error(InvalidInput) naming the file (and the JSON path inside it) for a file
/// that is none of these, a bake spec, or a material that does not parse, and what the fit throws.
MaterialFile loadMaterialFile(const std::filesystem::path& path, const Context& context = {});

/// The same for a material object given as JSON (a Python dict), whose relative "file" resolves
/// against `baseDirectory`; `label` names it in messages ("material").
MaterialFile parseMaterialObject(const nlohmann::json& object, const std::filesystem::path& baseDirectory,
                                 const std::string& label, const Context& context = {});

}  // namespace brdfbake
