#pragma once
// The parts of the extension brdfbake._core, each adding its classes and functions to the module.
#include <brdfbake/env/environment.hpp>
#include <brdfbake/output/baked_output.hpp>
#include <brdfbake/run/map_outputs.hpp>
#include <brdfbake/run/sample_output.hpp>

#include <pybind11/pybind11.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake::python {

namespace py = pybind11;

/// An output of bake or prefilter read back, or a job's map in memory (brdfbake.Map): BakedOutput,
/// how it was opened, and what made it when the module made it (the job's entry).
struct OpenedMap {
  OutputSource source;  ///< its path is empty for a map in memory
  std::shared_ptr<const BakedOutput> output;
  py::object result = py::none();
  py::object pixelsRead;  // the pixels of kinds other than Map, read on first use
  /// A map in memory: every mip level (level 0 first; a chain's levels) and how to write it.
  std::vector<Image> levels;
  std::function<MapWriteReport(const MapOutputs&)> writer;
  std::vector<std::filesystem::path> written;  ///< the files the job (or save) wrote it to
};

/// brdfbake.Environment: an environment loaded or wrapped once (shared with every job given it).
struct PythonEnvironment {
  std::shared_ptr<const Environment> environment;
};

/// An Environment, a path (read without the GIL) or an (H, W, 3|4) array of radiance (lat-long
/// unless `from`). Throws Error naming "environment" or "from_".
std::shared_ptr<const Environment> environmentFromPython(const py::object& source,
                                                         const std::optional<std::string>& from);

/// A job's map in memory as a brdfbake.Map: its level 0 looked up, every level kept, `entry` as its
/// .result, and how to write it.
std::shared_ptr<OpenedMap> mapInMemory(std::vector<Image> levels, const MapInfo& info, const nlohmann::json& entry,
                                       std::function<MapWriteReport(const MapOutputs&)> writer);

/// Opens `source` without the GIL. Throws what BakedOutput::open throws.
std::shared_ptr<OpenedMap> openMap(const OutputSource& source);

void bindMaps(py::module_& module);         // Map, read_map
void bindResults(py::module_& module);      // BakeResult, MapResult, Fit
void bindJobs(py::module_& module);         // run_spec, fit_table, prefilter, matcap, ibl
void bindEnvironment(py::module_& module);  // Environment
void bindIbl(py::module_& module);          // ibl, Ibl

}  // namespace brdfbake::python
