#pragma once
/// @file
/// The write step of a job: the files a map made in memory goes to. A job computes its result
/// (makeMatcap, prefilterEnvironment, makeIbl) without touching a file; writing is a separate call
/// that takes the result and a MapOutputs.

#include <brdfbake/io/files.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/maps/texel_format.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake {

struct MapOutputs {
  /// The files the map is written to, the main one first, each in the format its extension names
  /// (.exr float, .png 8-bit sRGB, .hdr, .tif, .ktx2, .ktx, .dds); at most kMaxOutputs.
  std::vector<std::filesystem::path> files;
  CubeLayout layout = CubeLayout::Cross;        ///< cube maps: one cross, or six face files
  MipLayout mipLayout = MipLayout::Files;       ///< chains: STEM_mipK.EXT, or every level inside each file
  std::optional<TexelFormat> texelFormat;       ///< how .ktx2, .ktx and .dds outputs store texels
  std::vector<std::filesystem::path> inputs;    ///< files never overwritten (the job's inputs)
  std::optional<std::filesystem::path> folder;  ///< every output stays inside it (none: anywhere)

  /// Most files one map is written to.
  static constexpr std::size_t kMaxOutputs = 16;

  /// Throws Error::invalidField: "outputs" (none, more than kMaxOutputs, an unknown extension, one
  /// file twice), "texel_format" (set while no output is a texture container).
  void validate() const;
  /// What writing files[i] takes: the inputs, and the texel format for a texture container.
  WriteOptions writeOptionsFor(std::size_t i) const;
  /// The files as a report names them: "a.exr" or "a.exr, a.png".
  std::string names() const;
};

/// Checks, before any work, every file a job reads and writes (FilePlan: no input overwritten, no
/// file written twice, outputs inside `folder`, each output writable). Throws Error(InvalidArgument)
/// naming the file and its role.
void checkJobFiles(const std::vector<FilePlan::Entry>& inputs, const std::vector<FilePlan::Entry>& outputs,
                   const std::optional<std::filesystem::path>& folder);

}  // namespace brdfbake
