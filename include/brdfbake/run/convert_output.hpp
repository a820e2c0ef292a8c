#pragma once
/// @file
/// Resampling any output into another parameterization (`brdfbake convert`), as one call: each
/// output texel averages the input's lookups (as a renderer makes them) over its footprint.

#include <brdfbake/io/map_file.hpp>
#include <brdfbake/run/sample_output.hpp>

namespace brdfbake {

struct ConvertOptions {
  OutputSource source;  ///< an elevation stack needs cos_view (the map at that n.v)
  ParameterizationKind to = ParameterizationKind::Sphere;
  int resolution = 0;        ///< 0: the input's
  int samplesPerTexel = 16;  ///< footprint samples per output texel, in [1, 4096]
  CubeLayout layout = CubeLayout::Cross;
  std::filesystem::path output;
  /// Further files the one resampled map is written to (formats by extension), after `output`.
  std::vector<std::filesystem::path> moreOutputs;
  /// How .ktx2, .ktx and .dds outputs store texels (default rgba16f); at least one output must be one.
  std::optional<TexelFormat> texelFormat;

  /// Throws Error(InvalidArgument) for values out of range, an output of an unknown format, a texel
  /// format no output can take.
  void validate() const;
  /// `output`, then `moreOutputs`.
  std::vector<std::filesystem::path> outputs() const;
};

struct ConvertResult {
  std::vector<std::filesystem::path> files;
  std::vector<std::string> notes;
  double seconds = 0.0;  ///< resampling

  std::string briefReport() const;  ///< "wrote FILE" per file, notes
  nlohmann::json toJson() const;    ///< {"files", "seconds", "notes"}
};

/// Opens the input, checks the files, resamples and writes the map (its metadata records the
/// input's spec and "converted_from"). A Fresnel table converts to a sphere map only (as seen from
/// +z). Throws Error(InvalidArgument) for options the input cannot take.
ConvertResult convertOutput(const ConvertOptions& options, const Context& context = {});

}  // namespace brdfbake
