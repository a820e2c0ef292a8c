#include <brdfbake/bake/baker.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/run/convert_output.hpp>

namespace brdfbake {

namespace {

// Where the map came from, in its metadata.
nlohmann::json convertedFrom(const ConvertOptions& options, const nlohmann::json& described) {
  nlohmann::json from = {
      {"file", options.source.path.string()},
      {"kind", described["kind"]},
      {"parameterization", described.value("parameterization", described["kind"].get<std::string>())},
      {"resolution", described.value("resolution", 0)}};
  if (options.source.cosView) from["cos_view"] = *options.source.cosView;
  if (options.source.mipLevel > 0) from["mip_level"] = options.source.mipLevel;
  return from;
}

}  // namespace

void ConvertOptions::validate() const {
  JobOptions::validate();
  require(resolution >= 0 && resolution <= 65536, "resolution must be in [1, 65536] (0: the input's)");
  require(samplesPerTexel >= 1 && samplesPerTexel <= 4096, "samples per texel must be in [1, 4096]");
  imageFormatFor(output);  // a bad extension fails before the work
}

ConvertResult convertOutput(const ConvertOptions& options) {
  options.validate();
  const BakedOutput source = options.source.open();
  options.source.checkCosView(source, false);
  if (source.kind() == OutputKind::FresnelTable && options.to != ParameterizationKind::Sphere) {
    throw Error(Error::Kind::InvalidArgument,
                "to: a Fresnel table is a function of n.v; only a sphere map (eye space, view +z) holds it as a "
                "function of direction");
  }
  const nlohmann::json described = source.describe();
  const int resolution = options.resolution > 0 ? options.resolution : described.value("resolution", 0);
  require(resolution >= 1, "resolution: the input has none to keep; give one");
  const auto target = makeParameterization(options.to, resolution);
  FilePlan plan;
  plan.addInput(options.source.path, "map");
  for (const auto& f :
       mapOutputFiles(options.output, "output", options.to == ParameterizationKind::Cube, options.layout)) {
    plan.addOutput(f.file, f.role);
  }
  plan.check();
  BakeOptions bake;
  bake.samplesPerTexel = options.samplesPerTexel;
  bake.threads = options.threads;
  bake.allowLarge = options.allowLarge;
  bake.progress = progressFor(options.progress, "convert " + options.source.path.filename().string());
  const BakedMap baked = bakeMap(*target, BakedOutputFunction(source, options.source.cosView), bake);
  MapInfo info;
  info.parameterization = options.to;
  info.resolution = resolution;
  info.conventionVersion = kConventionVersion;
  info.spec = source.metadata().value("spec", nlohmann::json::object());
  info.spec["converted_from"] = convertedFrom(options, described);
  const auto written = writeMap(baked.image, info, options.output, options.layout,
                                {.inputs = {options.source.path}, .texelFormat = std::nullopt});
  return {written.files, written.notes, baked.summary.seconds};
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
