// The jobs as Python calls: run_spec (runSpec), fit_table (fitTable), prefilter_environment
// (prefilterEnvironment), each run by runJob; and write_environment, which writes a numpy
// environment to the image file prefilter reads. The package's bake(), fit() and prefilter() call
// these (python/brdfbake/__init__.py).
#include <brdfbake/maps/image_io.hpp>
#include <brdfbake/run/fit_table.hpp>
#include <brdfbake/run/prefilter_job.hpp>
#include <brdfbake/run/spec_runner.hpp>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <sstream>

#include "bindings.hpp"
#include "convert.hpp"
#include "job_runner.hpp"

namespace brdfbake::python {

namespace {

JobOptions jobOptions(int threads, bool allowLarge) {
  JobOptions options;
  options.threads = threads;
  options.allowLarge = allowLarge;
  options.validate();
  return options;
}

SpecRunResult runSpecJob(const std::optional<std::filesystem::path>& spec, const py::object& document,
                         const std::optional<std::filesystem::path>& outDir, int threads, bool allowLarge,
                         const std::string& label, const py::object& progress) {
  SpecRunOptions options;
  static_cast<JobOptions&>(options) = jobOptions(threads, allowLarge);
  if (spec) options.spec = *spec;
  if (!document.is_none()) options.document = jsonFromPython(document, label);
  options.label = label;
  if (outDir) options.outDir = *outDir;
  options.validate();
  SpecRunResult result;
  runJob(
      [&](const ProgressSink& sink) {
        SpecRunOptions withProgress = options;
        withProgress.progress = sink;
        result = runSpec(withProgress);
      },
      progress);
  return result;
}

// A name of `parse`'s set; errors name the keyword.
template <class Parse>
auto parseNamed(const char* keyword, const std::string& name, Parse parse) {
  try {
    return parse(name);
  } catch (const Error& e) {
    throw Error(e.kind(), std::string(keyword) + ": " + e.what());
  }
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
  static_cast<JobOptions&>(options) = jobOptions(threads, false);
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
  require(rgb == "cie1931" || rgb == "single_wavelengths",
          "rgb: expected cie1931 or single_wavelengths, got '" + rgb + "'");
  options.rgb = rgb == "cie1931" ? RgbMethod::Cie1931 : RgbMethod::SingleWavelengths;
  if (output) options.output = *output;
  if (report) options.report = *report;
  options.validate();
  auto result = std::make_shared<FitTableResult>();
  runJob(
      [&](const ProgressSink& sink) {
        FitTableOptions withProgress = options;
        withProgress.progress = sink;
        *result = fitTable(withProgress);
      },
      progress);
  return std::move(*result);
}

std::optional<Vec3> optionalVector(const py::object& value, const char* keyword) {
  if (value.is_none()) return std::nullopt;
  const Directions d = directionsFromPython(value, keyword);
  if (!d.single) throw Error(Error::Kind::InvalidArgument, std::string(keyword) + ": expected one (3,) direction");
  requireDirections(d, keyword);
  return d[0];
}

void bindPrefilter(py::module_& module) {
  module.def(
      "prefilter_environment",
      [](const std::filesystem::path& environment, const std::string& lobe, const std::string& to, int resolution,
         const std::filesystem::path& output, const std::string& method, double maxError,
         const std::optional<std::string>& from, bool mips, bool tiled, bool faces, const py::object& view,
         const py::object& up, int samplesPerTexel, std::optional<int> elevations, std::optional<double> fresnelIor,
         const std::optional<std::string>& combine, std::optional<double> glossScale, std::optional<double> glossBias,
         std::optional<int> mipCount, bool edgeFixup, const std::optional<std::filesystem::path>& shOutput, int threads,
         const py::object& progress) {
        PrefilterRequest r;
        r.environment = environment;
        r.lobe = lobe;
        r.to = to;
        r.output = output;
        r.resolution = resolution;
        r.method = method;
        r.maxError = maxError;
        r.from = from;
        r.mips = mips;
        r.tiled = tiled;
        r.faces = faces;
        r.view = optionalVector(view, "view");
        r.up = optionalVector(up, "up");
        r.samplesPerTexel = samplesPerTexel;
        r.elevations = elevations;
        r.fresnelIor = fresnelIor;
        r.combine = combine;
        r.glossScale = glossScale;
        r.glossBias = glossBias;
        r.mipCount = mipCount;
        r.edgeFixup = edgeFixup;
        r.shOutput = shOutput;
        const JobOptions options = jobOptions(threads, false);
        MapResult made;
        runJob(
            [&](const ProgressSink& sink) {
              JobOptions withProgress = options;
              withProgress.progress = sink;
              made = prefilterEnvironment(r, withProgress);
            },
            progress);
        OutputSource source;
        source.path = made.output;
        std::shared_ptr<OpenedMap> map = openMap(source);
        map->result = pythonFromJson(made.toJson());
        return map;
      },
      py::arg("environment"), py::arg("lobe"), py::arg("to"), py::arg("resolution"), py::arg("output"),
      py::arg("method"), py::arg("max_error"), py::arg("from_"), py::arg("mips"), py::arg("tiled"), py::arg("faces"),
      py::arg("view"), py::arg("up"), py::arg("samples_per_texel"), py::arg("elevations"), py::arg("fresnel_ior"),
      py::arg("combine"), py::arg("gloss_scale"), py::arg("gloss_bias"), py::arg("mip_count"), py::arg("edge_fixup"),
      py::arg("sh_output"), py::arg("threads"), py::arg("progress"),
      "prefilterEnvironment (run/prefilter_job.hpp), then the map read back; use brdfbake.prefilter.");
}

// An (H, W, 3 or 4) array of radiance as a float RGBA image (alpha 1 where not given).
Image environmentImage(const py::object& value) {
  const auto array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!array || array.ndim() != 3 || (array.shape(2) != 3 && array.shape(2) != 4) || array.shape(0) < 1 ||
      array.shape(1) < 1) {
    std::ostringstream shape;
    if (array)
      for (py::ssize_t i = 0; i < array.ndim(); ++i) shape << (i ? ", " : "") << array.shape(i);
    throw Error(
        Error::Kind::InvalidArgument,
        "environment: expected an (H, 2H, 3) array of radiance (a lat-long image, row 0 at the top)" +
            (array ? ", got shape (" + shape.str() + ")" : ", got a " + std::string(py::str(value.get_type()))));
  }
  const int height = static_cast<int>(array.shape(0)), width = static_cast<int>(array.shape(1));
  const int channels = static_cast<int>(array.shape(2));
  Image image(width, height, Rgba::Ones());
  const float* in = array.data();
  float* out = image.data();
  for (std::size_t i = 0; i < static_cast<std::size_t>(width) * height; ++i) {
    for (int c = 0; c < channels; ++c) {
      const float v = in[i * channels + c];
      if (!std::isfinite(v)) {
        std::ostringstream text;
        text << "environment[" << i / width << ", " << i % width << ", " << c << "]: radiance must be finite, got "
             << v;
        throw Error(Error::Kind::InvalidArgument, text.str());
      }
      out[4 * i + c] = v;
    }
  }
  return image;
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
  module.def(
      "write_environment",
      [](const py::object& array, const std::filesystem::path& path) {
        const Image image = environmentImage(array);
        const py::gil_scoped_release release;
        writeImage(image, path);
      },
      py::arg("array"), py::arg("path"),
      "Writes an (H, W, 3|4) float array of radiance as a plain image (OpenEXR) for prefilter to read.");
}

}  // namespace brdfbake::python
