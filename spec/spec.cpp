#include <brdfbake/bake/baked_mips.hpp>
#include <brdfbake/core/printable.hpp>
#include <brdfbake/env/sh_irradiance.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/maps/map_mips.hpp>
#include <brdfbake/spec/material_spec.hpp>
#include <brdfbake/spec/spec.hpp>

#include <sys/stat.h>

#include <fstream>
#include <map>
#include <sstream>

#include "map_outputs.hpp"
#include "registry_entries.hpp"

namespace brdfbake {
namespace fs = std::filesystem;
namespace {

constexpr std::size_t kMaxLights = 256;  // per map (docs/limits.md)
constexpr std::size_t kMaxMaps = 1024;   // per spec

DirectionalLight parseLight(const nlohmann::json& value, const std::string& path, const Vec3& view, bool& atEye) {
  JsonObjectReader light(value, path);
  DirectionalLight result;
  const auto& direction = light.require("direction");
  atEye = direction.is_string();
  if (atEye) {
    if (direction.get<std::string>() != "eye") {
      throw specError(light.child("direction"), "must be \"eye\" or [x, y, z], got " + describe(direction));
    }
    result.direction = view;
  } else {
    result.direction = JsonObjectReader::asDirection(direction, light.child("direction"));
  }
  result.color = light.color("color", Rgb::Ones());
  light.finish();
  return result;
}

// "lobe": an analytic lobe (PrefilterLobe::parse), or a fitted lobe model ("lobes:FIT.json").
void parseEnvironmentLobe(JsonObjectReader& env, EnvironmentMapSpec& e, MapSpec& spec, const fs::path& baseDirectory) {
  e.lobeName = env.string("lobe");
  try {
    LobeArgument lobe = parseLobeArgument(e.lobeName, baseDirectory);
    if (!lobe.fitFile.empty()) spec.inputs.push_back({lobe.fitFile, env.child("lobe")});
    e.lobe = std::move(lobe.lobe);
  } catch (const Error& error) {
    throw specError(env.child("lobe"), error.what());
  }
}

// "gloss_chain" with "lobe": "phong" | "blinn" (each level's lobe from cmft's gloss mapping) or
// "ggx" (level k of L: perceptual roughness k / (L - 1), cmgen's mapping).
void parseGlossChain(JsonObjectReader& env, EnvironmentMapSpec& e, const MapSpec& spec) {
  e.lobeName = env.string("lobe");
  if (e.lobeName != "phong" && e.lobeName != "blinn" && e.lobeName != "ggx") {
    throw specError(env.child("lobe"),
                    "a gloss chain is made of Phong, Blinn-Phong or GGX levels: \"phong\", \"blinn\" or \"ggx\" (no "
                    "exponent or roughness; each level gets its own), got \"" +
                        shortenForMessage(e.lobeName, 40) + "\"");
  }
  JsonObjectReader chain = env.object("gloss_chain");
  GlossChain g;
  g.lobe = e.lobeName == "ggx"     ? GlossChain::Lobe::Ggx
           : e.lobeName == "phong" ? GlossChain::Lobe::Phong
                                   : GlossChain::Lobe::Blinn;
  if (g.lobe == GlossChain::Lobe::Ggx) {
    for (const char* key : {"scale", "bias"}) {
      if (chain.has(key)) {
        throw specError(
            chain.child(key),
            "a GGX chain's level k of L holds perceptual roughness k / (L - 1) (cmgen's mapping); scale and "
            "bias set Phong exponents");
      }
    }
  } else {
    g.scale = chain.number("scale");
    g.bias = chain.number("bias", 1.0, -HUGE_VAL, HUGE_VAL, false);
  }
  const int available = std::min(16, mipLevelCount(spec.resolution));
  g.levels = chain.integer("levels", available, 1, available);
  g.edgeFixup = chain.boolean("edge_fixup", g.edgeFixup);
  chain.finish();
  try {
    e.chainLobes = g.lobes(spec.resolution);
  } catch (const Error& error) {
    throw specError(chain.path(), error.what());
  }
  e.lobe = e.chainLobes.front();
  e.lobeName = e.chainLobes.front().name() + " ... " + e.chainLobes.back().name();
  e.glossChain = g;
}

// What the environment map makes besides one map: mips, a stack over elevation, a Fresnel
// decomposition, SH irradiance; and which combinations are refused.
void parseEnvironmentOutputs(JsonObjectReader& env, EnvironmentMapSpec& e, const MapSpec& spec,
                             const fs::path& baseDirectory) {
  const bool normalLobe = e.analyticLobe() && e.analyticLobe()->indexedByNormal();  // irradiance
  e.mips = env.boolean("mips", false);
  // A gloss chain is its own mip chain: "mip_layout": "tiled" puts every level in one file.
  e.mipLayout = materials::parseMipLayout(env, e.mips || e.glossChain.has_value(), spec.output, spec.resolution);
  if (e.glossChain && e.mipLayout == MipLayout::Tiled &&
      static_cast<int>(e.chainLobes.size()) != mipLevelCount(spec.resolution)) {
    throw specError(env.child("mip_layout"),
                    "a chain in one file holds every level down to 1 texel: give \"levels\": " +
                        std::to_string(mipLevelCount(spec.resolution)) + " (or leave it out) for resolution " +
                        std::to_string(spec.resolution) + ", got " + std::to_string(e.chainLobes.size()));
  }
  const bool varying = e.lobeModel() && e.lobeModel()->variesWithView();
  if (env.has("elevations")) {
    if (!varying) {
      throw specError(env.child("elevations"),
                      "only lobe models that vary with elevation (lobes:FIT.json with a varying or colour-profiled "
                      "model) make a stack of maps over elevation");
    }
    e.elevations = env.integer("elevations", 2, 64);
  }
  if (env.has("fresnel")) {
    if (e.lobeModel() || normalLobe) {
      throw specError(env.child("fresnel"),
                      "a Fresnel decomposition needs a specular lobe (mirror, phong:N, blinn:N, "
                      "ggx:R) for its specular map; the irradiance map is made with it");
    }
    e.fresnel = materials::parseFresnelTerm(env, "fresnel");
  }
  if (env.has("combine")) {
    if (!e.fresnel)
      throw specError(env.child("combine"), "needs \"fresnel\" (how the Fresnel decomposition is combined)");
    e.combine = env.parsed("combine", parseFresnelCombine);
  }
  if (const auto sh = env.optionalString("sh_output")) {
    if (!normalLobe || e.fresnel) {
      throw specError(env.child("sh_output"),
                      "spherical-harmonic coefficients hold irradiance: use it with \"lobe\": \"irradiance\"");
    }
    if (env.has("sh_format")) e.shCmgen = env.parsed("sh_format", parseShFormat) == ShFormat::Cmgen;
    if (const std::string problem = ShOutput{*sh, e.shCmgen}.problem(); !problem.empty())
      throw specError(env.child("sh_output"), problem);
    e.shOutput = fs::path(*sh).is_absolute() ? fs::path(*sh) : baseDirectory / *sh;
  } else if (env.has("sh_format")) {
    throw specError(env.child("sh_format"), "needs \"sh_output\" (the file the coefficients go to)");
  }
  if (e.glossChain && (e.mips || e.fresnel)) {
    throw specError(env.child("gloss_chain"),
                    "the chain is its own mip levels (STEM_mipK.EXT); it does not combine with "
                    "\"mips\" or \"fresnel\"");
  }
}

// "environment": {"file", "lobe", "method", "max_error", "mips", "mip_layout", "from", "view", "up",
// "elevations", "fresnel", "combine", "gloss_chain", "sh_output"} in place of "material" and "lights".
void parseEnvironmentMap(JsonObjectReader& map, MapSpec& spec, const fs::path& baseDirectory) {
  for (const char* key : {"material", "lights"}) {
    if (map.has(key))
      throw specError(map.child(key), "an environment map takes its values from \"environment\"; remove it");
  }
  if (spec.anyAuto())
    throw specError(map.path(), "environment maps need a fixed parameterization, resolution and samples_per_texel");
  if (spec.viewGiven || spec.viewNeed != MapSpec::ViewNeed::Unspecified) {
    throw specError(map.child("view"),
                    "environment maps live in the environment's frame; a sphere map's view goes in "
                    "\"environment\": {\"view\": [x, y, z]}");
  }
  JsonObjectReader env = map.object("environment");
  EnvironmentMapSpec e;
  const std::string file = env.string("file");
  if (file.empty()) throw specError(env.child("file"), "must not be empty");
  e.file = fs::path(file).is_absolute() ? fs::path(file) : baseDirectory / file;
  spec.inputs.push_back({e.file, env.child("file")});
  if (env.has("gloss_chain")) {
    parseGlossChain(env, e, spec);
  } else {
    parseEnvironmentLobe(env, e, spec, baseDirectory);
  }
  if (env.has("method")) e.method = env.parsed("method", parsePrefilterMethod);
  e.maxError = env.number("max_error", 0.01, 0.0, 0.5, /*exclusiveMinimum=*/true);
  if (env.has("from")) e.from = env.parsed("from", parseParameterizationKind);
  for (const char* key : {"view", "up"}) {
    if (!env.has(key)) continue;
    if (spec.parameterization != ParameterizationKind::Sphere) {
      throw specError(env.child(key), "only sphere maps have a view; the others live in the environment's frame");
    }
    (std::string(key) == "view" ? e.view : e.up) = env.direction(key);
  }
  parseEnvironmentOutputs(env, e, spec, baseDirectory);
  env.finish();
  spec.content = std::move(e);
}

// The rules a map's material must meet (lights, view, profile symmetry): at parse time, or after
// a deferred fit has made the material.
void checkMaterialMap(const MapSpec& spec) {
  const MaterialMapSpec& m = *spec.materialMap();
  if (m.environment) {  // lit by an environment: only the BRDF matters
    try {
      requireBrdf(*m.material);
    } catch (const Error& e) {
      throw specError(spec.jsonPath + ".material", e.what());
    }
    return;
  }
  if (m.material->usesLights() && m.lights.empty()) {
    throw specError(spec.jsonPath + ".lights", std::string(m.material->model()) + " needs at least one light");
  }
  if (!m.material->usesLights() && !m.lights.empty()) {
    throw specError(spec.jsonPath + ".lights", std::string(m.material->model()) + " ignores lights; remove them");
  }
  const bool viewDependent = !m.material->viewIndependent() || m.lightAtEye;
  if (viewDependent && spec.viewNeed == MapSpec::ViewNeed::Free) {
    throw specError(spec.jsonPath + ".view",
                    std::string(m.material->model()) + (m.lightAtEye ? " lit from the eye" : "") +
                        " depends on the view direction, so no environment map can serve a free view;"
                        " use \"view\": \"fixed\"");
  }
  // A fixed view ("fixed", or a sphere map's eye space) is +z in every candidate map frame.
  const bool viewFixed =
      spec.viewGiven || spec.viewNeed == MapSpec::ViewNeed::Fixed || spec.autoSelect.parameterization;
  if (spec.parameterization != ParameterizationKind::Sphere && viewDependent && !viewFixed) {
    throw specError(spec.jsonPath,
                    std::string(m.material->model()) + (m.lightAtEye ? " lit from the eye" : "") +
                        " depends on the view direction, but a " + std::string(toString(spec.parameterization)) +
                        " map is indexed by reflected direction only; fix the view with \"view\": [x, y, z]"
                        " or use a sphere map");
  }
  if (spec.radialProfile && !spec.makeFunction()->symmetryAxis()) {
    throw specError(spec.jsonPath + ".parameterization",
                    "a profile needs a map radially symmetric about one axis: reflectance-mode and Fresnel materials, "
                    "silhouettes, untwisted colorgrams, or lobes (Phong, fitted) about one light; " +
                        std::string(m.material->model()) + " here is not");
  }
}

// "material", "lights" and the extra files of some models: a material map.
void parseMaterialMap(JsonObjectReader& map, MapSpec& spec, const fs::path& baseDirectory) {
  MaterialMapSpec& m = spec.content.emplace<MaterialMapSpec>();
  std::optional<DeferredFit> deferred;
  const bool underEnvironment = map.has("environment");  // lit by an environment (docs/matcap.md)
  m.material = parseMaterial(map.require("material"), map.child("material"),
                             {baseDirectory, &spec.inputs, &spec.notes, &deferred, underEnvironment});
  m.deferredFit = std::move(deferred);
  if (underEnvironment) {
    materials::parseEnvironmentLighting(map, spec, baseDirectory);
    if (!m.deferredFit) checkMaterialMap(spec);
    return;
  }

  if (map.has("lights")) {
    const auto& lights = map.array("lights", kMaxLights);
    for (std::size_t i = 0; i < lights.size(); ++i) {
      bool atEye = false;
      m.lights.push_back(parseLight(lights[i], map.child("lights") + "[" + std::to_string(i) + "]", spec.view, atEye));
      m.lightAtEye = m.lightAtEye || atEye;
    }
  }
  if (m.deferredFit) {
    // What can be checked before the fit: whether the mode uses lights.
    const bool usesLights = m.deferredFit->mode != LobeMaterialMode::Reflectance;
    if (usesLights && m.lights.empty())
      throw specError(map.child("lights"), "measured in this mode needs at least one light");
    if (!usesLights && !m.lights.empty())
      throw specError(map.child("lights"), "measured in reflectance mode ignores lights; remove them");
  } else {
    checkMaterialMap(spec);
  }
  materials::parseMapExtras(map, spec);  // "mips", "fresnel_table_output"
  if (spec.radialProfile && m.mips) throw specError(map.child("mips"), "a profile has no mip levels of its own");
  if (!m.deferredFit && !spec.anyAuto() && !spec.radialProfile) materials::checkMaterialSampling(spec);
}

// "parameterization": a map kind, "profile" or "auto".
void parseParameterization(JsonObjectReader& map, MapSpec& spec) {
  const std::string kind = map.string("parameterization");
  if (kind == "auto") {
    spec.autoSelect.parameterization = true;
  } else if (kind == "profile") {
    spec.radialProfile = true;
  } else {
    try {
      spec.parameterization = parseParameterizationKind(kind);
    } catch (const Error&) {
      throw specError(map.child("parameterization"),
                      "parameterization must be one of sphere, paraboloid, cube, latlong, profile, auto; got \"" +
                          printable(kind, 40) + "\"");
    }
  }
}

// "resolution" and "samples_per_texel", each a number or "auto", and "max_error", which "auto" needs.
void parseSampling(JsonObjectReader& map, MapSpec& spec) {
  auto isAuto = [&](const char* key) {
    const auto* entry = map.find(key);
    return entry && entry->is_string() && *entry == "auto";
  };
  if (isAuto("resolution"))
    spec.autoSelect.resolution = true;
  else
    spec.resolution = map.integer("resolution", 256, 1, 65536);
  if (isAuto("samples_per_texel"))
    spec.autoSelect.samplesPerTexel = true;
  else
    spec.samplesPerTexel = map.integer("samples_per_texel", 16, 1, 4096);
  if (spec.anyAuto()) {
    if (!map.has("max_error"))
      throw specError(map.child("max_error"), "required with \"auto\" values: the RMS lookup error to meet, e.g. 0.01");
    spec.autoSelect.maxError = map.number("max_error", 0.0, 1.0, /*exclusiveMinimum=*/true);
    if (spec.autoSelect.maxError >= 1.0) throw specError(map.child("max_error"), "must be < 1");
  } else if (map.has("max_error")) {
    throw specError(map.child("max_error"),
                    "only applies when parameterization, resolution or samples_per_texel is \"auto\"");
  }
}

// "layout" of a cube map: "cross" or "faces".
void parseCubeLayout(JsonObjectReader& map, MapSpec& spec) {
  if (const auto* layout = map.find("layout")) {
    if (spec.parameterization != ParameterizationKind::Cube)
      throw specError(map.child("layout"), "only applies to cube maps");
    if (*layout == "cross") {
      spec.cubeLayout = CubeLayout::Cross;
    } else if (*layout == "faces") {
      spec.cubeLayout = CubeLayout::Faces;
    } else {
      throw specError(map.child("layout"), "must be \"cross\" or \"faces\", got " + describe(*layout));
    }
  }
}

// "view": "fixed", "free" or a direction [x, y, z].
void parseView(JsonObjectReader& map, MapSpec& spec) {
  if (const auto* view = map.find("view"); view && view->is_string()) {
    if (*view == "fixed") {
      spec.viewNeed = MapSpec::ViewNeed::Fixed;
    } else if (*view == "free") {
      spec.viewNeed = MapSpec::ViewNeed::Free;
      if (!spec.autoSelect.parameterization && spec.parameterization == ParameterizationKind::Sphere) {
        throw specError(map.child("view"),
                        "a sphere map holds one view (eye space); a free view needs a paraboloid, cube or latlong map");
      }
    } else {
      throw specError(map.child("view"), "must be \"fixed\", \"free\" or [x, y, z], got " + describe(*view));
    }
  } else if (map.has("view")) {
    if (spec.autoSelect.parameterization || spec.parameterization == ParameterizationKind::Sphere) {
      throw specError(map.child("view"),
                      spec.autoSelect.parameterization
                          ? "with \"parameterization\": \"auto\" give \"view\": \"fixed\" or \"free\""
                          : "sphere maps live in eye space, where the view vector is always +z; remove it");
    }
    spec.view = map.direction("view");
    spec.viewGiven = true;
  }
}

MapSpec parseMap(const nlohmann::json& value, const std::string& path, const fs::path& baseDirectory, bool inMemory) {
  JsonObjectReader map(value, path);
  MapSpec spec;
  spec.jsonPath = path;
  spec.raw = value;
  spec_detail::parseMapOutputs(map, spec, baseDirectory, inMemory);  // "output" or "outputs"
  parseParameterization(map, spec);
  parseSampling(map, spec);
  parseCubeLayout(map, spec);
  parseView(map, spec);

  if (map.has("environment") && !map.has("material")) {  // a prefiltered environment map (docs/prefilter.md)
    if (spec.radialProfile) throw specError(map.child("parameterization"), "environment maps cannot be profiles");
    parseEnvironmentMap(map, spec, baseDirectory);
  } else {
    parseMaterialMap(map, spec, baseDirectory);
  }
  spec_detail::parseTexelFormatAndCheckOutputs(map, spec);
  map.finish();
  spec_detail::refuseFilesInMemory(spec);
  return spec;
}

}  // namespace

void MapSpec::prepare(const Context& context) {
  MaterialMapSpec* m = materialMap();
  if (!m || !m->deferredFit) return;
  try {
    m->material = m->deferredFit->run(context);
    m->deferredFit.reset();
    checkMaterialMap(*this);
    if (!anyAuto() && !radialProfile) materials::checkMaterialSampling(*this);
  } catch (const Error& e) {
    throw Error(e.kind(), specLabel.empty() ? std::string(e.what()) : specLabel + ": " + e.what());
  }
}

std::string MaterialMapSpec::modelName() const {
  if (material) return std::string(material->model());
  return deferredFit ? "measured" : "";
}

std::string MapSpec::modelName() const {
  const MaterialMapSpec* m = materialMap();
  return m ? m->modelName() : "";
}

std::vector<FilePlan::Entry> MapSpec::plannedOutputs() const {
  std::vector<FilePlan::Entry> out;
  auto add = [&out](const std::vector<FilePlan::Entry>& files) { out.insert(out.end(), files.begin(), files.end()); };
  const std::vector<fs::path> files = outputs();
  if (const EnvironmentMapSpec* environment = environmentMap()) {
    const EnvironmentMapSpec& e = *environment;
    PrefilterOutputs shape{parameterization, resolution, e.mips, cubeLayout, e.mipLayout};
    if (e.lobeModel() && e.lobeModel()->variesWithView()) shape.elevationSlices = e.elevations;
    shape.fresnel = e.fresnel.has_value();
    if (e.glossChain) shape.mips = true, shape.mipLevels = static_cast<int>(e.chainLobes.size());
    for (std::size_t i = 0; i < files.size(); ++i) add(prefilterOutputFiles(files[i], shape, outputJsonPath(i)));
    if (const auto& sh = e.shOutput) out.push_back({*sh, jsonPath + ".environment.sh_output"});
    return out;
  }
  const MaterialMapSpec& m = *materialMap();
  const bool cube = parameterization == ParameterizationKind::Cube && !anyAuto() && !radialProfile;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const std::string role = outputJsonPath(i);
    add(mapOutputFiles(files[i], role, cube, cubeLayout));
    if (m.mips && m.mipLayout == MipLayout::Files) {
      for (int level = 1; level < mipLevelCount(resolution); ++level) {
        add(mapOutputFiles(mipLevelPath(files[i], level), role + " (mip level " + std::to_string(level) + ")"));
      }
    }
  }
  if (const auto& table = m.fresnelTableOutput) {
    add(mapOutputFiles(table->is_absolute() ? *table : output.parent_path() / *table,
                       jsonPath + ".fresnel_table_output"));
  }
  return out;
}

FilePlan planSpecFiles(const BakeSpec& spec, const fs::path& specFile, const std::optional<fs::path>& outputFolder) {
  FilePlan plan(outputFolder);
  if (!specFile.empty()) plan.addInput(specFile, "spec");
  for (const auto& map : spec.maps) {
    for (const auto& input : map.inputs) plan.addInput(input.file, input.role);
  }
  for (const auto& map : spec.maps) {
    for (const auto& output : map.plannedOutputs()) plan.addOutput(output.file, output.role);
  }
  return plan;
}

AutoOptions MapSpec::autoOptions() const {
  AutoOptions options;
  options.maxError = autoSelect.maxError;
  options.allowRadialProfile = autoSelect.parameterization || radialProfile;
  if (radialProfile) {
    options.parameterizations.clear();  // profiles only
  } else if (autoSelect.parameterization) {
    options.parameterizations =
        viewNeed == ViewNeed::Free
            ? std::vector{ParameterizationKind::Paraboloid, ParameterizationKind::Cube, ParameterizationKind::LatLong}
            : std::vector{ParameterizationKind::Sphere, ParameterizationKind::Paraboloid, ParameterizationKind::Cube,
                          ParameterizationKind::LatLong};
  } else {
    options.parameterizations = {parameterization};
  }
  if (!autoSelect.resolution) options.resolutions = {resolution};
  if (!autoSelect.samplesPerTexel) options.samplesPerTexel = {samplesPerTexel};
  return options;
}

PrefilterOptions MapSpec::prefilterOptions() const {
  const EnvironmentMapSpec* environment = environmentMap();
  if (!environment) throw Error(Error::Kind::InvalidArgument, jsonPath + ": a material map has no prefilter options");
  PrefilterOptions options;
  options.parameterization = parameterization;
  options.resolution = resolution;
  options.mips = environment->mips;
  options.method = environment->method;
  options.maxError = environment->maxError;
  options.view = environment->view;
  options.up = environment->up;
  options.mirrorSamples = samplesPerTexel;
  options.elevations = environment->elevations;
  if (environment->glossChain) options.cubeEdgeFixup = environment->glossChain->edgeFixup;
  return options;
}

std::shared_ptr<const MapFunction> MapSpec::makeFunction() const {
  const MaterialMapSpec* m = materialMap();
  if (!m) {
    throw Error(Error::Kind::InvalidArgument, jsonPath +
                                                  ": an environment map is prefiltered from its environment "
                                                  "(brdfbake bake or prefilter), not baked from a material");
  }
  if (m->environment) {
    throw Error(Error::Kind::InvalidArgument, jsonPath +
                                                  ": a material lit by an environment is made by "
                                                  "bakeUnderEnvironment (spec.hpp), not baked from a function of "
                                                  "directions");
  }
  if (!m->material) {
    throw Error(Error::Kind::InvalidArgument,
                jsonPath + ": the measured material's fit has not run yet; call MapSpec::prepare() first");
  }
  return std::make_shared<MaterialMapFunction>(m->material, m->lights, view);
}

BakeSpec parseBakeSpec(const nlohmann::json& document, const fs::path& baseDirectory, const std::string& label,
                       bool inMemory) {
  try {
    JsonObjectReader root(document, "");
    BakeSpec spec;
    const auto& maps = root.array("maps", kMaxMaps);
    if (maps.empty()) throw specError("maps", "must hold at least one map");
    for (std::size_t i = 0; i < maps.size(); ++i) {
      spec.maps.push_back(parseMap(maps[i], "maps[" + std::to_string(i) + "]", baseDirectory, inMemory));
      spec.maps.back().specLabel = label;
    }
    root.finish();
    // Each output (every file of "outputs") resolved once, then looked up among those before it: the
    // same resolved path, or the same existing file (a hard link).
    std::map<fs::path, std::string> byPath;
    std::map<std::pair<dev_t, ino_t>, std::string> byInode;
    for (const MapSpec& map : spec.maps) {
      const std::vector<fs::path> files = map.outputs();
      for (std::size_t k = 0; k < files.size(); ++k) {
        const std::string name = map.outputJsonPath(k);
        const auto [path, fresh] = byPath.emplace(resolvedPath(files[k]), name);
        if (!fresh) throw specError(name, "same file as " + path->second);
        struct stat info {};
        if (::stat(files[k].c_str(), &info) != 0) continue;
        const auto [inode, freshInode] = byInode.emplace(std::pair(info.st_dev, info.st_ino), name);
        if (!freshInode) throw specError(name, "same file as " + inode->second);
      }
    }
    return spec;
  } catch (const Error& e) {
    throw Error(e.kind(), printable(label) + ": " + e.what());
  }
}

BakeSpec loadBakeSpec(const fs::path& file, bool inMemory) {
  const nlohmann::json document = readJsonFile(file);
  BakeSpec spec =
      parseBakeSpec(document, file.parent_path().empty() ? fs::path(".") : file.parent_path(), file.string(), inMemory);
  spec.file = file;
  return spec;
}

LobeArgument parseLobeArgument(const std::string& text, const fs::path& baseDirectory) {
  LobeArgument argument;
  if (text.rfind("lobes:", 0) == 0) {  // a fitted lobe model (docs/fitting.md)
    const fs::path fit(text.substr(6));
    argument.fitFile = fit.is_absolute() ? fit : baseDirectory / fit;
    argument.lobe = std::make_shared<const LobeModel>(readFitFile(argument.fitFile).fit.model);
  } else {
    argument.lobe = PrefilterLobe::parse(text, baseDirectory);
  }
  return argument;
}

}  // namespace brdfbake
