#pragma once
/// @file
/// A matcap (docs/matcap.md): a material shaded under an environment, seen from a fixed view and
/// stored as a sphere map looked up by the view-space normal. What `brdfbake matcap MATERIAL
/// ENVIRONMENT -o OUT` does, as one call. A request is a one-map spec (matcapSpec: "material" beside
/// "environment", docs/spec.md) run by runSpec, so a matcap is made, checked and written exactly as
/// such a map of a spec is, and a request's errors name the spec keys its fields stand for (the
/// tool renames them to its flags).
///
///   MapResult made = makeMatcap({.material = "gold.json", .environment = "sky.exr", .output = "gold.exr"});

#include <brdfbake/run/spec_runner.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>

namespace brdfbake {

/// One matcap; each field is the spec key in brackets (docs/spec.md, "Materials under an environment").
struct MatcapRequest {
  /// ["material"]: a JSON file holding one material object ({"model": "cook_torrance", ...}: inline,
  /// its relative "file" resolved against the file's folder), a fit.json of `brdfbake fit` (model
  /// "lobes", lighting mode) or a measured table (.astm, .brdf, .mat: model "measured", method "fit").
  std::filesystem::path material;
  std::filesystem::path environment;  ///< ["environment"]["file"]: EXR, HDR, ... (radiance)
  std::filesystem::path output;       ///< ["output"]: .exr (float) or .png (8-bit sRGB, clamped), ...
  /// With `output`, ["outputs"]: the map made once and written to each file (formats by extension).
  std::vector<std::filesystem::path> moreOutputs;
  std::optional<std::string> texelFormat;   ///< ["texel_format"] (.ktx2, .ktx, .dds outputs): rgba16f, rgb9e5, ...
  std::string parameterization = "sphere";  ///< ["parameterization"]: sphere | paraboloid | cube | latlong
  int resolution = 256;                     ///< ["resolution"]
  int samplesPerTexel = 16;                 ///< ["samples_per_texel"]
  std::string method = "auto";              ///< ["environment"]["method"]: auto | sampled | reference
  double maxError = 0.01;                   ///< ["environment"]["max_error"]: the bound, relative to the peak
  std::optional<std::string> from;          ///< ["environment"]["from"]: parameterization of a plain image
  /// ["camera"]["yaw"], ["camera"]["pitch"] (degrees): turns the default camera (looking down -z, up
  /// +y) by yaw about +y from -z towards +x, then tilts it up by pitch. Unset: the default camera.
  std::optional<double> yaw, pitch;
  /// ["exposure"]: stops the written map is scaled by (2^exposure), for 8-bit outputs.
  double exposure = 0.0;
};

/// The request as a one-map spec document {"maps": [{...}]}; its relative paths resolve against the
/// current folder, as runSpec resolves an in-memory spec's. Reads MATERIAL's first bytes (and, for a
/// JSON file, the file) to tell the three kinds apart. Throws Error(Io) for an unreadable material
/// file and Error(InvalidInput) naming it for a JSON file that is a bake spec or not an object.
nlohmann::json matcapSpec(const MatcapRequest& request);

/// Runs matcapSpec(request) (runSpec with `options`) and returns its one map: its entry holds
/// "under_environment" with the error estimate (error_estimate, error_metric). Throws what runSpec
/// throws, and the map's error when making it failed (nothing is written then).
MapResult makeMatcap(const MatcapRequest& request, const JobOptions& options = {});

}  // namespace brdfbake
