// brdfbake.ibl and brdfbake.Ibl: engine-ready image-based lighting made in memory (makeIbl), its cube
// maps as (6, N, N, 4) arrays in the face order of docs/conventions.md, written on demand (writeIbl).
#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/run/ibl_job.hpp>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cstring>

#include "bindings.hpp"
#include "convert.hpp"
#include "job_runner.hpp"

namespace brdfbake::python {

namespace {

constexpr const char* kIblDoc = R"(Engine-ready image-based lighting, in memory (brdfbake.ibl makes it).

specular: the GGX chain, one (6, N >> k, N >> k, 4) float32 array per level k of L; level k holds GGX
  of perceptual roughness k / (L - 1) (level 0 the mirror), read at lod = R (L - 1).
irradiance: (6, n, n, 4), E/pi at the normal. sh: (9, 3), the irradiance's spherical-harmonic
  coefficients (E/pi, orthonormal basis). skybox: (6, M, M, 4), the environment as a cube.
dfg: (D, D, 2), the split-sum DFG table: n.v along the columns, perceptual roughness along the rows.
Faces are in OpenGL order +X, -X, +Y, -Y, +Z, -Z, each as cube-map tools write them (docs/conventions.md).
save(out_dir, ...) writes the files `brdfbake ibl` writes, as one set.)";

// A cube cross (4N x 3N) as a (6, N, N, 4) array, faces in OpenGL order.
py::array_t<float> cubeFaces(const Image& cross) {
  const int n = cross.width() / 4;
  const CubeMap cube(n);
  py::array_t<float> faces({6, n, n, 4});
  float* out = faces.mutable_data();
  for (int face = 0; face < 6; ++face) {
    const TexelRect r = cube.region(face);
    for (int y = 0; y < n; ++y) {
      std::memcpy(out + ((static_cast<std::size_t>(face) * n + y) * n) * 4, cross.data() + cross.index(r.x0, r.y0 + y),
                  sizeof(float) * 4 * n);
    }
  }
  return faces;
}

py::array_t<double> shArray(const ShExpansion& sh) {
  const auto count = static_cast<py::ssize_t>(sh.coefficients.size());
  py::array_t<double> array({count, static_cast<py::ssize_t>(3)});
  for (py::ssize_t i = 0; i < count; ++i)
    for (int c = 0; c < 3; ++c) array.mutable_at(i, c) = sh.coefficients[static_cast<std::size_t>(i)][c];
  return array;
}

py::array_t<float> dfgArray(const Image& table) {
  py::array_t<float> array({table.height(), table.width(), 2});
  for (int y = 0; y < table.height(); ++y)
    for (int x = 0; x < table.width(); ++x)
      for (int c = 0; c < 2; ++c) array.mutable_at(y, x, c) = static_cast<float>(table.at(x, y)[c]);
  return array;
}

struct PythonIbl {
  std::shared_ptr<const IblResult> result;
};

py::object saveIbl(const PythonIbl& ibl, const std::filesystem::path& folder, const std::string& format,
                   const std::string& stem, const std::optional<std::string>& texelFormat,
                   const std::string& shFormat) {
  IblOutputs outputs;
  outputs.folder = folder;
  outputs.format = format;
  outputs.stem = stem;
  if (texelFormat) outputs.texelFormat = parseNamed("texel_format", *texelFormat, parseTexelFormat);
  outputs.shCmgen = parseNamed("sh_format", shFormat, parseShFormat) == ShFormat::Cmgen;
  IblReport report;
  try {
    const py::gil_scoped_release release;
    report = writeIbl(*ibl.result, outputs);
  } catch (const Error& e) {
    if (e.field().empty()) throw;
    throw Error(e.kind(), (e.field() == "out_dir" ? "out_dir" : e.field()) + ": " + e.problem());
  }
  return pythonFromJson(report.toJson());
}

}  // namespace

void bindIbl(py::module_& module) {
  py::class_<PythonIbl>(module, "Ibl", kIblDoc)
      .def_property_readonly("specular",
                             [](const PythonIbl& ibl) {
                               py::list levels;
                               for (const Image& level : ibl.result->specular.map.levels)
                                 levels.append(cubeFaces(level));
                               return levels;
                             })
      .def_property_readonly("irradiance",
                             [](const PythonIbl& ibl) { return cubeFaces(ibl.result->irradiance.map.levels.front()); })
      .def_property_readonly("sh", [](const PythonIbl& ibl) { return shArray(*ibl.result->irradiance.sh); })
      .def_property_readonly("skybox",
                             [](const PythonIbl& ibl) { return cubeFaces(ibl.result->skybox.map.levels.front()); })
      .def_property_readonly("dfg", [](const PythonIbl& ibl) { return dfgArray(ibl.result->dfg); })
      .def(
          "to_json", [](const PythonIbl& ibl) { return pythonFromJson(ibl.result->toJson()); },
          "Each part's summary: method, error estimate, seconds.")
      .def("save", &saveIbl, py::arg("out_dir"), py::kw_only(), py::arg("format") = "ktx2", py::arg("stem") = "ibl",
           py::arg("texel_format") = py::none(), py::arg("sh_format") = "brdfbake",
           "Writes the files `brdfbake ibl` writes into out_dir, as one set (none replaced unless all are "
           "written); returns what `brdfbake ibl --json` prints.")
      .def("__repr__", [](const PythonIbl& ibl) {
        const auto& levels = ibl.result->specular.map.levels;
        return "<brdfbake.Ibl specular " + std::to_string(levels.front().width() / 4) + " (" +
               std::to_string(levels.size()) + " levels)>";
      });

  module.def(
      "ibl",
      [](const py::object& environment, int resolution, int irradianceResolution, int skyboxResolution, int dfgSize,
         const std::string& dfgForm, double maxError, int threads, const py::object& progress) {
        IblRequest request;
        request.resolution = resolution;
        request.irradianceResolution = irradianceResolution;
        request.skyboxResolution = skyboxResolution;
        request.dfgSize = dfgSize;
        request.maxError = maxError;
        request.dfgForm = parseNamed("dfg_form", dfgForm, parseDfgForm);
        request.environment = environmentFromPython(environment, std::nullopt);
        auto result = std::make_shared<IblResult>();
        try {
          runJob([&](const Context& context) { *result = makeIbl(request, context); }, progress, threads);
        } catch (const Error& e) {
          if (e.field().empty()) throw;
          throw Error(e.kind(), e.field() + ": " + e.problem());
        }
        return PythonIbl{result};
      },
      py::arg("environment"), py::arg("resolution"), py::arg("irradiance_resolution"), py::arg("skybox_resolution"),
      py::arg("dfg_size"), py::arg("dfg_form"), py::arg("max_error"), py::arg("threads"), py::arg("progress"),
      "makeIbl (run/ibl_job.hpp) in memory; use brdfbake.ibl.");
}

}  // namespace brdfbake::python
