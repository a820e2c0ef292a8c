// brdfbake._core: the extension behind the brdfbake package (python/brdfbake/__init__.py). A thin
// front over the run layer, as the brdfbake tool is: each function fills a job's options, runs the
// job (job_runner.hpp) and returns its result.
#include <brdfbake/core/version.hpp>

#include "bindings.hpp"
#include "convert.hpp"

namespace py = pybind11;
using brdfbake::Error;

PYBIND11_MODULE(_core, module) {
  module.doc() = "The extension behind the brdfbake package; use the package (import brdfbake), not this module.";
  // brdfbake::Error becomes brdfbake.Error's subclass for its kind (brdfbake/_errors.py).
  py::register_exception_translator([](std::exception_ptr failure) {
    try {
      if (failure) std::rethrow_exception(failure);
    } catch (const Error& error) {
      try {
        const py::object type = brdfbake::python::errorClass(error.kind());
        PyErr_SetObject(type.ptr(), type(error.what()).ptr());
      } catch (py::error_already_set& unexpected) {
        unexpected.restore();
      }
    }
  });
  brdfbake::python::bindResults(module);
  brdfbake::python::bindMaps(module);
  brdfbake::python::bindEnvironment(module);
  brdfbake::python::bindJobs(module);
  brdfbake::python::bindIbl(module);
  module.attr("version") = BRDFBAKE_VERSION_STRING;
}
