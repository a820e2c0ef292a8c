#pragma once
// How runSpec makes one map of each kind (spec_runner.cpp dispatches; material_maps.cpp and
// environment_maps.cpp make them). Private to the run layer.
#include <brdfbake/env/environment.hpp>
#include <brdfbake/maps/image_io.hpp>
#include <brdfbake/run/spec_runner.hpp>

#include <string>
#include <vector>

namespace brdfbake::run_detail {

/// What every map of one run shares.
struct MapRunContext {
  const JobOptions& options;
  /// The inputs no output may overwrite (the spec, the map's environment); each output's texel format
  /// comes from MapSpec::writeOptionsFor.
  WriteOptions write;
};

/// The entry every map's JSON shares: output, files, parameterization, resolution, width,
/// height, bake_path, bake_seconds, write_seconds, notes.
struct EntryFacts {
  std::string parameterization;
  int resolution = 0, width = 0, height = 0;
  std::string bakePath;
  double bakeSeconds = 0.0, writeSeconds = 0.0;
};
MapResult makeMapResult(const MapSpec& map, const EntryFacts& facts, std::vector<std::filesystem::path> files,
                        std::vector<std::string> notes);

/// A map baked from a material (and lights), `auto` choosing its configuration when asked.
MapResult runMaterialMap(const MapSpec& map, const MapRunContext& context);

/// A map of a material lit by an environment (MaterialMapSpec::environment; a matcap when a sphere
/// map), its measured material's fit run first.
MapResult runUnderEnvironmentMap(const MapSpec& map, const Environment& environment, const MapRunContext& context);

/// A map prefiltered from an environment: one map, a stack over elevation, a Fresnel
/// decomposition or a gloss chain, and the SH irradiance file when asked.
MapResult runEnvironmentMap(const MapSpec& map, const EnvironmentMapSpec& e, const Environment& environment,
                            const MapRunContext& context);

/// Adds `from`'s files and its notes not already in `into` (one output of several written).
void appendWritten(MapWriteReport& into, const MapWriteReport& from);

/// The map's outputs as its "wrote" line names them: "a.exr", or "a.exr, a.png, a.ktx2".
std::string outputNames(const MapSpec& map);

/// Sets a one-map spec's "output" (or, with `more`, "outputs") and "texel_format", for the jobs that
/// build a spec from a request (prefilter, matcap).
void putOutputs(nlohmann::json& map, const std::filesystem::path& output,
                const std::vector<std::filesystem::path>& more, const std::optional<std::string>& texelFormat);

/// A number as the tool prints seconds and errors (6 significant digits, as iostream).
std::string formatNumber(double value);

}  // namespace brdfbake::run_detail
