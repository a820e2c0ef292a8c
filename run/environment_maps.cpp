// A map prefiltered from an environment (docs/prefilter.md): one map, a stack over view elevation
// (varying lobe models), a Fresnel decomposition (three files) or a gloss chain; SH irradiance beside.
#include <brdfbake/core/files.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/env/prefilter_stack.hpp>
#include <brdfbake/env/sh_irradiance.hpp>

#include <chrono>

#include "map_runners.hpp"

namespace brdfbake::run_detail {
namespace fs = std::filesystem;

namespace {

// What prefiltering made, before it is written.
struct Prefiltered {
  std::optional<PrefilteredStack> stack;
  std::optional<FresnelDecomposition> decomposition;
  PrefilteredMap map;  // the one map, the chain, or (stack, decomposition) the summary and first map
};

Prefiltered prefilterMap(const MapSpec& map, const EnvironmentMapSpec& e, const Environment& environment,
                         const PrefilterOptions& options) {
  Prefiltered made;
  if (e.lobeModel() && e.lobeModel()->variesWithView()) {
    made.stack = prefilterLobeModelStack(environment, *e.lobeModel(), e.lobeName, options);
    made.map.summary = made.stack->summary;
    made.map.map = made.stack->slices.front().map;
  } else if (e.fresnel) {
    made.decomposition =
        prefilterFresnelDecomposition(environment, *e.analyticLobe(), *e.fresnel, e.combine, options, map.resolution);
    made.map.summary = made.decomposition->specular.summary;
    made.map.map = made.decomposition->specular.map;
  } else if (e.glossChain) {
    made.map = prefilterGlossChain(environment, e.chainLobes, options);
  } else if (e.lobeModel()) {
    made.map = prefilterLobeModel(environment, *e.lobeModel(), e.lobeName, options);
  } else {
    made.map = prefilter(environment, *e.analyticLobe(), options);
  }
  return made;
}

// What the map was made from, as its JSON entry and the SH file record it.
nlohmann::json environmentSource(const EnvironmentMapSpec& e, const Environment& environment) {
  return {{"file", e.file.string()},
          {"lobe", e.lobeName},
          {"parameterization", std::string(toString(environment.kind()))},
          {"resolution", environment.map->resolution()},
          {"detected", environment.detection}};
}

// What was made, written to one of the map's outputs (its format by its extension).
MapWriteReport writeToOutput(const MapSpec& map, const EnvironmentMapSpec& e, const Prefiltered& made, std::size_t i,
                             const fs::path& file, const MapRunContext& context) {
  const WriteOptions options = map.writeOptionsFor(i, context.write.inputs);
  if (made.stack) return writePrefilteredStack(*made.stack, file, map.raw, map.cubeLayout, options, e.mipLayout);
  if (made.decomposition) {
    return writeFresnelDecomposition(*made.decomposition, file, map.raw, map.cubeLayout, options, e.mipLayout);
  }
  return writePrefilteredMap(made.map, file, map.raw, map.cubeLayout, options, e.mipLayout);
}

// Every output of the map from the one computation, then the SH file once.
MapWriteReport writePrefiltered(const MapSpec& map, const EnvironmentMapSpec& e, const Prefiltered& made,
                                const Environment& environment, const MapRunContext& context) {
  MapWriteReport written;
  const std::vector<fs::path> files = map.outputs();
  for (std::size_t i = 0; i < files.size(); ++i) {
    appendWritten(written, writeToOutput(map, e, made, i, files[i], context));
  }
  if (const auto& sh = e.shOutput) {
    const ShExpansion coefficients = irradianceSh(environment);
    if (e.shCmgen) {
      for (const auto& input : context.write.inputs)
        if (sameFile(input, *sh))
          throw Error(Error::Kind::InvalidArgument, sh->string() + ": would overwrite an input");
      writeFileAtomically(*sh, irradianceShCmgenText(coefficients));
    } else {
      writeIrradianceSh(coefficients, environmentSource(e, environment), *sh, context.write.inputs);
    }
    written.files.push_back(*sh);
    written.notes.push_back(sh->string() +
                            (e.shCmgen ? ": irradiance as cmgen prints it (--sh-shader): 9 RGB coefficients, E(n)/pi "
                                         "= sh[0] + sh[1] y + sh[2] z + sh[3] x + sh[4] yx + sh[5] yz + sh[6] (3z^2 "
                                         "- 1) + sh[7] zx + sh[8] (x^2 - y^2)"
                                       : ": irradiance as 9 SH coefficients per channel (3 bands), E(n)/pi = sum c_i "
                                         "Y_i(n): cosine convolution and 1/pi included, orthonormal basis (the file "
                                         "states it)"));
  }
  return written;
}

// What a kind adds to the map's JSON entry: the environment read, the stack, Fresnel maps, chain, SH.
void addKindEntries(const MapSpec& map, const EnvironmentMapSpec& e, const Prefiltered& made,
                    const Environment& environment, nlohmann::json& entry) {
  entry["prefilter"] = made.map.summary.toJson();
  entry["environment"] = environmentSource(e, environment);
  if (made.stack) {
    entry["elevations"] = {
        {"slices", made.stack->slices.size()}, {"cos_theta", made.stack->cosines}, {"t", made.stack->coordinates}};
  }
  if (made.decomposition) {
    entry["fresnel"] = {{"combine", std::string(toString(e.combine))},
                        {"irradiance", fresnelIrradiancePath(map.output).string()},
                        {"table", fresnelTablePath(map.output).string()},
                        {"irradiance_prefilter", made.decomposition->irradiance.summary.toJson()}};
  }
  if (e.glossChain) {
    nlohmann::json levels = nlohmann::json::array();
    for (std::size_t k = 0; k < e.chainLobes.size(); ++k) {
      nlohmann::json level = k < made.map.levelValues.size() ? made.map.levelValues[k] : nlohmann::json::object();
      level["level"] = k;
      level["resolution"] = std::max(1, map.resolution >> static_cast<int>(k));
      levels.push_back(level);
    }
    if (e.glossChain->ggx) {
      entry["gloss_chain"] = {{"kind", "ggx"},
                              {"roughness_mapping",
                               "level k of L holds perceptual roughness R = k / (L - 1) "
                               "(alpha = R^2); a renderer reads R at lod = R (L - 1)"},
                              {"levels", levels}};
    } else {
      entry["gloss_chain"] = {{"kind", e.lobeName.substr(0, 5) == "blinn" ? "blinn" : "phong"},
                              {"scale", e.glossChain->scale},
                              {"bias", e.glossChain->bias},
                              {"levels", levels}};
    }
  }
  if (const auto& sh = e.shOutput) entry["sh"] = sh->string();
}

// The summaries whose error estimate missed the bound, as notes.
std::vector<std::string> boundNotes(const Prefiltered& made) {
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

void addLines(const MapSpec& map, const Prefiltered& made, double writeSeconds, MapResult& result) {
  const std::string what = made.stack ? elevationSlicePath(map.output, 0).string() + " ..." : outputNames(map);
  result.lines.push_back("wrote " + what + " (" + std::string(toString(map.parameterization)) + " " +
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

MapResult runEnvironmentMap(const MapSpec& map, const EnvironmentMapSpec& e, const Environment& environment,
                            const MapRunContext& context) {
  PrefilterOptions options = map.prefilterOptions();
  options.threads = context.options.threads;
  options.allowLarge = context.options.allowLarge;
  options.progress = progressFor(context.options.progress, map.jsonPath + " " + map.output.filename().string());
  const Prefiltered made = prefilterMap(map, e, environment, options);
  const auto writeStart = std::chrono::steady_clock::now();
  MapWriteReport written = writePrefiltered(map, e, made, environment, context);
  const double writeSeconds = secondsSince(writeStart);
  for (auto& note : boundNotes(made)) written.notes.push_back(std::move(note));
  const PrefilterSummary& summary = made.map.summary;
  MapResult result = makeMapResult(
      map,
      {std::string(toString(map.parameterization)), map.resolution, made.map.map->width(), made.map.map->height(),
       "prefilter:" + std::string(toString(summary.method)), summary.seconds, writeSeconds},
      written.files, written.notes);
  addKindEntries(map, e, made, environment, result.entry);
  addLines(map, made, writeSeconds, result);
  return result;
}

}  // namespace brdfbake::run_detail
