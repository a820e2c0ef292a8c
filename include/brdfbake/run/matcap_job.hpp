#pragma once
/// @file
/// A matcap (docs/matcap.md): a material shaded under an environment, seen from a fixed view and
/// stored as a sphere map looked up by the view-space normal. Three steps, each usable alone:
///
///   auto sky = std::make_shared<const Environment>(loadEnvironment("sky.exr"));  // once, for many materials
///   MatcapResult made = makeMatcap({.material = gold, .environment = sky, .maxError = 0.05}, context);
///   writeMatcap(made, {.files = {"gold.png"}});                       // or use made.map.image in memory
///
/// and runMatcap, what `brdfbake matcap MATERIAL ENVIRONMENT -o OUT` does: the files read, checked
/// and written in one call. A spec's map of a material under an environment is made by the same
/// makeMatcap and writeMatcap (run/spec_runner.hpp).

#include <brdfbake/core/context.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/material_under_environment.hpp>
#include <brdfbake/run/map_outputs.hpp>
#include <brdfbake/run/spec_runner.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace brdfbake {

/// One matcap, in memory. Fields are named in messages as the spec keys and Python keywords are
/// (snake_case: "max_error").
struct MatcapRequest {
  /// The material, lit through its BRDF (loadMaterialFile reads one; hand-designed maps have none).
  std::shared_ptr<const Material> material;
  /// The light: radiance over the sphere (loadEnvironment, or makeEnvironment around an image).
  std::shared_ptr<const Environment> environment;
  ParameterizationKind parameterization = ParameterizationKind::Sphere;  ///< sphere: the matcap
  int resolution = 256;                                                  ///< in [1, 65536]
  int samplesPerTexel = 16;                                              ///< footprint samples, in [1, 4096]
  /// Towards the viewer in eye space: +z for sphere maps (turn the camera instead); the other
  /// parameterizations, indexed by the reflected direction, may fix another.
  Vec3 view = Vec3::UnitZ();
  UnderEnvironmentMethod method = UnderEnvironmentMethod::Auto;
  /// The bound on the estimated error, relative to the peak, in (0, 0.5] (material_under_environment.hpp).
  double maxError = 0.01;
  /// The bound on each texel's relative error where the picture is above 1 % of its median, in (0, 10]
  /// (default 3 x maxError; material_under_environment.hpp).
  std::optional<double> maxRelativeError;
  CameraFrame camera;     ///< default: looking down -z, up +y (CameraFrame::fromYawPitch turns it)
  double exposure = 0.0;  ///< stops the map is scaled by (2^exposure), in [-30, 30]: for 8-bit outputs
  /// Picks `exposure` from the map instead: the stops that put the 99th percentile of its texels'
  /// largest channel (over the texels the map covers) at 1, the white of an 8-bit output, within
  /// [-30, 30]. The map's metadata and notes record the stops chosen. The command line's default
  /// for .png outputs.
  bool autoExposure = false;
  /// How the map's metadata records the material ({"model": ..., "file": NAME}); empty: its model.
  nlohmann::json materialDescription;

  /// Throws Error::invalidField naming the field: "material" (none, or no BRDF), "environment",
  /// "resolution", "samples_per_texel", "max_error", "max_relative_error", "exposure", "camera".
  void validate() const;
  /// The options shadeUnderEnvironment takes.
  UnderEnvironmentOptions shadingOptions() const;
  /// The request as a map's metadata records it: a spec's map object (docs/spec.md) with the
  /// environment and material by name (no folder).
  nlohmann::json describe() const;
};

struct MatcapResult {
  MaterialUnderEnvironment map;  ///< the image (exposure applied), its parameterization, the summary
  nlohmann::json description;    ///< MatcapRequest::describe(), written as the map's metadata

  /// "cook_torrance under the environment by sampled (...): estimated error ... , 0.05 s".
  std::string briefReport() const { return map.summary.briefReport(); }
  /// What `matcap --json` prints of the map, but its files: parameterization, resolution, width,
  /// height, bake_path, bake_seconds, samples_per_texel, under_environment (the summary).
  nlohmann::json toJson() const;
};

/// The stops that bring the 99th percentile of the covered texels' largest channel to 1 (0 for a
/// black map), within [-30, 30]: MatcapRequest::autoExposure.
double exposureFor(const Image& image);

/// Makes the matcap in memory: validate(), then shadeUnderEnvironment on `context` (threads,
/// progress, cancellation), then the exposure. Throws what validate() and shadeUnderEnvironment throw.
MatcapResult makeMatcap(const MatcapRequest& request, const Context& context = {});

/// Writes the map to every file of `outputs` (MapOutputs::validate first), with its metadata and
/// error estimate. Throws Error(Io) for a file that cannot be written (earlier files stay).
MapWriteReport writeMatcap(const MatcapResult& result, const MapOutputs& outputs);

/// What `brdfbake matcap MATERIAL ENVIRONMENT -o OUT` takes.
struct MatcapFiles {
  std::filesystem::path material;            ///< loadMaterialFile reads it
  std::filesystem::path environment;         ///< EXR, HDR, ... (loadEnvironment)
  std::optional<ParameterizationKind> from;  ///< the environment's parameterization if plain
  MatcapRequest request;                     ///< material and environment are filled in
  MapOutputs outputs;
};

/// Checks every file (the material, the environment and each output) before any work, reads the
/// material and the environment, makes the matcap and writes it. Returns the map's entry as `bake
/// --json` prints a map's. Errors name the file or the request's field.
MapResult runMatcap(const MatcapFiles& files, const Context& context = {});

}  // namespace brdfbake
