#include <brdfbake/bake/baker.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/run/convert_output.hpp>

namespace brdfbake {
namespace fs = std::filesystem;

namespace {

// Where the map came from, in its metadata.
nlohmann::json convertedFrom(const ConvertOptions& options, const nlohmann::json& described) {
  nlohmann::json from = {
      {"file", options.source.path.filename().string()},
      {"kind", described["kind"]},
      {"parameterization", described.value("parameterization", described["kind"].get<std::string>())},
      {"resolution", described.value("resolution", 0)}};
  if (options.source.cosView) from["cos_view"] = *options.source.cosView;
  if (options.source.mipLevel > 0) from["mip_level"] = options.source.mipLevel;
  return from;
}

}  // namespace

void ConvertOptions::validate() const {
  requireField(resolution >= 0 && resolution <= 65536, "resolution", "must be in [1, 65536] (0: the input's)");
  requireField(samplesPerTexel >= 1 && samplesPerTexel <= 4096, "samples_per_texel", "must be in [1, 4096]");
  outputs.validate();
}

ConvertResult convertOutput(const ConvertOptions& options, const Context& context) {
  options.validate();
  const BakedOutput source = options.source.open();
  options.source.checkCosView(source, false);
  if (source.kind() == OutputKind::FresnelTable && options.to != ParameterizationKind::Sphere) {
    throw Error::invalidField("to",
                              "a Fresnel table is a function of n.v; only a sphere map (eye space, view +z) holds it "
                              "as a function of direction");
  }
  const nlohmann::json described = source.describe();
  const int resolution = options.resolution > 0 ? options.resolution : described.value("resolution", 0);
  requireField(resolution >= 1, "resolution", "the input has none to keep; give one");
  const auto target = makeParameterization(options.to, resolution);
  FilePlan plan;
  plan.addInput(options.source.path, "map");
  MapOutputs outputs = options.outputs;
  outputs.inputs.push_back(options.source.path);
  for (std::size_t i = 0; i < outputs.files.size(); ++i) {
    const fs::path& file = outputs.files[i];
    for (const auto& f : mapOutputFiles(file, "output", options.to == ParameterizationKind::Cube, outputs.layout))
      plan.addOutput(f.file, f.role);
    const OutputShape shape{options.to, resolution, false, outputs.layout, outputs.writeOptionsFor(i).texelFormat};
    if (const std::string problem = containerProblem(file, shape); !problem.empty())
      throw Error::invalidField("outputs", problem);
  }
  plan.check();
  BakeOptions bake;
  bake.samplesPerTexel = options.samplesPerTexel;
  const BakedMap baked = bakeMap(*target, BakedOutputFunction(source, options.source.cosView), bake,
                                 context.task("convert " + options.source.path.filename().string()));
  MapInfo info;
  info.parameterization = options.to;
  info.resolution = resolution;
  info.conventionVersion = kConventionVersion;
  info.spec = source.metadata().value("spec", nlohmann::json::object());
  info.spec["converted_from"] = convertedFrom(options, described);
  ConvertResult result{{}, {}, baked.summary.seconds};
  for (std::size_t i = 0; i < outputs.files.size(); ++i) {  // the one resampled map, in each format
    const auto written = writeMap(baked.image, info, outputs.files[i], outputs.layout, outputs.writeOptionsFor(i));
    result.files.insert(result.files.end(), written.files.begin(), written.files.end());
    result.notes.insert(result.notes.end(), written.notes.begin(), written.notes.end());
  }
  return result;
}

std::string ConvertResult::briefReport() const {
  std::string text;
  for (const auto& f : files) text += "wrote " + f.string() + "\n";
  for (const auto& note : notes) text += "  note: " + note + "\n";
  return text;
}

nlohmann::json ConvertResult::toJson() const {
  return {{"files", pathsToJson(files)}, {"seconds", seconds}, {"notes", notes}};
}

}  // namespace brdfbake
