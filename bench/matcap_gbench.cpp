// The matcap bake (shadeUnderEnvironment, auto at 1 %) as Google Benchmark runs it: GGX copper
// (Schlick F0 (0.955, 0.638, 0.538), alpha 0.3, separable Smith G) and Phong 200 under
// SkyEnvironment (a 1.5-degree sun of radiance ~2000) as a 1024 x 512 lat-long, at 256^2 and
// 512^2, on 1 and 2 threads. Counters: the map's own error estimate (max of the lookup RMS and the
// value-weighted RMS, relative to the peak) and its bright texels. Figures: docs/matcap.md.
//
// MatcapPreview is a material editor's live preview: 256^2 at a 5 % bound under the README's sample
// sky, prepared once (the environment keeps its bright texels and pyramid between calls), reported
// with `loops`, its time as a fraction of the plain single-threaded Phong loop (plain_loop.hpp) timed
// in the same run.
//
//   build/bench/matcap_gbench --benchmark_min_time=1
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/material_under_environment.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "plain_loop.hpp"

namespace {
using namespace brdfbake;

const Environment& sky() {
  static const Environment environment =
      bakeEnvironment(SkyEnvironment(), ParameterizationKind::LatLong, 512, "sky", 16);
  return environment;
}

std::shared_ptr<const Material> material(int which) {
  if (which == 1) return std::make_shared<PhongMaterial>(Rgb(0.5, 0.5, 0.5), 200.0, Rgb(0.4, 0.1, 0.1));
  CookTorranceParams p;
  p.mode = CookTorranceMode::Lighting;
  p.distribution = MicrofacetDistribution::Ggx;
  p.roughness = 0.3;
  p.fresnel = FresnelTerm::schlick(Rgb(0.955, 0.638, 0.538));
  p.shadowing = MicrofacetShadowing::SmithSeparable;
  return std::make_shared<CookTorranceMaterial>(p);
}

// Arguments: material (0 GGX copper, 1 Phong 200), resolution, threads.
void Matcap(benchmark::State& state) {
  const auto m = material(static_cast<int>(state.range(0)));
  UnderEnvironmentOptions options;
  options.resolution = static_cast<int>(state.range(1));
  const Context context({.threads = static_cast<int>(state.range(2))});
  const Environment& environment = sky();
  UnderEnvironmentSummary summary;
  for (auto _ : state) {
    MaterialUnderEnvironment made = shadeUnderEnvironment(environment, *m, options, context);
    benchmark::DoNotOptimize(made.image.data());
    summary = made.summary;
  }
  state.SetLabel(std::string(m->model()) + ": " + summary.detail);
  state.counters["error_estimate_pct"] = 100.0 * summary.errorEstimate;
  state.counters["bright_texels"] = summary.brightTexels;
}
BENCHMARK(Matcap)
    ->ArgNames({"material", "resolution", "threads"})
    ->ArgsProduct({{0, 1}, {256, 512}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The plain loop's seconds, the median of 3 runs, measured once per process.
double plainLoopSeconds() {
  static const double seconds = [] {
    std::vector<float> out;
    std::vector<double> runs;
    for (int i = 0; i < 3; ++i) {
      const auto start = std::chrono::steady_clock::now();
      brdfbake::bench::plainPhongLoop(out);
      runs.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      benchmark::DoNotOptimize(out.data());
    }
    std::sort(runs.begin(), runs.end());
    return runs[1];
  }();
  return seconds;
}

// Arguments: material (0 GGX copper, 1 Phong 200), threads.
void MatcapPreview(benchmark::State& state) {
  static const Environment environment =
      loadEnvironment(BRDFBAKE_SOURCE_DIR "/data_samples/environments/sky_latlong.exr");
  const auto m = material(static_cast<int>(state.range(0)));
  UnderEnvironmentOptions options;
  options.resolution = 256;
  options.maxError = 0.05;
  const Context context({.threads = static_cast<int>(state.range(1))});
  const double loop = plainLoopSeconds();
  UnderEnvironmentSummary summary;
  double seconds = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    MaterialUnderEnvironment made = shadeUnderEnvironment(environment, *m, options, context);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    benchmark::DoNotOptimize(made.image.data());
    summary = made.summary;
  }
  state.SetLabel(std::string(m->model()) + ": " + summary.detail);
  state.counters["loops"] = seconds / static_cast<double>(state.iterations()) / loop;
  state.counters["error_estimate_pct"] = 100.0 * summary.errorEstimate;
}
BENCHMARK(MatcapPreview)
    ->ArgNames({"material", "threads"})
    ->ArgsProduct({{0, 1}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
