// Bake throughput (texel-samples per second) and accuracy against the exact model, for sphere
// and paraboloid maps of Phong (n = 50) and Cook-Torrance (Beckmann m = 0.3, copper F0, lighting
// mode) under a general light, over resolution, samples per texel and threads; plus the plain
// single-threaded double loop the target refers to.
//
//   build/bench/bench_bake                        # everything
//   build/bench/bench_bake --benchmark_filter=Target
#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/auto_config.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/maps/paraboloid_map.hpp>
#include <brdfbake/maps/sphere_map.hpp>

#include <benchmark/benchmark.h>

#include "plain_loop.hpp"

#include <random>

namespace {
using namespace brdfbake;

const Vec3 kLight = Vec3(1, 1, 1).normalized();
constexpr double kExponent = 50.0;

MaterialMapFunction phongFunction() {
  return MaterialMapFunction(std::make_shared<PhongMaterial>(Rgb::Ones(), kExponent), {{kLight, Rgb::Ones()}},
                             Vec3::UnitZ());
}

MaterialMapFunction cookTorranceFunction() {
  CookTorranceParams params;
  params.mode = CookTorranceMode::Lighting;
  params.roughness = 0.3;
  params.fresnel = FresnelTerm::fromF0(Rgb(0.955, 0.638, 0.538));
  return MaterialMapFunction(std::make_shared<CookTorranceMaterial>(params), {{kLight, Rgb::Ones()}}, Vec3::UnitZ());
}

// Arguments: model (0 Phong, 1 Cook-Torrance), parameterization, resolution, samples, threads.
void BakeMap(benchmark::State& state) {
  const int model = static_cast<int>(state.range(0));
  const auto kind = static_cast<ParameterizationKind>(state.range(1));
  const int resolution = static_cast<int>(state.range(2));
  BakeOptions options;
  options.samplesPerTexel = static_cast<int>(state.range(3));
  const Context context({.threads = static_cast<int>(state.range(4))});
  const auto map = makeParameterization(kind, resolution);
  const auto function = model == 0 ? phongFunction() : cookTorranceFunction();
  Image image;
  for (auto _ : state) {
    image = bake(*map, function, options, context);
    benchmark::DoNotOptimize(image.data());
  }
  const double samples = double(map->width()) * map->height() * options.samplesPerTexel;
  state.counters["samples/s"] = benchmark::Counter(samples, benchmark::Counter::kIsIterationInvariantRate);
  // The library's measures (docs/accuracy.md), relative to the peak: `error` is what max_error bounds.
  const ErrorStats error = measureMapError(image, *map, function);
  state.counters["rms_err"] = error.rms;
  state.counters["max_err"] = error.max;
  state.counters["highlight_rms"] = error.highlightRms;
  state.counters["error"] = autoErrorMeasure(error, kind);
  state.SetLabel(std::string(model == 0 ? "phong " : "cook-torrance ") + std::string(toString(kind)));
}

void BakeArguments(benchmark::internal::Benchmark* b) {
  for (int model : {0, 1})
    for (int kind : {0, 1})
      for (int n : {256, 512, 1024, 2048})
        for (int spt : {1, 4, 16, 64})
          for (int threads : {1, 2}) b->Args({model, kind, n, spt, threads});
}
// CPU time is the process's (every thread's): on a shared machine compare CPU times, which other
// jobs inflate far less than wall times (bench/bake_table.py prints both).
BENCHMARK(BakeMap)
    ->Apply(BakeArguments)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->MinTime(0.2);

// The baseline: a plain single-threaded loop over texels and samples in double,
// evaluating the model through the inverse mapping (1024^2 sphere map, 16 samples per texel).
void TargetPlainLoop(benchmark::State& state) {
  std::vector<float> out;
  for (auto _ : state) {
    bench::plainPhongLoop(out);
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(TargetPlainLoop)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime()->MinTime(1.0);

// The same map through brdfbake's baker, on 1 and 2 threads (argument), with its error bound. On a
// sphere map Phong bakes on the radial path from the samples' normals, with texels culled in runs
// (bake/baker.cpp, SphereRadialPath).
void TargetBrdfbake(benchmark::State& state) {
  const SphereMap map(1024);
  const auto function = phongFunction();
  BakeOptions options;
  options.samplesPerTexel = 16;
  const Context context({.threads = static_cast<int>(state.range(0))});
  Image image;
  for (auto _ : state) {
    image = bake(map, function, options, context);
    benchmark::DoNotOptimize(image.data());
  }
  state.counters["samples/s"] =
      benchmark::Counter(1024.0 * 1024.0 * 16.0, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["error"] = autoErrorMeasure(measureMapError(image, map, function), ParameterizationKind::Sphere);
}
BENCHMARK(TargetBrdfbake)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->MinTime(1.0);

}  // namespace

BENCHMARK_MAIN();
