#pragma once
/// @file
/// Looking up any output of bake or prefilter as a renderer does (output/baked_output.hpp): what
/// `brdfbake sample` does, as one call.

#include <brdfbake/output/baked_output.hpp>
#include <brdfbake/run/job.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake {

/// Which output to open and how (the flags every command that reads outputs shares).
struct OutputSource {
  std::filesystem::path path;                ///< a map, STEM.EXT of cube faces or a stack, a profile, an SH JSON
  std::optional<ParameterizationKind> from;  ///< how to read a plain image (no brdfbake metadata)
  int mipLevel = 0;                          ///< mip level of a map, faces or stack
  /// n.v where the output needs it: an elevation stack's slices are interpolated at it, a Fresnel
  /// table read at it. Kinds that do not use it refuse it.
  std::optional<double> cosView;

  /// Opens the output; `fromName` names `from` in messages. Throws what BakedOutput::open throws.
  BakedOutput open(const std::string& fromName = "--from") const;
  /// Throws Error(InvalidArgument) when `cosView` is missing where `output` needs it (stacks, and
  /// Fresnel tables when `fresnelNeedsIt`) or given where it is not used.
  void checkCosView(const BakedOutput& output, bool fresnelNeedsIt = true) const;
};

struct SampleOptions {
  OutputSource source;
  /// Lookup directions in the map's frame (any length but 0)...
  std::vector<Vec3> directions;
  /// ...or a file of them, one "x y z" per line ('#' comments and blank lines skipped; errors name
  /// FILE:LINE). A Fresnel table takes neither (n.v alone).
  std::filesystem::path directionsFile;

  void validate() const;
};

struct SampleResult {
  struct Lookup {
    Vec3 direction = Vec3::UnitZ();
    int line = 0;  ///< line of the directions file, 0 otherwise
    Rgba value = Rgba::Zero();
  };
  std::vector<Lookup> lookups;
  bool usesDirection = true;
  std::optional<double> cosView;
  bool fromFile = false;                     ///< directions came from a file
  std::vector<std::filesystem::path> files;  ///< none: sample writes nothing
  std::vector<std::string> notes;

  /// "R G B A" per lookup, one line each.
  std::string briefReport() const;
  /// {"direction", "value", "cos_view"?} for one lookup; an array of them (each with its "line")
  /// for a directions file.
  nlohmann::json toJson() const;
};

SampleResult sampleOutput(const SampleOptions& options, const Context& context = {});

}  // namespace brdfbake
