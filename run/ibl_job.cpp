// Engine-ready image-based lighting (ibl_job.hpp): three cube maps and the DFG table made in memory by
// the prefilter job, then written as one set.
#include <brdfbake/core/error.hpp>
#include <brdfbake/env/sh_irradiance.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/text_io.hpp>
#include <brdfbake/maps/map_mips.hpp>
#include <brdfbake/run/ibl_job.hpp>

#include <chrono>

#include "map_runners.hpp"

namespace brdfbake {
namespace fs = std::filesystem;
using namespace run_detail;

namespace {

void requirePowerOfTwo(int value, int low, int high, const std::string& field) {
  requireField(value >= low && value <= high && (value & (value - 1)) == 0, field,
               "must be a power of two in [" + std::to_string(low) + ", " + std::to_string(high) + "], got " +
                   std::to_string(value));
}

// The part of the set that one cube map is: its request beside the others'.
PrefilterRequest cubeRequest(const IblRequest& request, int resolution, double maxError) {
  PrefilterRequest part;
  part.environment = request.environment;
  part.parameterization = ParameterizationKind::Cube;
  part.resolution = resolution;
  part.maxError = maxError;
  return part;
}

// Every field but the environment.
void validateSizes(const IblRequest& r) {
  const int resolution = r.resolution, dfgSize = r.dfgSize;
  const double maxError = r.maxError;
  const std::optional<int>& levels = r.levels;
  requirePowerOfTwo(resolution, 1, 8192, "resolution");
  requirePowerOfTwo(r.irradianceResolution, 1, 1024, "irradiance_resolution");
  requirePowerOfTwo(r.skyboxResolution, 1, 8192, "skybox_resolution");
  requireField(dfgSize >= 1 && dfgSize <= 4096, "dfg_size", "must be in [1, 4096], got " + std::to_string(dfgSize));
  requireField(maxError > 0.0 && maxError <= 0.5, "max_error", "must be in (0, 0.5], got " + formatG(maxError));
  // A texture holds the whole chain: its levels must reach 1 texel.
  requireField(!levels || *levels == mipLevelCount(resolution), "levels",
               "a chain in one texture has every level down to 1 texel: " + std::to_string(mipLevelCount(resolution)) +
                   " levels for resolution " + std::to_string(resolution) + ", got " +
                   (levels ? std::to_string(*levels) : std::string()));
}

}  // namespace

void IblRequest::validate() const {
  requireField(environment && environment->map && !environment->image.empty(), "environment", "no environment given");
  validateSizes(*this);
}

IblResult makeIbl(const IblRequest& request, const Context& context) {
  request.validate();
  PrefilterRequest specular = cubeRequest(request, request.resolution, request.maxError);
  GlossChain chain;
  chain.lobe = GlossChain::Lobe::Ggx;
  chain.levels = mipLevelCount(request.resolution);
  // No edge fixup: engines sample cube maps seamlessly (Vulkan always, OpenGL and WebGL 2 with seamless
  // cube filtering), and averaging across edges would wipe out the coarsest levels (faces of 1 or 2 texels).
  chain.edgeFixup = false;
  specular.glossChain = chain;
  PrefilterRequest irradiance = cubeRequest(request, request.irradianceResolution, request.maxError);
  irradiance.lobe = PrefilterLobe::irradiance();
  irradiance.sh = true;
  const PrefilterRequest skybox = cubeRequest(request, request.skyboxResolution, request.maxError);
  IblResult result;
  result.specular = prefilterEnvironment(specular, context.task("ibl: specular"));
  result.irradiance = prefilterEnvironment(irradiance, context.task("ibl: irradiance"));
  result.skybox = prefilterEnvironment(skybox, context.task("ibl: skybox"));
  DfgOptions dfg;
  dfg.width = dfg.height = request.dfgSize;
  dfg.form = request.dfgForm;
  const Context dfgContext = context.task("ibl: DFG table");
  result.dfg = dfgTable(dfg, dfgContext);
  dfgContext.report(1.0);
  return result;
}

std::string IblResult::briefReport() const {
  return "specular: " + specular.briefReport() + "\nirradiance: " + irradiance.briefReport() +
         "\nskybox: " + skybox.briefReport() + "\n";
}

nlohmann::json IblResult::toJson() const {
  return {{"specular", specular.toJson()},
          {"irradiance", irradiance.toJson()},
          {"skybox", skybox.toJson()},
          {"dfg", dfg.metadata.value("dfg_table", nlohmann::json())}};
}

void IblOutputs::validate() const {
  requireField(!folder.empty(), "out_dir", "the output folder is required");
  requireField(format == "ktx2" || format == "ktx" || format == "dds" || format == "exr", "format",
               "must be ktx2, ktx, dds or exr, got \"" + printable(format, 40) + "\"");
  requireField(!texelFormat || format != "exr", "texel_format", "applies to the ktx2, ktx and dds formats, not exr");
  requireField(!stem.empty() && stem.find('/') == std::string::npos && stem != "." && stem != "..", "stem",
               "is a file name, not a path: \"" + printable(stem, 80) + "\"");
}

std::string IblOutputs::extension() const { return "." + format; }

fs::path IblOutputs::file(const std::string& suffix, const std::string& fileExtension) const {
  return folder / (stem + suffix + fileExtension);
}

namespace {

struct IblPaths {
  fs::path specular, irradiance, sh, shText, skybox, dfg;
};

IblPaths pathsOf(const IblOutputs& o) {
  return {o.file("_ggx", o.extension()), o.file("_irradiance", o.extension()), o.file("_sh", ".json"),
          o.file("_sh", ".txt"),         o.file("_skybox", o.extension()),     o.file("_dfg", o.extension())};
}

MapOutputs cubeOutputs(const IblOutputs& o, const fs::path& file, MipLayout layout = MipLayout::Files) {
  MapOutputs outputs;
  outputs.files = {file};
  outputs.texelFormat = o.texelFormat;
  outputs.inputs = o.inputs;
  outputs.mipLayout = layout;
  return outputs;
}

// A map's worst error estimate as its entry states it (null if exact or not estimated).
nlohmann::json errorEstimate(const MapResult& map) {
  const auto p = map.entry.find("prefilter");
  return p != map.entry.end() && p->is_object() ? p->value("error_estimate", nlohmann::json()) : nlohmann::json();
}

// Each file with its role (see ibl_job.hpp).
void listOutputs(const IblOutputs& o, const IblPaths& paths, const nlohmann::json& dfg, IblReport& report) {
  const auto& maps = report.maps;
  const nlohmann::json& chain = maps[0].entry["gloss_chain"];
  report.outputs.push_back({"specular",
                            paths.specular,
                            "GGX chain: a cube texture whose level k of L holds ggx:R_k, R_k = k / (L - 1) (level 0 "
                            "the mirror); sample at lod = R (L - 1)",
                            {{"levels", chain["levels"]},
                             {"roughness_mapping", chain["roughness_mapping"]},
                             {"error_estimate", errorEstimate(maps[0])}}});
  report.outputs.push_back({"irradiance",
                            paths.irradiance,
                            "irradiance cube: E/pi at the normal n (a white Lambertian surface's radiance)",
                            {{"quantity", kIrradianceQuantity}, {"error_estimate", errorEstimate(maps[1])}}});
  report.outputs.push_back({"irradiance_sh",
                            paths.sh,
                            "9 RGB spherical-harmonic coefficients of E/pi (3 bands, the file states the basis)",
                            {{"quantity", kIrradianceQuantity}}});
  report.outputs.push_back({"skybox", paths.skybox, "the environment resampled into a cube (the background)", {}});
  report.outputs.push_back(
      {"dfg", paths.dfg, "split-sum DFG table: n.v along x, perceptual roughness along y, texel centres (i + 0.5) / N",
       dfg});
  if (o.shCmgen) {
    report.outputs.push_back(
        {"irradiance_sh_cmgen", paths.shText, "the 9 lines cmgen --sh-shader prints (E/pi, cmgen's basis)", {}});
  }
}

// One cube map of the set, written, and its report.
MapResult writeCube(const PrefilterResult& made, const MapOutputs& outputs, const std::optional<ShOutput>& sh,
                    const std::string& jsonPath) {
  const auto start = std::chrono::steady_clock::now();
  MapWriteReport written = writePrefiltered(made, outputs, sh);
  return reportPrefiltered(made, MapPlace{jsonPath, outputs.files, false}, std::move(written), secondsSince(start), sh);
}

}  // namespace

std::vector<FilePlan::Entry> plannedFiles(const IblOutputs& outputs) {
  outputs.validate();
  const IblPaths paths = pathsOf(outputs);
  std::vector<FilePlan::Entry> out;
  for (const auto& [file, role] : {std::pair{paths.specular, "specular"}, std::pair{paths.irradiance, "irradiance"},
                                   std::pair{paths.skybox, "skybox"}, std::pair{paths.dfg, "dfg table"}}) {
    const auto files = mapOutputFiles(file, role, role != std::string("dfg table"));
    out.insert(out.end(), files.begin(), files.end());
  }
  out.push_back({paths.sh, "irradiance SH"});
  if (outputs.shCmgen) out.push_back({paths.shText, "irradiance SH, cmgen's lines"});
  return out;
}

IblReport writeIbl(const IblResult& result, const IblOutputs& outputs) {
  outputs.validate();
  const IblPaths paths = pathsOf(outputs);
  std::error_code ec;
  fs::create_directories(outputs.folder, ec);
  if (ec)
    throw Error(Error::Kind::Io,
                printable(outputs.folder.string()) + ": cannot create the output folder: " + ec.message());
  IblReport report;
  report.environment = result.specular.environment.value("file", std::string());
  OutputBatch batch;  // every file or none
  report.maps.push_back(
      writeCube(result.specular, cubeOutputs(outputs, paths.specular, MipLayout::Tiled), {}, "specular"));
  report.maps.push_back(
      writeCube(result.irradiance, cubeOutputs(outputs, paths.irradiance), ShOutput{paths.sh, false}, "irradiance"));
  report.maps.push_back(writeCube(result.skybox, cubeOutputs(outputs, paths.skybox), {}, "skybox"));
  WriteOptions write;
  write.inputs = outputs.inputs;
  write.texelFormat = outputs.texelFormat;
  const WriteReport dfgWritten = writeDfgTable(result.dfg, paths.dfg, write);
  report.notes.insert(report.notes.end(), dfgWritten.notes.begin(), dfgWritten.notes.end());
  if (outputs.shCmgen) writeFileAtomically(paths.shText, irradianceShCmgenText(*result.irradiance.sh));
  batch.commit();
  for (const MapResult& map : report.maps) report.files.insert(report.files.end(), map.files.begin(), map.files.end());
  report.files.push_back(paths.dfg);
  if (outputs.shCmgen) report.files.push_back(paths.shText);
  listOutputs(outputs, paths, result.dfg.metadata.value("dfg_table", nlohmann::json()), report);
  return report;
}

IblReport runIbl(const IblFiles& files, const Context& context) {
  IblRequest request = files.request;
  IblOutputs outputs = files.outputs;
  if (outputs.stem.empty()) outputs.stem = files.environment.stem().string();
  outputs.inputs.push_back(files.environment);
  validateSizes(request);  // the request's own fields first, then the files
  checkJobFiles({{files.environment, "environment"}}, plannedFiles(outputs), outputs.folder);
  for (const fs::path& file : {pathsOf(outputs).dfg}) {
    OutputShape shape;
    shape.texelFormat = outputs.texelFormat;
    if (const std::string problem = containerProblem(file, shape); !problem.empty())
      throw Error::invalidField("format", problem);
  }
  try {
    request.environment = std::make_shared<const Environment>(loadEnvironment(files.environment, {files.from}));
  } catch (const Error& e) {
    throw Error(e.kind(), "environment: " + std::string(e.what()));
  }
  const IblResult made = makeIbl(request, context);
  return writeIbl(made, outputs);
}

std::string IblReport::briefReport() const {
  std::string text;
  for (const MapResult& map : maps) text += map.briefReport();
  for (const IblFile& f : outputs) text += f.role + ": " + f.file.string() + " (" + f.description + ")\n";
  for (const auto& note : notes) text += "  note: " + note + "\n";
  return text;
}

nlohmann::json IblReport::toJson() const {
  nlohmann::json listed = nlohmann::json::array();
  for (const IblFile& f : outputs) {
    nlohmann::json entry = {{"role", f.role}, {"file", f.file.string()}, {"description", f.description}};
    if (f.details.is_object()) entry.update(f.details);
    listed.push_back(entry);
  }
  nlohmann::json mapEntries = nlohmann::json::array();
  for (const MapResult& map : maps) mapEntries.push_back(map.entry);
  return {{"environment", environment.string()}, {"files", listed}, {"maps", mapEntries}, {"notes", notes}};
}

}  // namespace brdfbake
