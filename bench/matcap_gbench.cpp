// The matcap bake (shadeUnderEnvironment, auto at 1 %) as Google Benchmark runs it: GGX copper
// (Schlick F0 (0.955, 0.638, 0.538), alpha 0.3, separable Smith G) and Phong 200 under
// SkyEnvironment (a 1.5-degree sun of radiance ~2000) as a 1024 x 512 lat-long, at 256^2 and
// 512^2, on 1 and 2 threads. Counters: the map's own error estimate (max of the lookup RMS and the
// value-weighted RMS, relative to the peak) and its bright texels. Figures: docs/matcap.md.
//
//   build/bench/matcap_gbench --benchmark_min_time=1
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/material_under_environment.hpp>

#include <benchmark/benchmark.h>

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

}  // namespace

BENCHMARK_MAIN();
