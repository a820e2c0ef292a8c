// The jobs as Python calls, each run by runJob on a Context (threads, progress, KeyboardInterrupt):
// run_spec (runSpec), fit_table (fitTable), and, in memory, prefilter (prefilterEnvironment), matcap
// (makeMatcap) and ibl (makeIbl). The package's bake(), fit(), prefilter(), matcap() and ibl() call
// these (python/brdfbake/__init__.py).
#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/run/fit_table.hpp>
#include <brdfbake/run/ibl_job.hpp>
#include <brdfbake/run/matcap_job.hpp>
#include <brdfbake/run/prefilter_job.hpp>
#include <brdfbake/run/spec_runner.hpp>
#include <brdfbake/spec/material_file.hpp>
#include <brdfbake/spec/spec.hpp>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <sstream>

#include "bindings.hpp"
#include "convert.hpp"
#include "job_runner.hpp"

namespace brdfbake::python {

namespace {

SpecRunResult runSpecJob(const std::optional<std::filesystem::path>& spec, const py::object& document,
                         const std::optional<std::filesystem::path>& outDir, int threads, bool allowLarge,
                         const std::string& label, const py::object& progress) {
  SpecRunOptions options;
  if (spec) options.spec = *spec;
  if (!document.is_none()) options.document = jsonFromPython(document, label);
  options.label = label;
  if (outDir) options.outDir = *outDir;
  options.inMemory = true;  // a map without "output" comes back as MapResult.map
  options.validate();
  SpecRunResult result;
  runJob([&](const Context& context) { result = runSpec(options, context); }, progress, threads, allowLarge);
  return result;
}

// "auto" (nullopt) or a number in [lowest, highest] (whole when `whole`); errors name the keyword.
std::optional<double> autoOrNumber(const py::object& value, const char* keyword, double lowest, double highest,
                                   bool whole) {
  if (py::isinstance<py::str>(value) && value.cast<std::string>() == "auto") return std::nullopt;
  const bool number =
      !PyBool_Check(value.ptr()) && (PyLong_Check(value.ptr()) || (!whole && PyFloat_Check(value.ptr())));
  if (number) {
    const double x = value.cast<double>();
    if (x >= lowest && x <= highest) return x;
  }
  std::ostringstream text;
  text << keyword << ": expected \"auto\" or a " << (whole ? "whole " : "") << "number in [" << lowest << ", "
       << highest << "], got " << std::string(py::repr(value)).substr(0, 40);
  throw Error(Error::Kind::InvalidArgument, text.str());
}

FitTableResult fitTableJob(const std::filesystem::path& table, const py::object& lobes, const std::string& kind,
                           const std::string& elevation, const std::string& method, const py::object& maxExponent,
                           const py::object& varyingPrior, const std::string& colorProfile,
                           const std::string& halfDifference, bool heldOut, int folds, const std::string& channels,
                           const std::string& rgb, const std::string& format,
                           const std::optional<std::filesystem::path>& output,
                           const std::optional<std::filesystem::path>& report, int threads,
                           const py::object& progress) {
  FitTableOptions options;
  options.table = table;
  options.format = parseNamed("format", format, parseTableFormat);
  FitOptions& fit = options.fit;
  fit.lobes = static_cast<int>(autoOrNumber(lobes, "lobes", 1, kMaxFitLobes, true).value_or(0));
  fit.kind = parseNamed("kind", kind, parseLobeKindChoice);
  fit.elevation = parseNamed("elevation", elevation, parseElevationChoice);
  fit.method = parseNamed("method", method, parseFitMethod);
  if (const auto cap = autoOrNumber(maxExponent, "max_exponent", 1, 1e5, false)) {
    fit.maxExponent = *cap;
    fit.chooseMaxExponent = false;
  }
  if (const auto prior = autoOrNumber(varyingPrior, "varying_prior", 0, 1, false)) {
    fit.varyingPrior = *prior;
    fit.chooseVaryingPrior = false;
  }
  fit.colorProfile = parseNamed("color_profile", colorProfile, parseColorProfileChoice);
  require(halfDifference == "auto" || halfDifference == "none",
          "half_difference: expected auto or none, got '" + halfDifference + "'");
  fit.halfDifference = halfDifference == "auto";
  fit.estimateHeldOut = heldOut;
  require(folds >= 2 && folds <= 20, "folds: expected 2..20, got " + std::to_string(folds));
  fit.heldOut.folds = folds;
  require(channels == "rgb" || channels == "spectral", "channels: expected rgb or spectral, got '" + channels + "'");
  options.spectral = channels == "spectral";
  options.rgb = parseNamed("rgb", rgb, parseRgbMethod);
  if (output) options.output = *output;
  if (report) options.report = *report;
  options.validate();
  auto result = std::make_shared<FitTableResult>();
  runJob([&](const Context& context) { *result = fitTable(options, context); }, progress, threads);
  return std::move(*result);
}

std::optional<Vec3> optionalVector(const py::object& value, const char* keyword) {
  if (value.is_none()) return std::nullopt;
  const Directions d = directionsFromPython(value, keyword);
  if (!d.single) throw Error(Error::Kind::InvalidArgument, std::string(keyword) + ": expected one (3,) direction");
  requireDirections(d, keyword);
  return d[0];
}

// f(), an error naming a request field named by its keyword: {"parameterization", "to"}.
template <class F>
auto namingKeywords(const std::vector<std::pair<std::string, std::string>>& renamed, F&& f) {
  try {
    return f();
  } catch (const Error& error) {
    if (error.field().empty()) throw;
    std::string keyword = error.field();
    for (const auto& [field, name] : renamed)
      if (field == keyword) keyword = name;
    throw Error(error.kind(), keyword + ": " + error.problem());
  }
}

// ---- prefilter ----------------------------------------------------------------------------------

py::object prefilterJob(const py::object& environment, const std::optional<std::string>& from,
                        const LobeArguments& lobe, const std::string& to, const std::string& method,
                        const std::optional<std::string>& combine, std::optional<double> fresnelIor, PrefilterRequest r,
                        const std::optional<std::filesystem::path>& output,
                        const std::optional<std::filesystem::path>& shOutput, bool tiled, bool faces, int threads,
                        const py::object& progress) {
  const std::vector<std::pair<std::string, std::string>> keywords = {{"parameterization", "to"},
                                                                     {"fresnel", "fresnel_ior"},
                                                                     {"sh", "sh_output"},
                                                                     {"gloss_chain", "gloss_scale"},
                                                                     {"outputs", "output"}};
  return namingKeywords(keywords, [&]() -> py::object {
    lobe.apply(r);
    r.parameterization = parseNamed("to", to, parseParameterizationKind);
    r.method = parseNamed("method", method, parsePrefilterMethod);
    if (fresnelIor) r.fresnel = FresnelTerm::dielectric(Rgb::Constant(*fresnelIor));
    if (combine) r.combine = parseNamed("combine", *combine, parseFresnelCombine);
    r.sh = shOutput.has_value();
    requireField(!shOutput || output, "sh_output", "writes a file beside the map's: give output=PATH too");
    const bool several = r.fresnel || (r.lobeModel && r.lobeModel->variesWithView());
    requireField(!several || output, "output",
                 "a Fresnel decomposition or an elevation stack is several maps: give output=PATH (read_map reads "
                 "them back)");
    r.environment = environmentFromPython(environment, from);
    PrefilterResult made;
    runJob([&](const Context& context) { made = prefilterEnvironment(r, context); }, progress, threads);
    MapOutputs outputs;
    outputs.layout = faces ? CubeLayout::Faces : CubeLayout::Cross;
    outputs.mipLayout = tiled ? MipLayout::Tiled : MipLayout::Files;
    auto shared = std::make_shared<const PrefilterResult>(std::move(made));
    std::optional<ShOutput> sh;
    if (shOutput) sh = ShOutput{*shOutput, shOutput->extension() == ".txt"};
    std::vector<std::filesystem::path> written;
    if (output) {
      outputs.files = {*output};
      const py::gil_scoped_release release;
      written = writePrefiltered(*shared, outputs, sh).files;
    }
    if (several) {
      OutputSource source;
      source.path = *output;
      auto map = openMap(source);
      map->result = pythonFromJson(shared->toJson());
      return py::cast(map);
    }
    const MapInfo info = prefilteredMapInfo(shared->map, nlohmann::json(), 0);
    auto writer = [shared](const MapOutputs& o) { return writePrefiltered(*shared, o); };
    auto map = mapInMemory(shared->map.levels, info, shared->toJson(), writer);
    if (output) map->source.path = *output, map->written = written;
    return py::cast(map);
  });
}

void bindPrefilter(py::module_& module) {
  module.def(
      "prefilter",
      [](const py::object& environment, const std::string& lobe, const std::string& to, int resolution,
         const std::optional<std::filesystem::path>& output, const std::string& method, double maxError,
         const std::optional<std::string>& from, bool mips, bool tiled, bool faces, const py::object& view,
         const py::object& up, int samplesPerTexel, std::optional<int> elevations, std::optional<double> fresnelIor,
         const std::optional<std::string>& combine, const std::optional<std::string>& chain,
         std::optional<double> glossScale, std::optional<double> glossBias, std::optional<int> mipCount, bool edgeFixup,
         const std::optional<std::filesystem::path>& shOutput, int threads, const py::object& progress) {
        const LobeArguments lobeArguments{lobe, chain, glossScale, glossBias, mipCount, edgeFixup};
        PrefilterRequest r;
        r.resolution = resolution;
        r.maxError = maxError;
        r.mips = mips;
        if (const auto v = optionalVector(view, "view")) r.view = *v;
        if (const auto u = optionalVector(up, "up")) r.up = *u;
        r.samplesPerTexel = samplesPerTexel;
        if (elevations) r.elevations = *elevations;
        return prefilterJob(environment, from, lobeArguments, to, method, combine, fresnelIor, r, output, shOutput,
                            tiled, faces, threads, progress);
      },
      py::arg("environment"), py::arg("lobe"), py::arg("to"), py::arg("resolution"), py::arg("output"),
      py::arg("method"), py::arg("max_error"), py::arg("from_"), py::arg("mips"), py::arg("tiled"), py::arg("faces"),
      py::arg("view"), py::arg("up"), py::arg("samples_per_texel"), py::arg("elevations"), py::arg("fresnel_ior"),
      py::arg("combine"), py::arg("chain"), py::arg("gloss_scale"), py::arg("gloss_bias"), py::arg("mip_count"),
      py::arg("edge_fixup"), py::arg("sh_output"), py::arg("threads"), py::arg("progress"),
      "prefilterEnvironment (run/prefilter_job.hpp) in memory, written too when output is given; use "
      "brdfbake.prefilter.");
}

// ---- matcap -------------------------------------------------------------------------------------

// A material file (loadMaterialFile), its errors naming the keyword.
MaterialFile materialFromFile(const std::filesystem::path& path, const Context& context) {
  require(!path.empty(), "material: an empty path");
  try {
    return loadMaterialFile(path, context);
  } catch (const Error& e) {
    throw Error(e.kind(), "material: " + std::string(e.what()));
  }
}

// A material given as a dict in the spec's form or a Fit (a path: materialFromFile, whose fit of a
// measured table runs on the job's context).
MaterialFile materialFromPython(const py::object& material) {
  if (py::isinstance<FitTableResult>(material)) {
    MaterialFile file;
    file.kind = "fit";
    file.material = std::make_shared<LobeMaterial>(material.cast<const FitTableResult&>().file.fit.model,
                                                   LobeMaterialMode::Lighting, "lobes");
    file.description = {{"model", "lobes"}};
    return file;
  }
  if (py::isinstance<py::dict>(material)) {
    const nlohmann::json object = jsonFromPython(material, "material");
    const py::gil_scoped_release release;
    return parseMaterialObject(object, std::filesystem::current_path(), "material");
  }
  throw py::type_error("material: expected a path, a dict ({\"model\": ...}) or a brdfbake.Fit, got " +
                       std::string(py::str(material.get_type())));
}

py::object matcapJob(const py::object& material, const py::object& environment, MatcapRequest r,
                     const std::string& parameterization, const std::string& method, const py::object& camera,
                     const std::optional<std::filesystem::path>& output, int threads, const py::object& progress) {
  return namingKeywords({}, [&]() -> py::object {
    r.parameterization = parseNamed("parameterization", parameterization, parseParameterizationKind);
    r.method = parseNamed("method", method, parseUnderEnvironmentMethod);
    if (!camera.is_none()) {
      const auto angles = camera.cast<std::vector<double>>();
      requireField(angles.size() == 2, "camera", "expected (yaw, pitch) in degrees");
      r.camera = CameraFrame::fromYawPitch(angles[0], angles[1]);
    }
    r.environment = environmentFromPython(environment, std::nullopt);
    std::optional<std::filesystem::path> path;
    MaterialFile file;
    if (py::isinstance<py::str>(material) || py::hasattr(material, "__fspath__")) {
      path = material.cast<std::filesystem::path>();
    } else {
      file = materialFromPython(material);
    }
    auto made = std::make_shared<MatcapResult>();
    runJob(
        [&](const Context& context) {
          if (path) file = materialFromFile(*path, context);  // a measured table is fitted here
          r.material = file.material;
          r.materialDescription = file.description;
          *made = makeMatcap(r, context);
        },
        progress, threads);
    auto writer = [made](const MapOutputs& o) { return writeMatcap(*made, o); };
    std::vector<std::filesystem::path> written;
    if (output) {
      MapOutputs outputs;
      outputs.files = {*output};
      const py::gil_scoped_release release;
      written = writer(outputs).files;
    }
    auto map =
        mapInMemory({made->map.image}, underEnvironmentMapInfo(made->map, made->description), made->toJson(), writer);
    if (output) map->source.path = *output, map->written = written;
    return py::cast(map);
  });
}

void bindMatcap(py::module_& module) {
  module.def(
      "matcap",
      [](const py::object& material, const py::object& environment, int resolution, double maxError,
         std::optional<double> maxRelativeError, const std::string& method, const py::object& camera,
         const std::string& parameterization, int samplesPerTexel, double exposure,
         const std::optional<std::filesystem::path>& output, int threads, const py::object& progress) {
        MatcapRequest r;
        r.resolution = resolution;
        r.maxError = maxError;
        r.maxRelativeError = maxRelativeError;
        r.samplesPerTexel = samplesPerTexel;
        r.exposure = exposure;
        return matcapJob(material, environment, r, parameterization, method, camera, output, threads, progress);
      },
      py::arg("material"), py::arg("environment"), py::arg("resolution"), py::arg("max_error"),
      py::arg("max_relative_error"), py::arg("method"), py::arg("camera"), py::arg("parameterization"),
      py::arg("samples_per_texel"), py::arg("exposure"), py::arg("output"), py::arg("threads"), py::arg("progress"),
      "makeMatcap (run/matcap_job.hpp) in memory, written too when output is given; use brdfbake.matcap.");
}

}  // namespace

void bindJobs(py::module_& module) {
  module.def("run_spec", &runSpecJob, py::arg("spec"), py::arg("document"), py::arg("out_dir"), py::arg("threads"),
             py::arg("allow_large"), py::arg("label"), py::arg("progress"),
             "runSpec (run/spec_runner.hpp) on a spec file or a document; use brdfbake.bake.");
  module.def("fit_table", &fitTableJob, py::arg("table"), py::arg("lobes"), py::arg("kind"), py::arg("elevation"),
             py::arg("method"), py::arg("max_exponent"), py::arg("varying_prior"), py::arg("color_profile"),
             py::arg("half_difference"), py::arg("held_out"), py::arg("folds"), py::arg("channels"), py::arg("rgb"),
             py::arg("format"), py::arg("output"), py::arg("report"), py::arg("threads"), py::arg("progress"),
             "fitTable (run/fit_table.hpp); use brdfbake.fit.");
  bindPrefilter(module);
  bindMatcap(module);
}

}  // namespace brdfbake::python
