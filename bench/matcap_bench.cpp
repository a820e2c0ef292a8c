// A material under an environment (docs/matcap.md): time and error of shadeUnderEnvironment next to a
// plain brute-force sum over the environment's texels and, when Blender is installed, next to Blender
// Cycles rendering the same sphere.
//
//   build/bench/matcap_bench [--sky ROWS | --environment FILE] [--material copper|copper_smith|phong|...]
//                            [--resolution N] [--threads T] [--repeat R] [--check TEXELS]
//                            [--brute-force] [--cycles SAMPLES,...] [--write DIR]
//
// The error is docs/accuracy.md's, relative to the peak: texels of the map (or of Cycles' render)
// against the brute-force sum at `--check` texels drawn uniformly over the visible disc (fully covered
// texels), as the RMS and the largest, and value-weighted (texels drawn in proportion to the brute
// force's value). --brute-force times the brute force over the whole map (estimated from the
// checked texels). The sky is SkyEnvironment (a 1.5-degree sun of radiance ~2000) at ROWS rows.
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/material_under_environment.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/maps/sphere_map.hpp>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <string>

#include "matcap_cycles.hpp"

namespace brdfbake {
namespace {

using Clock = std::chrono::steady_clock;

// Copper as engines give it: Schlick with F0 = (0.955, 0.638, 0.538) (Filament's copper), GGX
// alpha 0.3, lighting mode.
std::shared_ptr<const Material> copper(MicrofacetShadowing shadowing) {
  CookTorranceParams p;
  p.mode = CookTorranceMode::Lighting;
  p.distribution = MicrofacetDistribution::Ggx;
  p.roughness = 0.3;
  p.fresnel = FresnelTerm::schlick(Rgb(0.955, 0.638, 0.538));
  p.shadowing = shadowing;
  return std::make_shared<CookTorranceMaterial>(p);
}

std::shared_ptr<const Material> materialNamed(const std::string& name) {
  if (name == "copper") return copper(MicrofacetShadowing::SmithSeparable);
  if (name == "copper_vcavity") return copper(MicrofacetShadowing::VCavity);
  if (name.rfind("copper:", 0) == 0) {  // copper:ROUGHNESS
    auto m = copper(MicrofacetShadowing::SmithSeparable);
    CookTorranceParams p = static_cast<const CookTorranceMaterial&>(*m).params();
    p.roughness = std::stod(name.substr(7));
    return std::make_shared<CookTorranceMaterial>(p);
  }
  if (name.rfind("phong:", 0) == 0)
    return std::make_shared<PhongMaterial>(Rgb(0.5, 0.5, 0.5), std::stod(name.substr(6)), Rgb(0.4, 0.1, 0.1));
  if (name == "cycles_copper") return cyclesPrincipledMetal(Rgb(0.955, 0.638, 0.538), 0.3);
  if (name == "phong") return std::make_shared<PhongMaterial>(Rgb(0.5, 0.5, 0.5), 200.0, Rgb(0.4, 0.1, 0.1));
  throw Error(Error::Kind::InvalidArgument, "unknown material " + name);
}

// The plain brute force: every texel of the environment, its centre, k shade(g, l) L Ω.
Rgb bruteForce(const Environment& environment, const Material& material, const Vec3& normal) {
  const Parameterization& map = *environment.map;
  const Vec3 v = Vec3::UnitZ();
  const ShadingGeometry g{normal, v, reflect(v, normal)};
  Rgb sum = Rgb::Zero();
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) {
      const double omega = map.texelSolidAngle(x, y);
      if (!(omega > 0.0)) continue;
      sum += material.shade(g, *map.getDirectionFor(Vec2(x + 0.5, y + 0.5))) * environment.image.at(x, y).head<3>() *
             omega;
    }
  return sum * material.lightColorPerIrradiance();
}

struct CheckTexel {
  int x = 0, y = 0;
  Vec3 normal;
  Rgb reference = Rgb::Zero();
  bool valueWeighted = false;
  double weight = 1.0;
};

// `count` texels fully inside the disc, uniform; then as many drawn in proportion to a first
// estimate of the value (the map itself), each weighted by v / q.
std::vector<CheckTexel> checkTexels(const Image& map, int count, unsigned seed) {
  const int n = map.width();
  std::vector<std::pair<int, int>> inside;
  std::vector<double> cdf{0.0};
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      if (map.at(x, y)[3] < 1.0) continue;
      inside.emplace_back(x, y);
      cdf.push_back(cdf.back() + map.at(x, y).head<3>().maxCoeff() + 1e-3);
    }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<CheckTexel> out;
  auto add = [&](std::size_t k, bool weighted) {
    const auto [x, y] = inside[k];
    const double sx = 2.0 * (x + 0.5) / n - 1.0, sy = 1.0 - 2.0 * (y + 0.5) / n;
    CheckTexel t;
    t.x = x, t.y = y, t.normal = Vec3(sx, sy, std::sqrt(std::max(0.0, 1.0 - sx * sx - sy * sy)));
    t.valueWeighted = weighted;
    if (weighted) t.weight = cdf.back() / (cdf[k + 1] - cdf[k]);  // 1 / q, q the texel's probability x count
    out.push_back(t);
  };
  for (int i = 0; i < count; ++i) add(static_cast<std::size_t>(unit(rng) * inside.size()) % inside.size(), false);
  for (int i = 0; i < count; ++i) {
    const double u = unit(rng) * cdf.back();
    add(std::min<std::size_t>(inside.size() - 1, std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin() - 1), true);
  }
  return out;
}

struct Errors {
  double rms = 0.0, max = 0.0, highlight = 0.0, peak = 0.0;
};
Errors errorsOf(const Image& image, const std::vector<CheckTexel>& texels) {
  Errors e;
  for (const auto& t : texels) e.peak = std::max(e.peak, t.reference.abs().maxCoeff());
  double uniform = 0.0, count = 0.0, weighted = 0.0, weights = 0.0;
  for (const auto& t : texels) {
    const double e2 = (image.at(t.x, t.y).head<3>() - t.reference).square().sum() / 3.0;
    e.max = std::max(e.max, std::sqrt(e2));
    if (t.valueWeighted) {
      const double v = t.reference.abs().maxCoeff() * t.weight;
      weighted += v * e2, weights += v;
    } else {
      uniform += e2, count += 1.0;
    }
  }
  e.rms = std::sqrt(uniform / count) / e.peak;
  e.highlight = std::sqrt(weighted / weights) / e.peak;
  e.max /= e.peak;
  return e;
}

std::string percent(double x) {
  std::ostringstream out;
  out.precision(3);
  out << 100.0 * x << " %";
  return out.str();
}

struct CyclesInputs {
  const Environment& environment;
  const Image& matcap;
  const std::vector<CheckTexel>& texels;  // with the brute force of the bench's material
  double seconds;                         // the matcap's median time
  Errors errors;                          // the matcap's against its brute force
  int threads;
};

double interpolateLogLog(const std::vector<std::pair<double, double>>& errorSeconds, double error) {
  // Seconds at `error` on the curve through (error, seconds) points, linear in log-log, extrapolated.
  auto sorted = errorSeconds;
  std::sort(sorted.begin(), sorted.end());
  std::size_t i = 1;
  while (i + 1 < sorted.size() && sorted[i].first < error) ++i;
  const auto [e0, t0] = sorted[i - 1];
  const auto [e1, t1] = sorted[i];
  const double slope = std::log(t1 / t0) / std::log(e1 / e0);
  return t0 * std::exp(slope * std::log(error / e0));
}

// Renders the sphere with Cycles at each sample count: its error against the brute force of Cycles'
// own BSDF (cyclesPrincipledMetal) at the checked texels, its time, the seconds Cycles needs for the
// matcap's error (log-log interpolation) and the matcap's agreement with the render of most samples.
void compareWithCycles(const CyclesInputs& in, const std::string& counts, const std::filesystem::path& work) {
  const Rgb copperF0(0.955, 0.638, 0.538);
  const auto cycles = cyclesPrincipledMetal(copperF0, 0.3);
  std::filesystem::create_directories(work);
  Image plain = in.environment.image;
  plain.metadata = nlohmann::json::object();
  writeImage(plain, work / "environment.exr");
  std::vector<CheckTexel> texels = in.texels;
  tbb::parallel_for(std::size_t(0), texels.size(), [&](std::size_t i) {
    texels[i].reference = bruteForce(in.environment, *cycles, texels[i].normal);
  });
  std::vector<std::pair<double, double>> curve;
  std::optional<CyclesRender> best;
  std::stringstream list(counts);
  for (std::string item; std::getline(list, item, ',');) {
    std::string message;
    const int samples = std::stoi(item);
    auto render = renderWithCycles(work / "environment.exr", copperF0, 0.3, in.matcap.width(), samples, in.threads,
                                   work, message);
    if (!render) {
      std::cout << "Cycles: " << message << "\n";
      return;
    }
    const Errors e = errorsOf(render->image, texels);
    std::cout << "Cycles " << samples << " samples: render " << render->seconds << " s (blender " << render->wallSeconds
              << " s); against the brute force of its BSDF: RMS " << percent(e.rms) << ", value-weighted "
              << percent(e.highlight) << ", max " << percent(e.max) << "\n";
    curve.emplace_back(std::max(e.rms, e.highlight), render->seconds);
    best = std::move(render);
  }
  const double ours = std::max(in.errors.rms, in.errors.highlight);
  if (curve.size() >= 2) {
    const double cyclesSeconds = interpolateLogLog(curve, ours);
    std::cout << "at the matcap's error " << percent(ours) << ": Cycles about " << cyclesSeconds << " s, the matcap "
              << in.seconds << " s: " << cyclesSeconds / in.seconds << "x\n";
  }
  // The matcap against the render of most samples, over the pixels both cover fully.
  double peak = 0.0, sum = 0.0, worst = 0.0, count = 0.0;
  for (int y = 0; y < in.matcap.height(); ++y)
    for (int x = 0; x < in.matcap.width(); ++x)
      if (in.matcap.at(x, y)[3] >= 1.0 && best->image.at(x, y)[3] >= 1.0)
        peak = std::max(peak, in.matcap.at(x, y).head<3>().maxCoeff());
  for (int y = 0; y < in.matcap.height(); ++y)
    for (int x = 0; x < in.matcap.width(); ++x) {
      if (in.matcap.at(x, y)[3] < 1.0 || best->image.at(x, y)[3] < 1.0) continue;
      const double e2 = (in.matcap.at(x, y).head<3>() - best->image.at(x, y).head<3>()).square().sum() / 3.0;
      sum += e2, count += 1.0, worst = std::max(worst, std::sqrt(e2));
    }
  std::cout << "the matcap against Cycles' render of most samples, over " << count << " pixels: RMS "
            << percent(std::sqrt(sum / count) / peak) << ", max " << percent(worst / peak) << " of the peak " << peak
            << "\n";
}

int run(int argc, char** argv) {
  std::map<std::string, std::string> args{{"--sky", "512"},   {"--material", "copper"}, {"--resolution", "512"},
                                          {"--threads", "2"}, {"--repeat", "3"},        {"--check", "200"}};
  for (int i = 1; i + 1 < argc; i += 2) args[argv[i]] = argv[i + 1];
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--brute-force") args["--brute-force"] = "1";
  const int threads = std::stoi(args["--threads"]);
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  Environment environment =
      args.count("--environment")
          ? loadEnvironment(args["--environment"])
          : bakeEnvironment(SkyEnvironment(), ParameterizationKind::LatLong, std::stoi(args["--sky"]), "sky", 64);
  const auto material = materialNamed(args["--material"]);
  UnderEnvironmentOptions options;
  options.resolution = std::stoi(args["--resolution"]);
  const Context context({.threads = threads});
  if (args.count("--samples"))
    options.method = UnderEnvironmentMethod::Sampled, options.importanceSamples = std::stoi(args["--samples"]);
  if (args.count("--grid"))
    options.method = UnderEnvironmentMethod::Sampled, options.gridPerWidth = std::stoi(args["--grid"]);
  if (args.count("--max-error")) options.maxError = std::stod(args["--max-error"]);
  std::cout << "environment " << environment.image.width() << " x " << environment.image.height() << ", material "
            << args["--material"] << ", sphere map " << options.resolution << ", " << threads << " threads\n";
  MaterialUnderEnvironment result;
  std::vector<double> seconds;
  for (int r = 0; r < std::stoi(args["--repeat"]); ++r) {
    const auto start = Clock::now();
    result = shadeUnderEnvironment(environment, *material, options, context);
    seconds.push_back(secondsSince(start));
  }
  std::sort(seconds.begin(), seconds.end());
  std::cout << "shadeUnderEnvironment: median " << seconds[seconds.size() / 2] << " s (" << seconds.front() << " to "
            << seconds.back() << ")\n  " << result.summary.briefReport() << "\n  setup " << result.summary.setupSeconds
            << " s, estimate " << result.summary.estimateSeconds << " s, output " << result.summary.outputSeconds
            << " s, bright texels " << result.summary.brightTexels << " (threshold " << result.summary.brightThreshold
            << ", share " << result.summary.brightShare << ")\n";
  for (const auto& c : result.summary.candidates)
    std::cout << "    " << (c.chosen ? "* " : "  ") << c.detail << ": predicted " << c.predictedSeconds << " s, "
              << c.seconds << " s, estimate " << percent(c.errorEstimate) << "\n";
  for (const auto& note : result.summary.notes) std::cout << "  note: " << note << "\n";

  auto texels = checkTexels(result.image, std::stoi(args["--check"]), 7);
  const auto bruteStart = Clock::now();
  tbb::parallel_for(std::size_t(0), texels.size(),
                    [&](std::size_t i) { texels[i].reference = bruteForce(environment, *material, texels[i].normal); });
  const double bruteSeconds = secondsSince(bruteStart);
  const Errors e = errorsOf(result.image, texels);
  std::cout << "against the brute force at " << texels.size() << " texel centres: RMS " << percent(e.rms)
            << ", value-weighted " << percent(e.highlight) << ", max " << percent(e.max) << " of the peak " << e.peak
            << "\n";
  const double inside = kPi / 4 * options.resolution * options.resolution;
  std::cout << "brute force: " << bruteSeconds / texels.size() * threads * 1e3 << " ms per texel on one core, "
            << bruteSeconds / texels.size() * inside / 60.0 << " min for the " << options.resolution
            << "^2 map's disc on " << threads << " threads\n";
  if (args.count("--write")) {
    const std::filesystem::path dir = args["--write"];
    writeImage(result.image, dir / ("matcap_" + args["--material"] + ".exr"));
  }
  if (args.count("--cycles")) {
    CyclesInputs in{environment, result.image, texels, seconds[seconds.size() / 2], e, threads};
    compareWithCycles(in, args["--cycles"], args.count("--write") ? args["--write"] : "cycles_work");
  }
  return 0;
}

}  // namespace
}  // namespace brdfbake

int main(int argc, char** argv) {
  try {
    return brdfbake::run(argc, argv);
  } catch (const brdfbake::Error& e) {
    std::cerr << "matcap_bench: " << e.what() << "\n";
    return 1;
  }
}
