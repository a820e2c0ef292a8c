// A map of a material lit by an environment (a matcap when it is a sphere map; docs/matcap.md):
// shadeUnderEnvironment through the spec (bakeUnderEnvironment), then written with its error report.
#include <brdfbake/env/material_under_environment.hpp>

#include <chrono>
#include <cmath>

#include "map_runners.hpp"

namespace brdfbake::run_detail {
namespace fs = std::filesystem;

MapResult runUnderEnvironmentMap(const MapSpec& specified, const Environment& environment,
                                 const MapRunContext& context) {
  MapSpec map = specified;
  if (const auto& fit = map.materialMap()->deferredFit) {  // a measured material's fit runs now
    map.prepare(progressFor(context.options.progress,
                            map.jsonPath + " fitting lobes to " + fs::path(fit->table.sourceFile).filename().string()));
  }
  RunOptions run;
  run.threads = context.options.threads;
  run.allowLarge = context.options.allowLarge;
  run.progress = progressFor(context.options.progress, map.jsonPath + " " + map.output.filename().string());
  MaterialUnderEnvironment made = bakeUnderEnvironment(map, environment, run);
  // "exposure" (checked by the spec's parser): 2^stops on RGB, for 8-bit outputs; the error estimate is
  // relative to the peak, so it holds for the scaled map too.
  const double exposure = map.raw.value("exposure", 0.0);
  if (exposure != 0.0) {
    const float scale = static_cast<float>(std::exp2(exposure));
    float* texels = made.image.data();
    for (std::size_t i = 0; i < made.image.index(0, made.image.height()); i += 4)
      for (int c = 0; c < 3; ++c) texels[i + c] *= scale;
  }
  const UnderEnvironmentSummary& s = made.summary;
  const auto writeStart = std::chrono::steady_clock::now();
  MapWriteReport written;
  const std::vector<fs::path> files = map.outputs();
  for (std::size_t i = 0; i < files.size(); ++i) {
    appendWritten(written, writeUnderEnvironmentMap(made, files[i], map.raw, map.cubeLayout,
                                                    map.writeOptionsFor(i, context.write.inputs)));
  }
  const double writeSeconds = secondsSince(writeStart);
  const std::string kind(toString(map.parameterization));
  const int width = made.map->width(), height = made.map->height();
  std::vector<std::string> notes = s.notes;
  notes.insert(notes.end(), written.notes.begin(), written.notes.end());
  MapResult result = makeMapResult(
      map, {kind, map.resolution, width, height, "under_environment", s.seconds, writeSeconds}, written.files, notes);
  result.entry["samples_per_texel"] = map.samplesPerTexel;
  result.entry["under_environment"] = s.toJson();
  result.lines.push_back("wrote " + outputNames(map) + " (" + kind + " " + std::to_string(width) + "x" +
                         std::to_string(height) + ", lit by " + map.environmentLighting()->file.filename().string() +
                         "): " + formatNumber(s.seconds) + " s, write " + formatNumber(writeSeconds) + " s");
  result.lines.push_back("  " + s.briefReport());
  for (const auto& note : result.notes) result.lines.push_back("  note: " + note);
  return result;
}

}  // namespace brdfbake::run_detail
