// The results of the jobs as Python objects: brdfbake.BakeResult and brdfbake.MapResult (runSpec,
// run/spec_runner.hpp) and brdfbake.Fit (fitTable, run/fit_table.hpp). Each has to_json(), the
// dict the tool prints with --json, and brief_report(), the text it prints without.
#include <brdfbake/io/files.hpp>
#include <brdfbake/run/fit_table.hpp>
#include <brdfbake/run/spec_runner.hpp>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <limits>

#include "bindings.hpp"
#include "convert.hpp"

namespace brdfbake::python {

namespace {

constexpr const char* kEvaluateDoc =
    R"(The fitted BRDF (1/sr, per channel) for lights wi and views wo, as `brdfbake eval` gives it.

wi, wo: (N, 3) arrays of directions in the local frame (z the normal), both pointing away from the
surface, any length but 0 (normalised here); one of them may be a single (3,) direction used for every
row. Returns an (N, C) float64 array (C = len(channel_names)), or (C,) when both are single; 0 where a
direction is at or below the horizon. Runs in parallel without the GIL.)";

// fit.json's document and a part of it.
nlohmann::ordered_json fitDocument(const FitTableResult& fit) { return fitFileToJson(fit.file); }

py::object fitPart(const FitTableResult& fit, const char* section, const char* key = nullptr) {
  const nlohmann::ordered_json document = fitDocument(fit);
  if (!document.contains(section)) return py::none();
  const auto& part = document[section];
  if (!key) return pythonFromJson(part);
  return part.contains(key) ? pythonFromJson(part[key]) : py::none();
}

py::object evaluateFit(const FitTableResult& fit, const py::object& wi, const py::object& wo) {
  const Directions lights = directionsFromPython(wi, "wi"), views = directionsFromPython(wo, "wo");
  requireDirections(lights, "wi");
  requireDirections(views, "wo");
  if (lights.count != views.count && !lights.single && !views.single) {
    throw Error(Error::Kind::InvalidArgument, "wi and wo: " + std::to_string(lights.count) + " and " +
                                                  std::to_string(views.count) +
                                                  " directions; give as many of each, or one of either");
  }
  const LobeModel& model = fit.file.fit.model;
  const std::size_t count = std::max(lights.count, views.count), channels = model.channelCount();
  py::array_t<double> values = resultRows(count, channels, lights.single && views.single);
  double* out = values.mutable_data();
  std::atomic<std::size_t> firstBad{std::numeric_limits<std::size_t>::max()};
  {
    const py::gil_scoped_release release;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1024), [&](const auto& rows) {
      for (std::size_t i = rows.begin(); i < rows.end(); ++i) {
        const Vec3 l = lights[lights.single ? 0 : i].normalized(), v = views[views.single ? 0 : i].normalized();
        const Eigen::VectorXd value = model.evaluate(l, v);
        if (!value.allFinite()) {
          for (std::size_t seen = firstBad.load(); i < seen && !firstBad.compare_exchange_weak(seen, i);) {
          }
        }
        for (std::size_t c = 0; c < channels; ++c) out[channels * i + c] = value[static_cast<Eigen::Index>(c)];
      }
    });
  }
  if (firstBad.load() != std::numeric_limits<std::size_t>::max()) {
    throw Error(Error::Kind::Numerical,
                "row " + std::to_string(firstBad.load()) + ": the model gave a non-finite value");
  }
  return values;
}

void saveFit(const FitTableResult& fit, const std::filesystem::path& path) {
  FilePlan plan;
  plan.addInput(fit.table, "table");
  plan.addOutput(path, "fit.json output");
  plan.check();
  const py::gil_scoped_release release;
  writeFitFile(path, fit.file);
}

void bindSpecResults(py::module_& module) {
  py::class_<MapResult>(module, "MapResult", "One map of a spec as made: what was written and how.")
      .def_readonly("json_path", &MapResult::jsonPath, "The map's place in the spec: \"maps[0]\".")
      .def_readonly("output", &MapResult::output, "The map's output path, placed in the output folder.")
      .def_readonly("written", &MapResult::written, "False when making it failed (error says why).")
      .def_readonly("error", &MapResult::error, "The failure's message, or \"\".")
      .def_readonly("files", &MapResult::files, "Every file written (faces, mip levels, sidecars, ...).")
      .def_readonly("notes", &MapResult::notes)
      .def_property_readonly(
          "map",
          [](const MapResult& m) -> py::object {
            if (!m.made) return py::none();
            return py::cast(mapInMemory(m.made->levels, m.made->info, m.entry, m.made->write));
          },
          "The map as a brdfbake.Map when the spec named no output for it (made in memory only), else None.")
      .def(
          "to_json", [](const MapResult& m) { return pythonFromJson(m.toJson()); },
          "The map's entry as `brdfbake bake --json` prints it: output, status, files, parameterization, "
          "resolution, width, height, bake_path, bake_seconds, write_seconds, notes, and its kind's keys.")
      .def("brief_report", &MapResult::briefReport, "The lines `brdfbake bake` prints for the map.")
      .def("__repr__", [](const MapResult& m) {
        if (m.made) return "<brdfbake.MapResult " + m.jsonPath + " in memory>";
        return "<brdfbake.MapResult " + m.jsonPath + " " + (m.written ? "written" : "failed") + " '" +
               m.output.string() + "'>";
      });

  py::class_<SpecRunResult>(module, "BakeResult",
                            "A spec run (brdfbake.bake): every map's result, in the spec's order.")
      .def_readonly("spec", &SpecRunResult::spec, "The spec file, or \"spec\" for a dict.")
      .def_readonly("maps", &SpecRunResult::maps, "A MapResult per map of the spec.")
      .def_readonly("files", &SpecRunResult::files, "Every file written, all maps.")
      .def_readonly("notes", &SpecRunResult::notes)
      .def_property_readonly("failed", &SpecRunResult::failed, "How many maps failed.")
      .def_property_readonly(
          "_first_error",
          [](const SpecRunResult& r) -> py::object {
            if (!r.firstError) return py::none();
            return py::make_tuple(kindName(r.firstError->kind()), r.firstError->what());
          },
          "The first failure as (kind, message), or None (brdfbake.bake raises it).")
      .def(
          "to_json", [](const SpecRunResult& r) { return pythonFromJson(r.toJson()); },
          "What `brdfbake bake --json` prints: {\"spec\": ..., \"maps\": [each map's entry]}.")
      .def("brief_report", &SpecRunResult::briefReport, "The text `brdfbake bake` prints.")
      .def("__repr__", [](const SpecRunResult& r) {
        return "<brdfbake.BakeResult '" + r.spec.string() + "': " + std::to_string(r.maps.size()) + " map(s), " +
               std::to_string(r.failed()) + " failed>";
      });
}

void bindFitResult(py::module_& module) {
  py::class_<FitTableResult, std::shared_ptr<FitTableResult>>(
      module, "Fit", "Lobes fitted to a measured table (brdfbake.fit), with the fit's statistics and held-out error.")
      .def_readonly("table", &FitTableResult::table, "The table as given.")
      .def_readonly("samples", &FitTableResult::samples, "Rows of the table as read.")
      .def_readonly("files", &FitTableResult::files, "Files written by fit() (output, report).")
      .def_readonly("notes", &FitTableResult::notes, "The table's notes (clamped negatives, conversions).")
      .def_property_readonly(
          "usable", [](const FitTableResult& f) { return f.file.fit.usable(); },
          "False when a solve failed (the fit is still saved, with \"usable\": false).")
      .def_property_readonly(
          "channel_names",
          [](const FitTableResult& f) {
            std::vector<std::string> names;
            for (const auto& c : f.file.fit.model.channels) names.push_back(c.name);
            return names;
          },
          "The fitted channels: R, G, B, or wavelengths.")
      .def_property_readonly(
          "model", [](const FitTableResult& f) { return fitPart(f, "model"); },
          "fit.json's \"model\": description, elevation, lobes per channel, ...")
      .def_property_readonly(
          "channels", [](const FitTableResult& f) { return fitPart(f, "channels"); },
          "fit.json's \"channels\": per channel its name, diffuse albedo k_d, lobes (weight, exponent, ...) and "
          "statistics.")
      .def_property_readonly(
          "lobes",
          [](const FitTableResult& f) {
            py::list lobes;
            for (py::handle channel : fitPart(f, "channels")) lobes.append(channel["lobes"]);
            return lobes;
          },
          "Per channel, its lobes as fit.json lists them (weight, exponent, and the kind's coefficients).")
      .def_property_readonly(
          "held_out", [](const FitTableResult& f) { return fitPart(f, "fit", "held_out"); },
          "The held-out error (log error on rows the fit did not see, as ratios to a Lambertian fit): k-fold "
          "off the mirror and per held-out elevation, and their score; None when not estimated.")
      .def_property_readonly(
          "held_out_score",
          [](const FitTableResult& f) -> py::object {
            if (!f.file.fit.heldOut) return py::none();
            return py::float_(f.file.fit.heldOut->score());
          },
          "The held-out score (the worse of the k-fold and elevation ratios to Lambert), or None.")
      .def_property_readonly(
          "in_sample_error", [](const FitTableResult& f) { return f.file.fit.inSampleError; },
          "The log error over every row of the table (in-sample).")
      .def_property_readonly(
          "candidates", [](const FitTableResult& f) { return fitPart(f, "fit", "candidates"); },
          "The models tried by the automatic choices, with their held-out scores.")
      .def_property_readonly(
          "seconds", [](const FitTableResult& f) { return f.file.fit.seconds; }, "Wall time of the fit.")
      .def_property_readonly(
          "document", [](const FitTableResult& f) { return pythonFromJson(fitDocument(f)); },
          "The fit.json document save() writes (docs/fitting.md).")
      .def("evaluate", &evaluateFit, py::arg("wi"), py::arg("wo"), kEvaluateDoc)
      .def("save", &saveFit, py::arg("path"),
           "Writes fit.json (atomically; never over the table), as `brdfbake fit -o PATH` does.")
      .def(
          "to_json", [](const FitTableResult& f) { return pythonFromJson(f.toJson()); },
          "What `brdfbake fit --json` prints: table, samples, channels, seconds, usable, files, notes and the "
          "fit.json document under \"fit\".")
      .def("brief_report", &FitTableResult::briefReport, "The text `brdfbake fit` prints.")
      .def("__repr__", [](const FitTableResult& f) {
        const LobeModel& model = f.file.fit.model;
        return "<brdfbake.Fit '" + f.table.string() + "': " + std::to_string(model.channels.size()) + " channel(s), " +
               (model.hasHalfDifference() ? std::string("a half-difference table")
                                          : std::to_string(model.channels.front().lobes.size()) + " lobe(s)") +
               ">";
      });
}

}  // namespace

void bindResults(py::module_& module) {
  bindSpecResults(module);
  bindFitResult(module);
}

}  // namespace brdfbake::python
