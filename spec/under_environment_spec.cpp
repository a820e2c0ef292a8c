// A material lit by an environment ("material" beside "environment": {"file", ...}; docs/matcap.md):
// the environment object and the map's "camera", the environment read with errors that name the JSON
// path, and the call that makes the map.
#include <brdfbake/spec/spec.hpp>

#include <sstream>

#include "registry_entries.hpp"

namespace brdfbake {
namespace fs = std::filesystem;
namespace {

// [x, y, z] of finite numbers, as written (not normalised: a camera frame must be orthonormal).
Vec3 rawVector(const nlohmann::json& value, const std::string& path) {
  if (!value.is_array() || value.size() != 3) throw specError(path, "must be [x, y, z], got " + describe(value));
  return {JsonObjectReader::asNumber(value[0], path + "[0]"), JsonObjectReader::asNumber(value[1], path + "[1]"),
          JsonObjectReader::asNumber(value[2], path + "[2]")};
}

// "camera": {"forward": [x, y, z], "up": [x, y, z]} or {"yaw": degrees, "pitch": degrees}.
CameraFrame parseCamera(JsonObjectReader& map) {
  JsonObjectReader camera = map.object("camera");
  const bool vectors = camera.has("forward") || camera.has("up");
  const bool angles = camera.has("yaw") || camera.has("pitch");
  if (vectors == angles) {
    throw specError(camera.path(),
                    "give either \"forward\" and \"up\" ([x, y, z], orthonormal) or \"yaw\" and "
                    "\"pitch\" (degrees)");
  }
  CameraFrame frame;
  if (vectors) {
    frame.forward = rawVector(camera.require("forward"), camera.child("forward"));
    frame.up = rawVector(camera.require("up"), camera.child("up"));
    try {
      frame.validate();
    } catch (const Error& e) {
      throw specError(camera.path(), std::string(e.what()) + ": the frame must be orthonormal");
    }
  } else {
    const double yaw = camera.number("yaw", 0.0, -360.0, 360.0, false);
    const double pitch = camera.number("pitch", 0.0, -90.0, 90.0, false);
    frame = CameraFrame::fromYawPitch(yaw, pitch);
  }
  camera.finish();
  return frame;
}

}  // namespace

namespace materials {

void parseEnvironmentLighting(JsonObjectReader& map, MapSpec& spec, const fs::path& baseDirectory) {
  MaterialMapSpec& m = *spec.materialMap();
  if (map.has("lights")) {
    throw specError(map.child("lights"),
                    "a material lit by an environment takes its light from it; remove \"lights\" (or \"environment\")");
  }
  if (spec.anyAuto() || spec.radialProfile) {
    throw specError(map.child("parameterization"),
                    "a material lit by an environment needs a fixed parameterization (sphere, paraboloid, cube or "
                    "latlong), resolution and samples_per_texel");
  }
  if (spec.viewNeed == MapSpec::ViewNeed::Free) {
    throw specError(map.child("view"),
                    "a material lit by an environment is seen from one view; \"free\" cannot be served");
  }
  JsonObjectReader env = map.object("environment");
  if (env.has("lobe")) {
    throw specError(env.child("lobe"),
                    "with a \"material\" the map is the material lit by the environment; \"lobe\" prefilters an "
                    "environment without a material: remove one of them");
  }
  EnvironmentLighting e;
  const std::string file = env.string("file");
  if (file.empty()) throw specError(env.child("file"), "must not be empty");
  e.file = fs::path(file).is_absolute() ? fs::path(file) : baseDirectory / file;
  spec.inputs.push_back({e.file, env.child("file")});
  if (env.has("from")) e.from = env.parsed("from", parseParameterizationKind);
  if (env.has("method")) e.method = env.parsed("method", parseUnderEnvironmentMethod);
  e.maxError = env.number("max_error", 0.01, 0.0, 0.5, /*exclusiveMinimum=*/true);
  if (env.has("max_relative_error"))
    e.maxRelativeError = env.number("max_relative_error", 0.0, 10.0, /*exclusiveMinimum=*/true);
  env.finish();
  if (map.has("camera")) e.camera = parseCamera(map);
  // "exposure": stops the written map is scaled by (2^exposure; for 8-bit outputs). Read again by the
  // runner from the map's JSON; checked here.
  if (map.has("exposure")) map.number("exposure", 0.0, -30.0, 30.0, false);
  m.environment = e;
}

}  // namespace materials

const EnvironmentLighting* MapSpec::environmentLighting() const {
  const MaterialMapSpec* m = materialMap();
  return m && m->environment ? &*m->environment : nullptr;
}

UnderEnvironmentOptions MapSpec::underEnvironmentOptions() const {
  const EnvironmentLighting* e = environmentLighting();
  if (!e) throw Error(Error::Kind::InvalidArgument, jsonPath + ": not a material lit by an environment");
  UnderEnvironmentOptions options;
  options.parameterization = parameterization;
  options.resolution = resolution;
  options.view = view;
  options.camera = e->camera;
  options.samplesPerTexel = samplesPerTexel;
  options.method = e->method;
  options.maxError = e->maxError;
  options.maxRelativeError = e->maxRelativeError;
  return options;
}

Environment loadMapEnvironment(const MapSpec& map) {
  fs::path file;
  std::optional<ParameterizationKind> from;
  if (const EnvironmentMapSpec* prefiltered = map.environmentMap()) {
    file = prefiltered->file, from = prefiltered->from;
  } else if (const EnvironmentLighting* lighting = map.environmentLighting()) {
    file = lighting->file, from = lighting->from;
  } else {
    throw Error(Error::Kind::InvalidArgument, map.jsonPath + ": the map reads no environment");
  }
  try {
    return loadEnvironment(file, EnvironmentLoadOptions{from});
  } catch (const Error& error) {
    const std::string where = (map.specLabel.empty() ? "" : map.specLabel + ": ") + map.jsonPath + ".environment.file";
    throw Error(error.kind(), where + ": " + error.what());
  }
}

MaterialUnderEnvironment bakeUnderEnvironment(const MapSpec& map, const Environment& environment,
                                              const Context& context) {
  const MaterialMapSpec* m = map.materialMap();
  if (!map.environmentLighting()) {
    throw Error(Error::Kind::InvalidArgument, map.jsonPath + ": not a material lit by an environment");
  }
  if (!m->material) {
    throw Error(Error::Kind::InvalidArgument,
                map.jsonPath + ": the measured material's fit has not run yet; call MapSpec::prepare() first");
  }
  UnderEnvironmentOptions options = map.underEnvironmentOptions();
  try {
    return shadeUnderEnvironment(environment, *m->material, options, context);
  } catch (const Error& error) {
    const std::string where = (map.specLabel.empty() ? "" : map.specLabel + ": ") + map.jsonPath;
    throw Error(error.kind(), where + ": " + error.what());
  }
}

}  // namespace brdfbake
