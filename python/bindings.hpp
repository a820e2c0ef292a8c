#pragma once
// The parts of the extension brdfbake._core, each adding its classes and functions to the module.
#include <brdfbake/output/baked_output.hpp>
#include <brdfbake/run/sample_output.hpp>

#include <pybind11/pybind11.h>

#include <memory>

namespace brdfbake::python {

namespace py = pybind11;

/// An output of bake or prefilter read back (brdfbake.Map): BakedOutput, how it was opened, and
/// what made it when the module made it (prefilter's entry).
struct OpenedMap {
  OutputSource source;
  std::shared_ptr<const BakedOutput> output;
  py::object result = py::none();
  py::object pixelsRead;  // the pixels of kinds other than Map, read on first use
};

/// Opens `source` without the GIL. Throws what BakedOutput::open throws.
std::shared_ptr<OpenedMap> openMap(const OutputSource& source);

void bindMaps(py::module_& module);     // Map, read_map
void bindResults(py::module_& module);  // BakeResult, MapResult, Fit
void bindJobs(py::module_& module);     // run_spec, fit_table, prefilter_environment, write_environment

}  // namespace brdfbake::python
