#pragma once
// How runSpec makes one map of each kind (spec_runner.cpp dispatches; material_maps.cpp,
// prefilter_job.cpp and matcap_job.cpp make them), and the report every written map shares. Private
// to the run layer.
#include <brdfbake/env/environment.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/run/map_outputs.hpp>
#include <brdfbake/run/prefilter_job.hpp>
#include <brdfbake/run/spec_runner.hpp>

#include <string>
#include <vector>

namespace brdfbake {
struct MatcapRequest;
}  // namespace brdfbake

namespace brdfbake::run_detail {

/// What every map of one run shares.
struct MapRunContext {
  const Context& context;
  /// The inputs no output may overwrite (the spec, the map's environment); each output's texel format
  /// comes from MapSpec::writeOptionsFor.
  WriteOptions write;
};

/// Where a map's report says it went: its place in a spec ("maps[0]", or "" outside one) and its
/// files, given as a list ("outputs") or one ("output").
struct MapPlace {
  std::string jsonPath;
  std::vector<std::filesystem::path> files;
  bool list = false;
  /// "a.exr" or "a.exr, a.png, a.ktx2".
  std::string names() const;
  /// How a report starts: "wrote a.exr, a.png", or "made maps[0] in memory" for a map without files.
  std::string made() const;
};
MapPlace placeOf(const MapSpec& map);
/// A spec map's outputs as the write step takes them.
MapOutputs outputsOf(const MapSpec& map, const std::vector<std::filesystem::path>& inputs);

/// The entry every map's JSON shares: output, files, parameterization, resolution, width,
/// height, bake_path, bake_seconds, write_seconds, notes.
struct EntryFacts {
  std::string parameterization;
  int resolution = 0, width = 0, height = 0;
  std::string bakePath;
  double bakeSeconds = 0.0, writeSeconds = 0.0;
};
MapResult makeMapResult(const MapPlace& place, const EntryFacts& facts, std::vector<std::filesystem::path> files,
                        std::vector<std::string> notes);

/// A map baked from a material (and lights), `auto` choosing its configuration when asked.
MapResult runMaterialMap(const MapSpec& map, const MapRunContext& context);

/// A map of a material lit by an environment (MaterialMapSpec::environment; a matcap when a sphere
/// map), its measured material's fit run first: MatcapRequest from the spec, then makeAndWriteMatcap.
MapResult runUnderEnvironmentMap(const MapSpec& map, const std::shared_ptr<const Environment>& environment,
                                 const MapRunContext& context);
/// makeMatcap, writeMatcap and the map's report (matcap_job.cpp).
MapResult makeAndWriteMatcap(const MatcapRequest& request, const MapOutputs& outputs, const MapPlace& place,
                             const Context& context);

/// A map prefiltered from an environment: PrefilterRequest from the spec, then makeAndWritePrefiltered.
MapResult runEnvironmentMap(const MapSpec& map, const EnvironmentMapSpec& e,
                            const std::shared_ptr<const Environment>& environment, const MapRunContext& context);

/// The report of a prefiltered map written to `place` (prefilter_job.cpp): entry, lines, notes.
MapResult reportPrefiltered(const PrefilterResult& made, const MapPlace& place, MapWriteReport written,
                            double writeSeconds, const std::optional<ShOutput>& sh);

/// Adds `from`'s files and its notes not already in `into` (one output of several written).
void appendWritten(MapWriteReport& into, const MapWriteReport& from);

/// `value` with every file name in it ("file", "output", "outputs", "sh_output", at any depth) cut to
/// its last component: what a file's metadata records of its inputs and outputs, so that no folder of
/// the machine that made it travels with it.
nlohmann::json withoutFolders(nlohmann::json value);

/// A number as the tool prints seconds and errors (6 significant digits, as iostream).
std::string formatNumber(double value);

}  // namespace brdfbake::run_detail
