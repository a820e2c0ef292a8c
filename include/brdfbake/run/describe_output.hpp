#pragma once
/// @file
/// What an output is: its kind, files, size, how a renderer looks it up and the spec it was made
/// from (`brdfbake info`), as one call. A plain image (no brdfbake metadata) is described as one.

#include <brdfbake/run/job.hpp>

#include <filesystem>

namespace brdfbake {

struct OutputDescription {
  std::filesystem::path path;
  /// {"file", "brdfbake", "kind", "files", "width", "height", "parameterization", "resolution",
  /// "lookup", "convention_version", "metadata", ...} (BakedOutput::describe, plus size).
  nlohmann::json description;
  std::vector<std::filesystem::path> files;  ///< none: info writes nothing
  std::vector<std::string> notes;

  std::string briefReport() const;
  nlohmann::json toJson() const { return description; }
};

/// Reads `path` (any output of bake or prefilter, or a plain image) and describes it. Throws
/// what BakedOutput::open throws.
OutputDescription describeOutput(const std::filesystem::path& path);

}  // namespace brdfbake
