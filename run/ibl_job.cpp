// Engine-ready image-based lighting: three cube maps as one spec, the DFG table beside (ibl_job.hpp).
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/files.hpp>
#include <brdfbake/core/json_text.hpp>
#include <brdfbake/env/prefilter_stack.hpp>
#include <brdfbake/env/sh_irradiance.hpp>
#include <brdfbake/maps/map_file.hpp>
#include <brdfbake/maps/map_mips.hpp>
#include <brdfbake/run/ibl_job.hpp>

#include <chrono>

namespace brdfbake {
namespace fs = std::filesystem;

namespace {

std::string extensionOf(const std::string& format) { return format == "ktx2" ? ".ktx2" : "." + format; }

std::string stemOf(const IblOptions& options) {
  return options.stem.empty() ? options.environment.stem().string() : options.stem;
}

fs::path outputName(const IblOptions& options, const std::string& suffix, const std::string& extension) {
  return fs::path(stemOf(options) + suffix + extension);
}

nlohmann::json environmentJson(const IblOptions& options, const std::string& lobe) {
  nlohmann::json e = {{"file", fs::absolute(options.environment).string()}, {"lobe", lobe}};
  if (options.from) e["from"] = *options.from;
  if (lobe != "mirror") e["max_error"] = options.maxError;
  return e;
}

void checkPowerOfTwo(int value, int low, int high, const std::string& field) {
  require(value >= low && value <= high && (value & (value - 1)) == 0,
          "ibl: " + field + " must be a power of two in [" + std::to_string(low) + ", " + std::to_string(high) +
              "], got " + std::to_string(value));
}

}  // namespace

void IblOptions::validate() const {
  JobOptions::validate();
  require(!environment.empty(), "ibl: the environment file (ENV) is required");
  require(!outDir.empty(), "ibl: the output folder (--out-dir) is required");
  require(format == "ktx2" || format == "ktx" || format == "dds" || format == "exr",
          "ibl: format (--format) must be ktx2, ktx, dds or exr, got \"" + format + "\"");
  require(!texelFormat || format != "exr",
          "ibl: a texel format (--texel-format) applies to the ktx2, ktx and dds formats, not exr");
  checkPowerOfTwo(resolution, 1, 8192, "resolution (--resolution)");
  checkPowerOfTwo(irradianceResolution, 1, 1024, "irradiance resolution (--irradiance-resolution)");
  checkPowerOfTwo(skyboxResolution, 1, 8192, "skybox resolution (--skybox-resolution)");
  require(dfgSize >= 1 && dfgSize <= 4096,
          "ibl: DFG size (--dfg-size) must be in [1, 4096], got " + std::to_string(dfgSize));
  require(maxError > 0.0 && maxError <= 0.5, "ibl: max error (--max-error) must be in (0, 0.5]");
  if (levels) {  // a texture holds the whole chain: its levels must reach 1 texel
    require(*levels == mipLevelCount(resolution),
            "ibl: levels (--levels): a chain in one texture has every level down to 1 texel: " +
                std::to_string(mipLevelCount(resolution)) + " levels for resolution " + std::to_string(resolution) +
                ", got " + std::to_string(*levels));
  }
  require(stem.find('/') == std::string::npos && stem != "." && stem != "..",
          "ibl: the stem (--stem) is a file name, not a path: \"" + stem + "\"");
}

nlohmann::json iblSpec(const IblOptions& options) {
  options.validate();
  const std::string ext = extensionOf(options.format);
  nlohmann::json ggx = environmentJson(options, "ggx");
  // No edge fixup: engines sample cube maps seamlessly (Vulkan always, OpenGL and WebGL 2 with seamless
  // cube filtering), and averaging across edges would wipe out the coarsest levels (faces of 1 or 2 texels).
  ggx["gloss_chain"] = {{"edge_fixup", false}};
  if (options.levels) ggx["gloss_chain"]["levels"] = *options.levels;
  ggx["mip_layout"] = "tiled";
  nlohmann::json irradiance = environmentJson(options, "irradiance");
  irradiance["sh_output"] = outputName(options, "_sh", ".json").string();
  nlohmann::json maps = nlohmann::json::array({{{"output", outputName(options, "_ggx", ext).string()},
                                                {"parameterization", "cube"},
                                                {"resolution", options.resolution},
                                                {"environment", ggx}},
                                               {{"output", outputName(options, "_irradiance", ext).string()},
                                                {"parameterization", "cube"},
                                                {"resolution", options.irradianceResolution},
                                                {"environment", irradiance}},
                                               {{"output", outputName(options, "_skybox", ext).string()},
                                                {"parameterization", "cube"},
                                                {"resolution", options.skyboxResolution},
                                                {"environment", environmentJson(options, "mirror")}}});
  nlohmann::json spec = {{"maps", maps}};
  if (options.texelFormat)
    for (auto& map : spec["maps"]) map["texel_format"] = std::string(toString(*options.texelFormat));
  return spec;
}

namespace {

// Removes what a failed job wrote, so that a failure leaves no partial output.
void removeWritten(const std::vector<fs::path>& files) {
  for (const fs::path& file : files) {
    std::error_code ignored;
    fs::remove(file, ignored);
  }
}

// The files beside the spec's maps, named before any work.
struct ExtraFiles {
  fs::path dfg, shText;
};

ExtraFiles planIbl(const IblOptions& options, const SpecRunOptions& run) {
  const ExtraFiles extra{options.outDir / outputName(options, "_dfg", extensionOf(options.format)),
                         options.outDir / outputName(options, "_sh", ".txt")};
  SpecPlan plan = planSpec(run);
  for (const auto& entry : mapOutputFiles(extra.dfg, "dfg table")) plan.files.addOutput(entry.file, entry.role);
  if (options.shCmgen) plan.files.addOutput(extra.shText, "irradiance SH, cmgen's lines");
  plan.files.check();
  OutputShape dfgShape;
  dfgShape.texelFormat = options.texelFormat;
  if (const std::string problem = containerProblem(extra.dfg, dfgShape); !problem.empty())
    throw Error(Error::Kind::InvalidArgument, problem);
  return extra;
}

// The DFG table (and cmgen's SH lines), after the maps.
nlohmann::json writeExtras(const IblOptions& options, const ExtraFiles& extra, IblResult& result) {
  DfgOptions dfg;
  dfg.width = dfg.height = options.dfgSize;
  dfg.form = options.dfgForm;
  dfg.threads = options.threads;
  if (options.progress) options.progress("ibl: DFG table", 0.0);
  const Image table = dfgTable(dfg);
  WriteOptions write;
  write.inputs = {options.environment};
  write.texelFormat = options.texelFormat;
  const WriteReport written = writeDfgTable(table, extra.dfg, write);
  if (options.progress) options.progress("ibl: DFG table", 1.0);
  result.files.push_back(extra.dfg);
  result.notes.insert(result.notes.end(), written.notes.begin(), written.notes.end());
  if (options.shCmgen) {
    const auto& irradiance = result.maps.maps[1].entry;
    const ShExpansion sh = irradianceShFromJson(readJsonFile(irradiance["sh"].get<std::string>()), "sh");
    writeFileAtomically(extra.shText, irradianceShCmgenText(sh));
    result.files.push_back(extra.shText);
  }
  return table.metadata["dfg_table"];
}

// A map's worst error estimate as its entry states it (null if exact or not estimated).
nlohmann::json errorEstimate(const MapResult& map) {
  const auto p = map.entry.find("prefilter");
  return p != map.entry.end() && p->is_object() ? p->value("error_estimate", nlohmann::json()) : nlohmann::json();
}

// Each file with its role (see ibl_job.hpp).
void listOutputs(const IblOptions& options, const ExtraFiles& extra, const nlohmann::json& dfg, IblResult& result) {
  const auto& maps = result.maps.maps;
  const nlohmann::json& chain = maps[0].entry["gloss_chain"];
  result.outputs.push_back({"specular",
                            maps[0].output,
                            "GGX chain: a cube texture whose level k of L holds ggx:R_k, R_k = k / (L - 1) (level 0 "
                            "the mirror); sample at lod = R (L - 1)",
                            {{"levels", chain["levels"]},
                             {"roughness_mapping", chain["roughness_mapping"]},
                             {"error_estimate", errorEstimate(maps[0])}}});
  result.outputs.push_back({"irradiance",
                            maps[1].output,
                            "irradiance cube: E/pi at the normal n (a white Lambertian surface's radiance)",
                            {{"quantity", kIrradianceQuantity}, {"error_estimate", errorEstimate(maps[1])}}});
  result.outputs.push_back({"irradiance_sh",
                            maps[1].entry["sh"].get<std::string>(),
                            "9 RGB spherical-harmonic coefficients of E/pi (3 bands, the file states the basis)",
                            {{"quantity", kIrradianceQuantity}}});
  result.outputs.push_back({"skybox", maps[2].output, "the environment resampled into a cube (the background)", {}});
  result.outputs.push_back(
      {"dfg", extra.dfg, "split-sum DFG table: n.v along x, perceptual roughness along y, texel centres (i + 0.5) / N",
       dfg});
  if (options.shCmgen) {
    result.outputs.push_back(
        {"irradiance_sh_cmgen", extra.shText, "the 9 lines cmgen --sh-shader prints (E/pi, cmgen's basis)", {}});
  }
}

}  // namespace

IblResult makeIbl(const IblOptions& options) {
  options.validate();
  SpecRunOptions run;
  static_cast<JobOptions&>(run) = options;
  run.document = iblSpec(options);
  run.label = "ibl";
  run.outDir = options.outDir;
  const ExtraFiles extra = planIbl(options, run);  // every file checked before any work
  const bool folderExisted = fs::exists(options.outDir);
  std::error_code ec;
  fs::create_directories(options.outDir, ec);
  if (ec) throw Error(Error::Kind::Io, options.outDir.string() + ": cannot create the output folder: " + ec.message());

  IblResult result;
  result.environment = options.environment;
  nlohmann::json dfg;
  try {  // a failure (an unreadable environment, a map that fails, a cancel) leaves nothing behind
    result.maps = runSpec(run);
    result.files = result.maps.files;
    if (result.maps.firstError) throw *result.maps.firstError;
    dfg = writeExtras(options, extra, result);
  } catch (...) {
    removeWritten(result.files);
    if (!folderExisted) fs::remove(options.outDir, ec);  // only if empty
    throw;
  }
  listOutputs(options, extra, dfg, result);
  return result;
}

std::string IblResult::briefReport() const {
  std::string text = maps.briefReport();
  for (const IblFile& f : outputs) text += f.role + ": " + f.file.string() + " (" + f.description + ")\n";
  for (const auto& note : notes) text += "  note: " + note + "\n";
  return text;
}

nlohmann::json IblResult::toJson() const {
  nlohmann::json listed = nlohmann::json::array();
  for (const IblFile& f : outputs) {
    nlohmann::json entry = {{"role", f.role}, {"file", f.file.string()}, {"description", f.description}};
    if (f.details.is_object()) entry.update(f.details);
    listed.push_back(entry);
  }
  return {{"environment", environment.string()}, {"files", listed}, {"maps", maps.toJson()["maps"]}, {"notes", notes}};
}

}  // namespace brdfbake
