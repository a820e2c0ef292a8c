#pragma once
/// @file
/// Running a bake spec (docs/spec.md): what `brdfbake bake SPEC.json` does, as one call.
///
///   SpecRunResult result = runSpec({.spec = "data_samples/specs/phong_eye.json", .outDir = "out"});
///
/// A spec is read and validated whole, and every file it reads and will write is checked (no
/// input overwritten, no two outputs on one file, outputs inside the output folder), and every
/// environment is loaded, before any map is made (planSpec). Then each map is made in order: a
/// material baked (or `auto` choosing its map), an environment prefiltered. A map that fails while
/// being made does not stop the others; its entry says so and the result keeps the first error.

#include <brdfbake/core/error.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/run/job.hpp>
#include <brdfbake/run/map_outputs.hpp>
#include <brdfbake/spec/spec.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake {

struct SpecRunOptions {
  /// The spec file. Relative paths in it resolve against its folder.
  std::filesystem::path spec;
  /// A spec given as a JSON document instead of a file (when not null): relative paths resolve
  /// against the current folder (outputs against `outDir` when given, which they must then stay
  /// in); messages name it `label`.
  nlohmann::json document;
  std::string label = "spec";
  /// Write the outputs under this folder instead of the spec's (an absolute "output" keeps only
  /// its file name); every output must stay inside the output folder.
  std::filesystem::path outDir;
  /// Let a map leave out "output": it is then made in memory only (MapResult::made), as a renderer or
  /// the Python module asks for. Without it every map needs an output (the tool's `bake`).
  bool inMemory = false;

  /// Throws Error(InvalidArgument) unless exactly one of `spec` and `document` is given.
  void validate() const;
};

/// A map made in memory (a spec map without outputs, SpecRunOptions::inMemory): its levels (level 0
/// first: a mip or gloss chain has more), its metadata, and how to write it later.
struct MadeMap {
  std::vector<Image> levels;
  MapInfo info;
  /// Writes the map as the spec would have (throws what writeMap throws).
  std::function<MapWriteReport(const MapOutputs&)> write;
};

/// One map of a spec as made: what was written and how.
struct MapResult {
  std::string jsonPath;                      ///< "maps[0]"
  std::filesystem::path output;              ///< the map's "output", placed (empty: made in memory)
  bool written = false;                      ///< false: making it failed (`error` says why)
  std::string error;                         ///< the failure's message
  std::vector<std::filesystem::path> files;  ///< every file written (faces, mip levels, sidecars, ...)
  std::vector<std::string> notes;
  /// The JSON entry `bake --json` prints for the map: output, status, files, parameterization,
  /// resolution, width, height, bake_path, bake_seconds, write_seconds, notes, and what its kind
  /// adds (samples_per_texel, auto, prefilter, elevations, fresnel, gloss_chain, sh, axis).
  nlohmann::json entry;
  /// The text lines `bake` prints for the map ("wrote ..." and notes).
  std::vector<std::string> lines;
  /// The map itself when it was made in memory (no output), else null.
  std::shared_ptr<const MadeMap> made;

  std::string briefReport() const;
  nlohmann::json toJson() const { return entry; }
};

/// A spec run: every map's result, in the spec's order.
struct SpecRunResult {
  std::filesystem::path spec;  ///< the spec file, or the label of an in-memory spec
  std::vector<MapResult> maps;
  std::vector<std::filesystem::path> files;  ///< every file written, all maps
  std::vector<std::string> notes;
  /// The first map's failure, when any map failed (kind and message as thrown).
  std::optional<Error> firstError;

  int failed() const;
  /// Each map's lines, then failureSummary().
  std::string briefReport() const;
  /// "N of M maps failed\n" (with "; the others were written" when some were) when any failed, else "".
  std::string failureSummary() const;
  /// {"spec": ..., "maps": [MapResult::entry, ...]}.
  nlohmann::json toJson() const;
};

/// A spec, validated, with everything checked before any work: the files it reads and writes.
struct SpecPlan {
  BakeSpec spec;
  FilePlan files;
  /// The folder every output must stay in: `outDir`, else the spec file's folder; none for an
  /// in-memory spec without `outDir`.
  std::optional<std::filesystem::path> outputFolder;
  std::filesystem::path specFile;  ///< empty for an in-memory spec
};

/// Reads and validates the spec, places the outputs, checks every file, map sizes (against the
/// context's limits) and the memory budget. Throws Error(InvalidInput) naming the JSON path for a bad
/// spec, Error(InvalidArgument) for files that collide or leave the folder, Error(Resource) for maps
/// too large.
SpecPlan planSpec(const SpecRunOptions& options, const Context& context = {});

/// planSpec, then loads every environment, then makes each map on `context` (see @file). Throws
/// what planSpec throws, errors loading an environment, and Cancelled; errors while making a map
/// are in its MapResult.
SpecRunResult runSpec(const SpecRunOptions& options, const Context& context = {});

}  // namespace brdfbake
