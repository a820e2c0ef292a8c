#pragma once
/// @file
/// Resampling any output into another parameterization (`brdfbake convert`), as one call: each
/// output texel averages the input's lookups (as a renderer makes them) over its footprint.

#include <brdfbake/io/map_file.hpp>
#include <brdfbake/run/map_outputs.hpp>
#include <brdfbake/run/sample_output.hpp>

namespace brdfbake {

struct ConvertOptions {
  OutputSource source;  ///< an elevation stack needs cos_view (the map at that n.v)
  ParameterizationKind to = ParameterizationKind::Sphere;
  int resolution = 0;        ///< 0: the input's
  int samplesPerTexel = 16;  ///< footprint samples per output texel, in [1, 4096]
  /// The files the one resampled map is written to (formats by extension), with the cube layout and
  /// texel format; the source is added to the inputs never overwritten.
  MapOutputs outputs;

  /// Throws Error::invalidField ("resolution", "samples_per_texel", MapOutputs::validate's fields).
  void validate() const;
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
