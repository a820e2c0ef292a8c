// A material under an environment (matcap_job.hpp): the request made in memory, written, and run from
// files; a spec's map of a material under an environment goes through the same three steps.
#include <brdfbake/core/error.hpp>
#include <brdfbake/io/text_io.hpp>
#include <brdfbake/run/matcap_job.hpp>
#include <brdfbake/spec/material_file.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "map_runners.hpp"

namespace brdfbake {
namespace fs = std::filesystem;
using namespace run_detail;

namespace {

// Every field but the material and the environment.
void validateSettings(const MatcapRequest& r) {
  const int resolution = r.resolution, samplesPerTexel = r.samplesPerTexel;
  const double maxError = r.maxError, exposure = r.exposure;
  const Vec3& view = r.view;
  const ParameterizationKind parameterization = r.parameterization;
  requireField(resolution >= 1 && resolution <= 65536, "resolution",
               "must be in [1, 65536], got " + std::to_string(resolution));
  requireField(samplesPerTexel >= 1 && samplesPerTexel <= 4096, "samples_per_texel",
               "must be in [1, 4096], got " + std::to_string(samplesPerTexel));
  requireField(maxError > 0.0 && maxError <= 0.5, "max_error",
               "must be in (0, 0.5] (0.01 is 1 % of the peak), got " + formatG(maxError));
  requireField(!r.maxRelativeError || (*r.maxRelativeError > 0.0 && *r.maxRelativeError <= 10.0), "max_relative_error",
               "must be in (0, 10] (0.03 is 3 % of a texel's value)");
  requireField(view.allFinite() && view.norm() > 0.0, "view", "must be a non-zero finite vector");
  requireField(parameterization != ParameterizationKind::Sphere || (view.normalized() - Vec3::UnitZ()).norm() < 1e-9,
               "view", "a sphere map views along +z (eye space); turn the camera instead");
  requireField(std::isfinite(exposure) && std::abs(exposure) <= 30.0, "exposure",
               "must be in [-30, 30] stops, got " + formatG(exposure));
  try {
    r.camera.validate();
  } catch (const Error& e) {
    throw Error::invalidField("camera", e.what());
  }
}

}  // namespace

void MatcapRequest::validate() const {
  requireField(material != nullptr, "material", "no material given");
  try {
    requireBrdf(*material);
  } catch (const Error& e) {
    throw Error::invalidField("material", e.what());
  }
  requireField(environment && environment->map && !environment->image.empty(), "environment", "no environment given");
  validateSettings(*this);
}

UnderEnvironmentOptions MatcapRequest::shadingOptions() const {
  UnderEnvironmentOptions options;
  options.parameterization = parameterization;
  options.resolution = resolution;
  options.samplesPerTexel = samplesPerTexel;
  options.view = view;
  options.method = method;
  options.maxError = maxError;
  options.maxRelativeError = maxRelativeError;
  options.camera = camera;
  return options;
}

nlohmann::json MatcapRequest::describe() const {
  nlohmann::json materialJson = materialDescription;
  if (materialJson.is_null() && material) materialJson = {{"model", std::string(material->model())}};
  nlohmann::json environmentJson = {{"method", std::string(toString(method))}, {"max_error", maxError}};
  if (maxRelativeError) environmentJson["max_relative_error"] = *maxRelativeError;
  if (environment) environmentJson["file"] = fs::path(environment->source).filename().string();
  nlohmann::json map = {{"parameterization", std::string(toString(parameterization))},
                        {"resolution", resolution},
                        {"samples_per_texel", samplesPerTexel},
                        {"material", materialJson},
                        {"environment", environmentJson},
                        {"camera",
                         {{"forward", {camera.forward.x(), camera.forward.y(), camera.forward.z()}},
                          {"up", {camera.up.x(), camera.up.y(), camera.up.z()}}}}};
  if (parameterization != ParameterizationKind::Sphere) map["view"] = {view.x(), view.y(), view.z()};
  if (exposure != 0.0) map["exposure"] = exposure;
  return map;
}

double exposureFor(const Image& image) {
  std::vector<float> brightest;
  brightest.reserve(static_cast<std::size_t>(image.width()) * image.height());
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      const Rgba v = image.at(x, y);
      if (v[3] > 0.0f) brightest.push_back(std::max({v[0], v[1], v[2]}));  // alpha 0: outside a sphere map's disc
    }
  }
  if (brightest.empty()) return 0.0;
  const auto at = brightest.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(brightest.size() - 1));
  std::nth_element(brightest.begin(), at, brightest.end());
  return *at > 0.0f ? std::clamp(-std::log2(static_cast<double>(*at)), -30.0, 30.0) : 0.0;
}

MatcapResult makeMatcap(const MatcapRequest& specified, const Context& context) {
  specified.validate();
  MatcapRequest request = specified;
  MatcapResult result;
  result.map = shadeUnderEnvironment(*request.environment, *request.material, request.shadingOptions(), context);
  if (request.autoExposure) {
    request.exposure = exposureFor(result.map.image);
    result.map.summary.notes.push_back("exposure " + formatG(request.exposure) +
                                       " stops (auto: the 99th percentile of the map at white)");
  }
  // The error estimate is relative to the peak, so it holds for the scaled map too.
  if (request.exposure != 0.0) {
    const float scale = static_cast<float>(std::exp2(request.exposure));
    float* texels = result.map.image.data();
    const std::size_t end = result.map.image.index(0, result.map.image.height());
    for (std::size_t i = 0; i < end; i += 4)
      for (int c = 0; c < 3; ++c) texels[i + c] *= scale;
  }
  result.description = request.describe();
  return result;
}

nlohmann::json MatcapResult::toJson() const {
  return {{"parameterization", std::string(toString(map.map->kind()))},
          {"resolution", map.map->resolution()},
          {"width", map.map->width()},
          {"height", map.map->height()},
          {"bake_path", "under_environment"},
          {"bake_seconds", map.summary.seconds},
          {"samples_per_texel", description.value("samples_per_texel", 16)},
          {"under_environment", map.summary.toJson()}};
}

MapWriteReport writeMatcap(const MatcapResult& result, const MapOutputs& outputs) {
  outputs.validate();
  MapWriteReport written;
  for (std::size_t i = 0; i < outputs.files.size(); ++i) {
    appendWritten(written, writeUnderEnvironmentMap(result.map, outputs.files[i], result.description, outputs.layout,
                                                    outputs.writeOptionsFor(i)));
  }
  return written;
}

namespace run_detail {

MapResult reportMatcap(const MatcapResult& made, const MapPlace& place, const MapWriteReport& written,
                       double writeSeconds) {
  const UnderEnvironmentSummary& s = made.map.summary;
  const std::string kind(toString(made.map.map->kind()));
  const int width = made.map.map->width(), height = made.map.map->height();
  std::vector<std::string> notes = s.notes;
  notes.insert(notes.end(), written.notes.begin(), written.notes.end());
  MapResult result = makeMapResult(
      place, {kind, made.map.map->resolution(), width, height, "under_environment", s.seconds, writeSeconds},
      written.files, notes);
  result.entry.update(made.toJson());
  const std::string environment = made.description["environment"].value("file", std::string("the environment"));
  result.lines.push_back(place.made() + " (" + kind + " " + std::to_string(width) + "x" + std::to_string(height) +
                         ", lit by " + environment + "): " + formatNumber(s.seconds) + " s, write " +
                         formatNumber(writeSeconds) + " s");
  result.lines.push_back("  " + s.briefReport());
  for (const auto& note : result.notes) result.lines.push_back("  note: " + note);
  return result;
}

MapResult makeAndWriteMatcap(const MatcapRequest& request, const MapOutputs& outputs, const MapPlace& place,
                             const Context& context) {
  auto made = std::make_shared<const MatcapResult>(makeMatcap(request, context));
  if (outputs.files.empty()) {  // in memory (a spec map without outputs)
    MapResult result = reportMatcap(*made, place, {}, 0.0);
    auto write = [made](const MapOutputs& o) { return writeMatcap(*made, o); };
    result.made = std::make_shared<const MadeMap>(
        MadeMap{{made->map.image}, underEnvironmentMapInfo(made->map, made->description), std::move(write)});
    return result;
  }
  const auto writeStart = std::chrono::steady_clock::now();
  const MapWriteReport written = writeMatcap(*made, outputs);
  return reportMatcap(*made, place, written, secondsSince(writeStart));
}

MapResult runUnderEnvironmentMap(const MapSpec& specified, const std::shared_ptr<const Environment>& environment,
                                 const MapRunContext& context) {
  MapSpec map = specified;
  if (const auto& fit = map.materialMap()->deferredFit) {  // a measured material's fit runs now
    map.prepare(context.context.task(map.jsonPath + " fitting lobes to " +
                                     fs::path(fit->table.sourceFile).filename().string()));
  }
  const UnderEnvironmentOptions o = map.underEnvironmentOptions();
  MatcapRequest request;
  request.material = map.materialMap()->material;
  request.environment = environment;
  request.parameterization = o.parameterization;
  request.resolution = o.resolution;
  request.samplesPerTexel = o.samplesPerTexel;
  request.view = o.view;
  request.method = o.method;
  request.maxError = o.maxError;
  request.maxRelativeError = o.maxRelativeError;
  request.camera = o.camera;
  request.exposure = map.raw.value("exposure", 0.0);  // checked by the spec's parser
  request.materialDescription = withoutFolders(map.raw.value("material", nlohmann::json()));
  return makeAndWriteMatcap(request, outputsOf(map, context.write.inputs), placeOf(map),
                            context.context.task(map.jsonPath + " " + map.outputName()));
}

}  // namespace run_detail

namespace {

// The environment, read and checked; errors name it as the request's "environment".
std::shared_ptr<const Environment> readEnvironment(const fs::path& file, std::optional<ParameterizationKind> from) {
  try {
    return std::make_shared<const Environment>(loadEnvironment(file, EnvironmentLoadOptions{from}));
  } catch (const Error& e) {
    throw Error(e.kind(), "environment: " + std::string(e.what()));
  }
}

}  // namespace

MapResult runMatcap(const MatcapFiles& files, const Context& context) {
  MatcapRequest request = files.request;
  validateSettings(request);
  files.outputs.validate();
  MapOutputs outputs = files.outputs;
  outputs.inputs.push_back(files.material);
  outputs.inputs.push_back(files.environment);
  std::vector<FilePlan::Entry> planned;
  const bool cube = request.parameterization == ParameterizationKind::Cube;
  for (const fs::path& file : outputs.files) {
    const auto entries = mapOutputFiles(file, "output", cube, outputs.layout);
    planned.insert(planned.end(), entries.begin(), entries.end());
    OutputShape shape;
    shape.parameterization = request.parameterization;
    shape.resolution = request.resolution;
    shape.cubeLayout = outputs.layout;
    shape.texelFormat = isTextureContainer(imageFormatFor(file)) ? outputs.texelFormat : std::nullopt;
    if (const std::string problem = containerProblem(file, shape); !problem.empty())
      throw Error::invalidField("outputs", problem);
  }
  checkJobFiles({{files.material, "material"}, {files.environment, "environment"}}, planned, outputs.folder);
  request.environment = readEnvironment(files.environment, files.from);
  const MaterialFile material =
      loadMaterialFile(files.material, context.task("fitting " + files.material.filename().string()));
  request.material = material.material;
  request.materialDescription = material.description;
  MapResult result = makeAndWriteMatcap(request, outputs, MapPlace{"", outputs.files, outputs.files.size() > 1},
                                        context.task("matcap " + outputs.files.front().filename().string()));
  for (const auto& note : material.notes) {
    result.notes.push_back(note);
    result.entry["notes"].push_back(note);
    result.lines.push_back("  note: " + note);
  }
  return result;
}

}  // namespace brdfbake
