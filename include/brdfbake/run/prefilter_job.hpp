#pragma once
/// @file
/// Prefiltering an environment (docs/prefilter.md): what `brdfbake prefilter ENV --lobe L --to KIND
/// -o OUT` does, as one call. A request is a one-map spec (prefilterSpec) run by runSpec, so a
/// prefiltered map is made, checked and written exactly as a spec's "environment" map is, and a
/// request's errors name the spec keys its fields stand for (the tool renames them to its flags).

#include <brdfbake/core/math.hpp>
#include <brdfbake/run/spec_runner.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>

namespace brdfbake {

/// One prefiltered environment map; each field is the spec key in brackets (docs/spec.md).
struct PrefilterRequest {
  std::filesystem::path environment;  ///< ["environment"]["file"]: EXR, HDR, ...
  std::string lobe;                   ///< ["lobe"]: mirror | irradiance | phong:N | blinn:N | ggx:R | lobes:FIT.json
  std::string to;                     ///< ["parameterization"]: sphere | paraboloid | cube | latlong
  std::filesystem::path output;       ///< ["output"]
  /// With `output`, ["outputs"]: the map made once and written to each file (formats by extension).
  std::vector<std::filesystem::path> moreOutputs;
  std::optional<std::string> texelFormat;  ///< ["texel_format"] (.ktx2, .ktx, .dds outputs): rgba16f, rgb9e5, ...
  int resolution = 256;                    ///< ["resolution"]
  std::string method = "auto";             ///< ["method"]: auto | reference | sh | importance | direct
  double maxError = 0.01;                  ///< ["max_error"]: the bound each map is made to
  std::optional<std::string> from;         ///< ["from"]: parameterization of a plain environment image
  bool mips = false;                       ///< ["mips"]
  bool tiled = false;                      ///< ["mip_layout"] "tiled"
  bool faces = false;                      ///< ["layout"] "faces" (cube maps)
  std::optional<Vec3> view, up;            ///< ["view"], ["up"] (sphere maps)
  int samplesPerTexel = 16;                ///< ["samples_per_texel"] (mirror lobe footprint)
  std::optional<int> elevations;           ///< ["elevations"] (varying lobe models)
  std::optional<double> fresnelIor;        ///< ["fresnel"]["ior"]: a Fresnel decomposition
  std::optional<std::string> combine;      ///< ["combine"]: add | mix
  /// ["lobe"] with ["gloss_chain"]: "ggx" makes a GGX chain (level k of L: roughness k / (L - 1))
  /// in place of `lobe` (which must then be empty or "ggx").
  std::optional<std::string> chain;
  std::optional<double> glossScale;               ///< ["gloss_chain"]["scale"]: a gloss chain (lobe phong or blinn)
  std::optional<double> glossBias;                ///< ["gloss_chain"]["bias"]
  std::optional<int> mipCount;                    ///< ["gloss_chain"]["levels"]
  bool edgeFixup = true;                          ///< ["gloss_chain"]["edge_fixup"]
  std::optional<std::filesystem::path> shOutput;  ///< ["sh_output"] (irradiance)
  std::optional<std::string> shFormat;            ///< ["sh_format"]: brdfbake (JSON) | cmgen (text)
};

/// The request as a one-map spec document {"maps": [{...}]}; its relative paths resolve against the
/// current folder, as runSpec resolves an in-memory spec's. Fields left at their defaults are left
/// out; the gloss-chain fields make a "gloss_chain" object as soon as one of them is set.
nlohmann::json prefilterSpec(const PrefilterRequest& request);

/// Runs prefilterSpec(request) (runSpec with `options`) and returns its one map. Throws what
/// runSpec throws, and the map's error when making it failed.
MapResult prefilterEnvironment(const PrefilterRequest& request, const JobOptions& options = {});

}  // namespace brdfbake
