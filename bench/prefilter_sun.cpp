// Is a prefiltered map's error estimate honest near a sun? (docs/prefilter.md, "Near a sun"; issue 22)
//
//   build/bench/prefilter_sun [--rows 1024] [--sun-radius 0.75] [--lobe ggx:0.134] [--to cube]
//                             [--resolution 256] [--directions 30] [--threads 2]
//
// The sky of SkyEnvironment with a hard sun (a disc of `--sun-radius` degrees, radiance 2000) as a
// 2 ROWS x ROWS lat-long image, prefiltered by `prefilter` (auto, 1 %); then bilinear lookups of the
// map at `--directions` directions uniform on the sphere and as many uniform within 5 degrees of the
// sun, each against the reference sum over every input texel (prefilterReferenceAt), as the relative
// error |a - r| / max(|r|, delta) of docs/prefilter.md: the RMS and largest of each set, next to what
// the map reports.
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/env/env_accuracy.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter.hpp>

#include <iostream>
#include <map>
#include <random>
#include <string>

namespace brdfbake {
namespace {

int run(int argc, char** argv) {
  std::map<std::string, std::string> args{{"--rows", "1024"}, {"--sun-radius", "0.75"}, {"--lobe", "ggx:0.134"},
                                          {"--to", "cube"},   {"--resolution", "256"},  {"--directions", "30"},
                                          {"--threads", "2"}};
  for (int i = 1; i + 1 < argc; i += 2) args[argv[i]] = argv[i + 1];
  SkyParameters sky;
  sky.sunAngularRadius = radians(std::stod(args["--sun-radius"]));
  sky.sunRadiance = Rgb::Constant(2000.0);
  const int threads = std::stoi(args["--threads"]);
  const Environment environment = bakeEnvironment(SkyEnvironment(sky), ParameterizationKind::LatLong,
                                                  std::stoi(args["--rows"]), "sky", 16, Context({.threads = threads}));
  const PrefilterLobe lobe = PrefilterLobe::parse(args["--lobe"]);
  PrefilterOptions options;
  options.parameterization = parseParameterizationKind(args["--to"]);
  options.resolution = std::stoi(args["--resolution"]);
  const auto start = std::chrono::steady_clock::now();
  const PrefilteredMap map = prefilter(environment, lobe, options, Context({.threads = threads}));
  std::cout << "environment " << environment.image.width() << " x " << environment.image.height() << ", sun "
            << args["--sun-radius"] << " degrees; " << lobe.name() << " into " << args["--to"] << " "
            << options.resolution << ": " << secondsSince(start) << " s\n  " << map.summary.briefReport() << "\n";
  if (args.count("--candidates")) {
    for (const auto& c : map.summary.candidates)
      std::cout << "    " << (c.chosen ? "* " : "  ") << c.detail << ": " << c.seconds << " s, estimate "
                << 100.0 * c.errorEstimate << " % (RMS " << 100.0 * c.errorEstimateRms << " %, highlight "
                << 100.0 * c.errorEstimateHighlight << " %, " << c.probes << " probes)\n";
    std::cout << "    estimate " << map.summary.estimateSeconds << " s, output " << map.summary.outputSeconds << " s\n";
  }

  const int count = std::stoi(args["--directions"]);
  std::mt19937 rng(5);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3> random, nearSun;
  while (static_cast<int>(random.size()) < count) {
    const Vec3 d(gauss(rng), gauss(rng), gauss(rng));
    if (d.norm() > 1e-9) random.push_back(d.normalized());
  }
  const Vec3 s = sky.sunDirection.normalized(), t = anyPerpendicular(s), b = s.cross(t);
  while (static_cast<int>(nearSun.size()) < count) {  // uniform in the cap of 5 degrees
    const double c = 1.0 - unit(rng) * (1.0 - std::cos(radians(5.0))), phi = kTwoPi * unit(rng);
    const double sn = std::sqrt(1.0 - c * c);
    nearSun.push_back((sn * (std::cos(phi) * t + std::sin(phi) * b) + c * s).normalized());
  }
  const double floor = prefilterErrorFloor(environment, lobe);
  for (const auto& [name, directions] :
       {std::pair{"random", random}, std::pair{"within 5 degrees of the sun", nearSun}}) {
    std::vector<Vec3> axes;
    for (const Vec3& d : directions) axes.push_back(prefilterAxis(d, lobe, options));
    const auto reference = prefilterReferenceAt(environment, lobe, axes, Context({.threads = threads}));
    std::vector<Rgb> looked;
    for (const Vec3& d : directions) looked.push_back(sampleBilinear(map.levels[0], *map.map, d).head<3>());
    const PrefilterError e =
        prefilterPointsError(looked, reference, std::vector<double>(directions.size(), 1.0), floor);
    std::cout << "  " << directions.size() << " directions " << name << ": RMS " << 100.0 * e.rms << " %, max "
              << 100.0 * e.max << " %\n";
  }
  return 0;
}

}  // namespace
}  // namespace brdfbake

int main(int argc, char** argv) {
  try {
    return brdfbake::run(argc, argv);
  } catch (const brdfbake::Error& e) {
    std::cerr << "prefilter_sun: " << e.what() << "\n";
    return 1;
  }
}
