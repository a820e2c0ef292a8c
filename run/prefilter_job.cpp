// Prefiltering an environment (prefilter_job.hpp): one map, a stack over view elevation (varying lobe
// models), a Fresnel decomposition (three files) or a gloss chain, with SH irradiance beside; made in
// memory, written, and run from files. A spec's environment map goes through the same steps.
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/printable.hpp>
#include <brdfbake/env/sh_irradiance.hpp>
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/text_io.hpp>
#include <brdfbake/maps/map_mips.hpp>
#include <brdfbake/run/prefilter_job.hpp>
#include <brdfbake/spec/spec.hpp>

#include <chrono>

#include "map_runners.hpp"

namespace brdfbake {
namespace fs = std::filesystem;
using namespace run_detail;

namespace {

void validateShape(const PrefilterRequest& r) {
  requireField(r.environment && r.environment->map && !r.environment->image.empty(), "environment",
               "no environment given");
  requireField(r.resolution >= 1 && r.resolution <= 65536, "resolution",
               "must be in [1, 65536], got " + std::to_string(r.resolution));
  requireField(r.samplesPerTexel >= 1 && r.samplesPerTexel <= 4096, "samples_per_texel",
               "must be in [1, 4096], got " + std::to_string(r.samplesPerTexel));
  requireField(r.maxError > 0.0 && r.maxError <= 0.5, "max_error",
               "must be in (0, 0.5] (0.01 is 1 %), got " + formatG(r.maxError));
  requireField(r.elevations >= 2 && r.elevations <= 64, "elevations",
               "must be in [2, 64], got " + std::to_string(r.elevations));
  requireField(r.method != PrefilterMethod::Resample, "method",
               "resample is the mirror lobe's; choose auto or reference");
  for (const auto& [vector, name] : {std::pair{&r.view, "view"}, std::pair{&r.up, "up"}}) {
    requireField(vector->allFinite() && vector->norm() > 0.0, name, "must be a non-zero finite vector");
    requireField(r.parameterization == ParameterizationKind::Sphere ||
                     (vector->normalized() - (vector == &r.view ? Vec3::UnitZ() : Vec3::UnitY())).norm() < 1e-12,
                 name, "only sphere maps have a view; the others live in the environment's frame");
  }
  requireField(r.view.normalized().cross(r.up.normalized()).norm() > 1e-6, "up", "must not be parallel to the view");
}

void validateLobe(const PrefilterRequest& r) {
  const bool analytic = !r.lobeModel && !r.glossChain;
  requireField(!(r.lobeModel && r.glossChain), "lobe", "give fitted lobes or a gloss chain, not both");
  requireField(!r.lobeModel || r.lobeModel->variesWithView() || r.elevations == 8, "elevations",
               "only lobe models that vary with elevation make a stack of maps over elevation");
  requireField(
      !analytic || !r.lobe.isMirror() || r.method == PrefilterMethod::Auto || r.method == PrefilterMethod::Reference,
      "method",
      "the mirror lobe is plain resampling (no integral); " + std::string(toString(r.method)) +
          " applies to filtered lobes only");
  requireField(!r.fresnel || (analytic && !r.lobe.indexedByNormal()), "fresnel",
               "a Fresnel decomposition needs a specular lobe (mirror, phong:N, blinn:N, ggx:R) for its specular "
               "map; the irradiance map is made with it");
  requireField(r.fresnel || r.combine == FresnelCombine::Add, "combine", "needs fresnel (how it is combined)");
  requireField(!r.sh || (analytic && r.lobe.indexedByNormal() && !r.fresnel), "sh",
               "spherical-harmonic coefficients hold irradiance: use them with the irradiance lobe");
  if (r.glossChain) {
    requireField(!r.mips && !r.fresnel, "gloss_chain",
                 "the chain is its own mip levels; it does not combine with mips or fresnel");
    const int available = std::min(16, mipLevelCount(r.resolution));
    requireField(r.glossChain->levels >= 0 && r.glossChain->levels <= available, "gloss_chain",
                 "levels must be in [1, " + std::to_string(available) + "] for resolution " +
                     std::to_string(r.resolution) + " (0: every level), got " + std::to_string(r.glossChain->levels));
    try {
      r.glossChain->lobes(r.resolution);
    } catch (const Error& e) {
      throw Error::invalidField("gloss_chain", e.what());
    }
  }
}

}  // namespace

void PrefilterRequest::validate() const {
  validateShape(*this);
  validateLobe(*this);
}

PrefilterOptions PrefilterRequest::options() const {
  PrefilterOptions o;
  o.parameterization = parameterization;
  o.resolution = resolution;
  o.mips = mips;
  o.method = method;
  o.maxError = maxError;
  o.view = view;
  o.up = up;
  o.mirrorSamples = samplesPerTexel;
  o.elevations = elevations;
  if (glossChain) o.cubeEdgeFixup = glossChain->edgeFixup;
  return o;
}

std::string PrefilterRequest::describedLobe() const {
  if (!lobeName.empty()) return lobeName;
  if (glossChain) {
    const auto lobes = glossChain->lobes(resolution);
    return lobes.front().name() + " ... " + lobes.back().name();
  }
  return lobeModel ? "lobes" : lobe.name();
}

namespace {

// --chain ggx, or --gloss-scale with --lobe phong|blinn; the chain's other flags need one of them.
std::optional<GlossChain> glossChainOf(const LobeArguments& a) {
  if (!a.chain && !a.glossScale) {
    requireField(!a.glossBias && !a.mipCount && a.edgeFixup, "gloss_chain",
                 "the gloss bias, mip count and edge fixup are a chain's: give a chain (ggx) or a gloss scale");
    return std::nullopt;
  }
  GlossChain chain;
  if (a.chain) {
    requireField(*a.chain == "ggx", "chain", "the only chain is \"ggx\", got \"" + printable(*a.chain, 40) + "\"");
    requireField(!a.glossScale && !a.glossBias, "gloss_chain",
                 "a GGX chain's level k of L holds roughness k / (L - 1); a gloss scale and bias set Phong exponents");
    requireField(a.lobe.empty() || a.lobe == "ggx", "lobe",
                 "a ggx chain sets every level's lobe; leave the lobe out, got \"" + printable(a.lobe, 40) + "\"");
  } else {
    requireField(a.lobe == "phong" || a.lobe == "blinn", "lobe",
                 "a gloss chain is made of phong or blinn levels (no exponent: each level gets its own), got \"" +
                     printable(a.lobe, 40) + "\"");
    chain.lobe = a.lobe == "phong" ? GlossChain::Lobe::Phong : GlossChain::Lobe::Blinn;
    chain.scale = *a.glossScale;
    chain.bias = a.glossBias.value_or(1.0);
  }
  chain.levels = a.mipCount.value_or(0);
  chain.edgeFixup = a.edgeFixup;
  return chain;
}

}  // namespace

void LobeArguments::apply(PrefilterRequest& request, const fs::path& baseDirectory) const {
  request.glossChain = glossChainOf(*this);
  if (request.glossChain) return;
  requireField(!lobe.empty(), "lobe", "give a lobe (or a chain: ggx)");
  LobeArgument parsed;
  try {
    parsed = parseLobeArgument(lobe, baseDirectory);
  } catch (const Error& e) {
    throw Error::invalidField("lobe", e.what());
  }
  if (const auto* analytic = std::get_if<PrefilterLobe>(&parsed.lobe)) {
    request.lobe = *analytic;
  } else {
    request.lobeModel = std::get<std::shared_ptr<const LobeModel>>(parsed.lobe);
    request.lobeName = lobe;
  }
}

PrefilterResult prefilterEnvironment(const PrefilterRequest& request, const Context& context) {
  request.validate();
  const Environment& environment = *request.environment;
  const PrefilterOptions options = request.options();
  PrefilterResult made;
  made.lobe = request.describedLobe();
  made.glossChain = request.glossChain;
  made.environment = {{"file", fs::path(environment.source).filename().string()},
                      {"lobe", made.lobe},
                      {"parameterization", std::string(toString(environment.kind()))},
                      {"resolution", environment.map->resolution()},
                      {"detected", environment.detection}};
  if (request.lobeModel && request.lobeModel->variesWithView()) {
    made.stack = prefilterLobeModelStack(environment, *request.lobeModel, made.lobe, options, context);
    made.map.summary = made.stack->summary;
    made.map.map = made.stack->slices.front().map;
  } else if (request.fresnel) {
    made.decomposition = prefilterFresnelDecomposition(environment, request.lobe, *request.fresnel, request.combine,
                                                       options, request.resolution, context);
    made.map.summary = made.decomposition->specular.summary;
    made.map.map = made.decomposition->specular.map;
  } else if (request.glossChain) {
    made.map = prefilterGlossChain(environment, request.glossChain->lobes(request.resolution), options, context);
  } else if (request.lobeModel) {
    made.map = prefilterLobeModel(environment, *request.lobeModel, made.lobe, options, context);
  } else {
    made.map = prefilter(environment, request.lobe, options, context);
  }
  if (request.sh) made.sh = irradianceSh(environment);
  return made;
}

namespace {

// The chain's entry: its kind, mapping or gloss constants, and each level's lobe and resolution.
nlohmann::json glossChainJson(const PrefilterResult& made) {
  const GlossChain& chain = *made.glossChain;
  nlohmann::json levels = nlohmann::json::array();
  const int resolution = made.map.map->resolution();
  for (std::size_t k = 0; k < made.map.levels.size(); ++k) {
    nlohmann::json level = k < made.map.levelValues.size() ? made.map.levelValues[k] : nlohmann::json::object();
    level["level"] = k;
    level["resolution"] = std::max(1, resolution >> static_cast<int>(k));
    levels.push_back(level);
  }
  if (chain.lobe == GlossChain::Lobe::Ggx) {
    return {{"kind", "ggx"},
            {"roughness_mapping",
             "level k of L holds perceptual roughness R = k / (L - 1) (alpha = R^2); a renderer reads R at lod = R "
             "(L - 1)"},
            {"levels", levels}};
  }
  return {{"kind", chain.lobeName()}, {"scale", chain.scale}, {"bias", chain.bias}, {"levels", levels}};
}

}  // namespace

nlohmann::json PrefilterResult::toJson() const {
  const PrefilterSummary& summary = map.summary;
  nlohmann::json entry = {{"parameterization", std::string(toString(map.map->kind()))},
                          {"resolution", map.map->resolution()},
                          {"width", map.map->width()},
                          {"height", map.map->height()},
                          {"bake_path", "prefilter:" + std::string(toString(summary.method))},
                          {"bake_seconds", summary.seconds},
                          {"prefilter", summary.toJson()},
                          {"environment", environment}};
  if (stack) {
    entry["elevations"] = {{"slices", stack->slices.size()}, {"cos_theta", stack->cosines}, {"t", stack->coordinates}};
  }
  if (decomposition) {
    entry["fresnel"] = {{"combine", std::string(toString(decomposition->combine))},
                        {"irradiance_prefilter", decomposition->irradiance.summary.toJson()}};
  }
  if (glossChain) entry["gloss_chain"] = glossChainJson(*this);
  return entry;
}

std::vector<FilePlan::Entry> plannedFiles(const PrefilterRequest& request, const MapOutputs& outputs,
                                          const std::optional<ShOutput>& sh) {
  PrefilterOutputs shape{request.parameterization, request.resolution, request.mips, outputs.layout, outputs.mipLayout};
  if (request.lobeModel && request.lobeModel->variesWithView()) shape.elevationSlices = request.elevations;
  shape.fresnel = request.fresnel.has_value();
  if (request.glossChain) shape.mips = true, shape.mipLevels = request.glossChain->levelCount(request.resolution);
  std::vector<FilePlan::Entry> out;
  for (std::size_t i = 0; i < outputs.files.size(); ++i) {
    const auto files = prefilterOutputFiles(outputs.files[i], shape, i == 0 ? "output" : "outputs");
    out.insert(out.end(), files.begin(), files.end());
  }
  if (sh) out.push_back({sh->file, "sh_output"});
  return out;
}

namespace {

MapWriteReport writeOne(const PrefilterResult& made, const fs::path& file, const nlohmann::json& spec,
                        const MapOutputs& outputs, std::size_t i) {
  const WriteOptions options = outputs.writeOptionsFor(i);
  if (made.stack) return writePrefilteredStack(*made.stack, file, spec, outputs.layout, options, outputs.mipLayout);
  if (made.decomposition) {
    return writeFresnelDecomposition(*made.decomposition, file, spec, outputs.layout, options, outputs.mipLayout);
  }
  return writePrefilteredMap(made.map, file, spec, outputs.layout, options, outputs.mipLayout);
}

void writeSh(const ShExpansion& coefficients, const ShOutput& sh, const nlohmann::json& source,
             const std::vector<fs::path>& inputs, MapWriteReport& written) {
  if (sh.cmgen) {
    for (const auto& input : inputs)
      if (sameFile(input, sh.file))
        throw Error(Error::Kind::InvalidArgument, sh.file.string() + ": would overwrite an input");
    writeFileAtomically(sh.file, irradianceShCmgenText(coefficients));
  } else {
    writeIrradianceSh(coefficients, source, sh.file, inputs);
  }
  written.files.push_back(sh.file);
  written.notes.push_back(sh.file.string() +
                          (sh.cmgen ? ": irradiance as cmgen prints it (--sh-shader): 9 RGB coefficients, E(n)/pi "
                                      "= sh[0] + sh[1] y + sh[2] z + sh[3] x + sh[4] yx + sh[5] yz + sh[6] (3z^2 "
                                      "- 1) + sh[7] zx + sh[8] (x^2 - y^2)"
                                    : ": irradiance as 9 SH coefficients per channel (3 bands), E(n)/pi = sum c_i "
                                      "Y_i(n): cosine convolution and 1/pi included, orthonormal basis (the file "
                                      "states it)"));
}

}  // namespace

MapWriteReport writePrefiltered(const PrefilterResult& result, const MapOutputs& outputs,
                                const std::optional<ShOutput>& sh, nlohmann::json spec) {
  outputs.validate();
  require(!sh || result.sh, "sh_output: the result holds no SH coefficients (ask for sh)");
  if (spec.is_null()) {
    spec = {{"parameterization", std::string(toString(result.map.map->kind()))},
            {"resolution", result.map.map->resolution()},
            {"environment", {{"file", result.environment.value("file", std::string())}, {"lobe", result.lobe}}}};
  }
  MapWriteReport written;
  for (std::size_t i = 0; i < outputs.files.size(); ++i)
    appendWritten(written, writeOne(result, outputs.files[i], spec, outputs, i));
  if (sh) writeSh(*result.sh, *sh, result.environment, outputs.inputs, written);
  return written;
}

namespace {

// What a written map's entry adds to its JSON: the Fresnel decomposition's files and the SH file.
void addFileEntries(const PrefilterResult& made, const MapPlace& place, const std::optional<ShOutput>& sh,
                    nlohmann::json& entry) {
  if (made.decomposition) {
    entry["fresnel"]["irradiance"] = fresnelIrradiancePath(place.files.front()).string();
    entry["fresnel"]["table"] = fresnelTablePath(place.files.front()).string();
  }
  if (sh) entry["sh"] = sh->file.string();
}

// The summaries whose error estimate missed the bound, as notes.
std::vector<std::string> boundNotes(const PrefilterResult& made) {
  std::vector<std::string> notes;
  const PrefilterSummary* irradiance = made.decomposition ? &made.decomposition->irradiance.summary : nullptr;
  for (const PrefilterSummary* summary : {&made.map.summary, irradiance}) {
    if (summary && summary->errorEstimated && !summary->metBound) {
      notes.push_back("the estimated error " + formatNumber(100.0 * summary->errorEstimate) + " % of " + summary->lobe +
                      " exceeds the bound (max_error) " + formatNumber(100.0 * summary->maxError) + " %");
    }
  }
  return notes;
}

void addLines(const PrefilterResult& made, const MapPlace& place, double writeSeconds, MapResult& result) {
  const std::string what =
      made.stack ? "wrote " + elevationSlicePath(place.files.front(), 0).string() + " ..." : place.made();
  result.lines.push_back(what + " (" + std::string(toString(made.map.map->kind())) + " " +
                         std::to_string(made.map.map->width()) + "x" + std::to_string(made.map.map->height()) +
                         "): " + made.map.summary.briefReport() + "; write " + formatNumber(writeSeconds) + " s");
  if (result.files.size() > 1) result.lines.push_back("  " + std::to_string(result.files.size()) + " files in all");
  if (made.decomposition) {
    result.lines.push_back("  irradiance map: " + made.decomposition->irradiance.summary.briefReport());
  }
  for (const auto& note : made.map.summary.notes) result.lines.push_back("  note: " + note);
  for (const auto& note : result.notes) result.lines.push_back("  note: " + note);
}

}  // namespace

namespace run_detail {

MapResult reportPrefiltered(const PrefilterResult& made, const MapPlace& place, MapWriteReport written,
                            double writeSeconds, const std::optional<ShOutput>& sh) {
  for (auto& note : boundNotes(made)) written.notes.push_back(std::move(note));
  const PrefilterSummary& summary = made.map.summary;
  MapResult result = makeMapResult(
      place,
      {std::string(toString(made.map.map->kind())), made.map.map->resolution(), made.map.map->width(),
       made.map.map->height(), "prefilter:" + std::string(toString(summary.method)), summary.seconds, writeSeconds},
      written.files, written.notes);
  result.entry.update(made.toJson());
  addFileEntries(made, place, sh, result.entry);
  addLines(made, place, writeSeconds, result);
  return result;
}

}  // namespace run_detail

namespace {

MapResult makeAndWritePrefiltered(const PrefilterRequest& request, const MapOutputs& outputs,
                                  const std::optional<ShOutput>& sh, const MapPlace& place, const nlohmann::json& spec,
                                  const Context& context) {
  auto made = std::make_shared<const PrefilterResult>(prefilterEnvironment(request, context));
  if (outputs.files.empty()) {  // in memory (a spec map without outputs)
    MapResult result = reportPrefiltered(*made, place, {}, 0.0, sh);
    auto write = [made, spec](const MapOutputs& o) { return writePrefiltered(*made, o, std::nullopt, spec); };
    result.made = std::make_shared<const MadeMap>(
        MadeMap{made->map.levels, prefilteredMapInfo(made->map, spec, 0), std::move(write)});
    return result;
  }
  const auto writeStart = std::chrono::steady_clock::now();
  MapWriteReport written = writePrefiltered(*made, outputs, sh, spec);
  return reportPrefiltered(*made, place, std::move(written), secondsSince(writeStart), sh);
}

}  // namespace

namespace run_detail {

MapResult runEnvironmentMap(const MapSpec& map, const EnvironmentMapSpec& e,
                            const std::shared_ptr<const Environment>& environment, const MapRunContext& context) {
  const PrefilterOptions o = map.prefilterOptions();
  PrefilterRequest request;
  request.environment = environment;
  if (const PrefilterLobe* lobe = e.analyticLobe()) request.lobe = *lobe;
  if (const auto* model = std::get_if<std::shared_ptr<const LobeModel>>(&e.lobe)) request.lobeModel = *model;
  request.glossChain = e.glossChain;
  request.lobeName = e.lobeName;
  request.parameterization = o.parameterization;
  request.resolution = o.resolution;
  request.method = o.method;
  request.maxError = o.maxError;
  request.mips = o.mips;
  request.view = o.view, request.up = o.up;
  request.samplesPerTexel = o.mirrorSamples;
  request.elevations = o.elevations;
  request.fresnel = e.fresnel;
  request.combine = e.combine;
  request.sh = e.shOutput.has_value();
  std::optional<ShOutput> sh;
  if (e.shOutput) sh = ShOutput{*e.shOutput, e.shCmgen};
  MapOutputs outputs = outputsOf(map, context.write.inputs);
  outputs.mipLayout = e.mipLayout;
  return makeAndWritePrefiltered(request, outputs, sh, placeOf(map), withoutFolders(map.raw),
                                 context.context.task(map.jsonPath + " " + map.outputName()));
}

}  // namespace run_detail

MapResult runPrefilter(const PrefilterFiles& files, const Context& context) {
  PrefilterRequest request = files.request;
  request.sh = request.sh || files.sh.has_value();
  if (files.sh) requireField(files.sh->problem().empty(), "sh", files.sh->problem());
  files.outputs.validate();
  MapOutputs outputs = files.outputs;
  outputs.inputs.push_back(files.environment);
  std::vector<FilePlan::Entry> inputs{{files.environment, "environment"}};
  checkJobFiles(inputs, plannedFiles(request, outputs, files.sh), outputs.folder);
  if (outputs.mipLayout == MipLayout::Tiled) {
    requireField(request.mips || request.glossChain, "mip_layout",
                 "a tiled file holds a whole mip chain: ask for mips or a gloss chain");
    requireField(
        !request.glossChain || request.glossChain->levelCount(request.resolution) == mipLevelCount(request.resolution),
        "gloss_chain",
        "a chain in one file holds every level down to 1 texel: " + std::to_string(mipLevelCount(request.resolution)) +
            " levels for resolution " + std::to_string(request.resolution));
  }
  for (std::size_t i = 0; i < outputs.files.size(); ++i) {
    OutputShape shape;
    shape.parameterization = request.parameterization;
    shape.resolution = request.resolution;
    shape.wholeChain = outputs.mipLayout == MipLayout::Tiled;
    shape.cubeLayout = outputs.layout;
    shape.texelFormat = outputs.writeOptionsFor(i).texelFormat;
    if (const std::string problem = containerProblem(outputs.files[i], shape); !problem.empty())
      throw Error::invalidField("outputs", problem);
  }
  try {
    request.environment = std::make_shared<const Environment>(loadEnvironment(files.environment, {files.from}));
  } catch (const Error& e) {
    throw Error(e.kind(), "environment: " + std::string(e.what()));
  }
  return makeAndWritePrefiltered(request, outputs, files.sh, MapPlace{"", outputs.files, outputs.files.size() > 1},
                                 nullptr, context.task("prefilter " + outputs.files.front().filename().string()));
}

}  // namespace brdfbake
