#pragma once
/// @file
/// An object shaded with an output, as a renderer would show it (`brdfbake preview`), as one call.

#include <brdfbake/output/preview.hpp>
#include <brdfbake/run/sample_output.hpp>

namespace brdfbake {

struct PreviewJobOptions {
  OutputSource source;
  PreviewOptions preview;        ///< object, resolution (pixels), view, per-vertex, exposure
  std::filesystem::path output;  ///< .png (8-bit sRGB) or .exr (HDR values)

  void validate() const;
};

struct PreviewResult {
  std::vector<std::filesystem::path> files;
  std::vector<std::string> notes;

  std::string briefReport() const;  ///< "wrote FILE", notes
  nlohmann::json toJson() const;    ///< {"output", "files", "notes"}
};

/// Opens the output, checks the files, renders and writes the picture (cancelled before writing when
/// `context` is).
PreviewResult makePreview(const PreviewJobOptions& options, const Context& context = {});

}  // namespace brdfbake
