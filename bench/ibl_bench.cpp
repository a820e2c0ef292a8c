// The GGX roughness chain of `brdfbake ibl` next to Filament's cmgen (Debian libfilament-tools), on
// cmgen's own job and on brdfbake's.
//
//   build/bench/ibl_bench [--quick] [--threads N] [--subset N] [--no-cmgen]
//
// Environment: the generated sky (SkyEnvironment: sky, aureole, ground, a 1.5 degree sun of radiance
// ~2000) as a 1024 x 512 lat-long image (256 x 128 with --quick), written as a 3-channel float EXR for
// cmgen. Faces of 256^2 (64^2 with --quick).
//
// 1. cmgen's job: `cmgen --no-mirror -s 256 -f exr --ibl-ld=DIR sky.exr` makes its levels (Debian's 1.9.25:
//    5 levels, perceptual roughness 0, 0.134, 0.293, 0.5, 1, read from what it prints), then brdfbake makes
//    the same levels (prefilterGlossChain with those roughnesses, `auto` to 1 %, no edge fixup).
// 2. brdfbake's own job: the whole chain down to 1 texel, R_k = k / (L - 1) (ggxChainLobes), as `ibl`
//    makes it.
// Each is timed (wall clock, one run) and each level k >= 1 compared with the reference sum
// (prefilterReferenceAt) at --subset random texels (default 256) at the tool's own texel centres: RMS and
// largest relative error (solid-angle weighted, docs/prefilter.md). Level 0 is the environment resampled
// by both and not compared. cmgen's face F holds the OpenGL face F of the frame (x, y, -z)
// (bench/prefilter_bench.cpp found it with a direction-coded environment).
#include <brdfbake/core/error.hpp>
#include <brdfbake/env/env_accuracy.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/env/prefilter_stack.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/maps/cube_map.hpp>

#include <OpenImageIO/imageio.h>

#include <unistd.h>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>
#include <regex>
#include <sstream>

#include "bench_support.hpp"

namespace {
using namespace brdfbake;
namespace fs = std::filesystem;
using bench::Clock;
using bench::cmgenDirection;
using bench::haveProgram;
using bench::since;
using bench::writeFloatRgbExr;

std::string percent(double value) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(2) << 100.0 * value << " %";
  return out.str();
}

// A texel of one face of a cube level: face, x, y.
struct Texel {
  int face, x, y;
};

std::vector<Texel> randomTexels(int size, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<Texel> texels;
  for (int i = 0; i < count; ++i)
    texels.push_back({static_cast<int>(rng() % 6), static_cast<int>(rng() % size), static_cast<int>(rng() % size)});
  return texels;
}

// The error of `values` at `axes` against the reference sum of `lobe` there.
PrefilterError levelError(const Environment& sky, const PrefilterLobe& lobe, const std::vector<Vec3>& axes,
                          const std::vector<Rgb>& values, const std::vector<double>& weights, int threads) {
  return prefilterPointsError(values, prefilterReferenceAt(sky, lobe, axes, Context({.threads = threads})), weights,
                              prefilterErrorFloor(sky, lobe));
}

struct ChainRun {
  std::string tool;
  double seconds = 0.0;
  std::vector<double> roughness;
  std::vector<PrefilterError> errors;  // per level; level 0 not compared
};

// brdfbake's chain of `roughness` (level 0 the mirror) at `faceSize`, timed and compared.
ChainRun brdfbakeChain(const Environment& sky, const std::vector<double>& roughness, int faceSize, int subset,
                       int threads) {
  std::vector<PrefilterLobe> lobes;
  for (double r : roughness) lobes.push_back(r == 0.0 ? PrefilterLobe::mirror() : PrefilterLobe::ggx(r));
  PrefilterOptions options;
  options.parameterization = ParameterizationKind::Cube;
  options.resolution = faceSize;
  options.cubeEdgeFixup = false;
  const auto start = Clock::now();
  const PrefilteredMap chain = prefilterGlossChain(sky, lobes, options, Context({.threads = threads}));
  ChainRun run{"brdfbake", since(start), roughness, {PrefilterError{}}};
  for (std::size_t k = 1; k < lobes.size(); ++k) {
    const int size = std::max(1, faceSize >> k);
    const CubeMap cube(size);
    std::vector<Vec3> axes;
    std::vector<Rgb> values;
    std::vector<double> weights;
    for (const Texel& t : randomTexels(size, subset, 17 + static_cast<unsigned>(k))) {
      const TexelRect r = cube.region(t.face);
      axes.push_back(*cube.getDirectionFor(Vec2(r.x0 + t.x + 0.5, r.y0 + t.y + 0.5)));
      values.push_back(chain.levels[k].at(r.x0 + t.x, r.y0 + t.y).head<3>());
      weights.push_back(cube.texelSolidAngle(r.x0 + t.x, r.y0 + t.y));
    }
    run.errors.push_back(levelError(sky, lobes[k], axes, values, weights, threads));
  }
  return run;
}

// cmgen --ibl-ld on `input`, timed; the roughness of each level from what it prints.
ChainRun cmgenChain(const Environment& sky, const fs::path& input, const fs::path& work, int faceSize, int subset,
                    int threads) {
  const fs::path out = work / "cmgen", log = work / "cmgen.log";
  std::ostringstream line;
  line << "cmgen --no-mirror -s " << faceSize << " -f exr --ibl-ld=" << out.string() << " " << input.string() << " > "
       << log.string() << " 2>&1";
  const std::string command = line.str();
  const auto start = Clock::now();
  const int status = std::system(command.c_str());
  ChainRun run{"cmgen", since(start), {}, {PrefilterError{}}};
  if (status != 0) throw Error(Error::Kind::Io, "cmgen failed: " + command);
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::regex level(R"(Level (\d+), roughness = [0-9.e-]+, roughness \(perceptual\) = ([0-9.e-]+))");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), level); it != std::sregex_iterator(); ++it)
    run.roughness.push_back(std::stod((*it)[2]));
  if (run.roughness.empty()) throw Error(Error::Kind::Io, "cmgen printed no levels: " + log.string());
  static const char* names[6] = {"px", "nx", "py", "ny", "pz", "nz"};
  const CubeMap unit(1);
  for (std::size_t k = 1; k < run.roughness.size(); ++k) {
    const int size = std::max(1, faceSize >> k);
    std::vector<Image> faces;
    for (const char* name : names)
      faces.push_back(readImage(out / input.stem() / ("m" + std::to_string(k) + "_" + name + ".exr")));
    const CubeMap cube(size);
    std::vector<Vec3> axes;
    std::vector<Rgb> values;
    std::vector<double> weights;
    for (const Texel& t : randomTexels(size, subset, 29 + static_cast<unsigned>(k))) {
      axes.push_back(cmgenDirection(t.face, t.x, t.y, size));
      values.push_back(faces[static_cast<std::size_t>(t.face)].at(t.x, t.y).head<3>());
      const TexelRect r = cube.region(0);
      weights.push_back(cube.texelSolidAngle(r.x0 + t.x, r.y0 + t.y));
    }
    run.errors.push_back(levelError(sky, PrefilterLobe::ggx(run.roughness[k]), axes, values, weights, threads));
  }
  return run;
}

void printRuns(const std::string& job, const std::vector<ChainRun>& runs) {
  std::cout << "\n"
            << job << "\n\n| tool | seconds | worst level RMS | per level RMS (max), k >= 1 |\n|---|---:|---:|---|\n";
  for (const ChainRun& run : runs) {
    double worst = 0.0;
    std::ostringstream levels;
    for (std::size_t k = 1; k < run.errors.size(); ++k) {
      worst = std::max(worst, run.errors[k].rms);
      levels << (k > 1 ? ", " : "") << "R " << std::setprecision(3) << run.roughness[k] << ": "
             << percent(run.errors[k].rms) << " (" << percent(run.errors[k].max) << ")";
    }
    std::cout << "| " << run.tool << " | " << std::setprecision(3) << run.seconds << " | " << percent(worst) << " | "
              << levels.str() << " |\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, useCmgen = true;
  int threads = 0, subset = 256;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick")
      quick = true;
    else if (a == "--no-cmgen")
      useCmgen = false;
    else if (a == "--threads" && i + 1 < argc)
      threads = std::stoi(argv[++i]);
    else if (a == "--subset" && i + 1 < argc)
      subset = std::stoi(argv[++i]);
    else {
      std::cerr << "usage: ibl_bench [--quick] [--threads N] [--subset N] [--no-cmgen]\n";
      return 2;
    }
  }
  try {
    const int rows = quick ? 128 : 512, faceSize = quick ? 64 : 256;
    const Environment sky = bakeEnvironment(SkyEnvironment(), ParameterizationKind::LatLong, rows, "sky", 16,
                                            Context({.threads = threads}));
    const fs::path work = fs::temp_directory_path() / ("brdfbake-ibl-bench-" + std::to_string(::getpid()));
    fs::create_directories(work);
    if (useCmgen && !haveProgram("cmgen")) {
      std::cerr << "cmgen not found (Debian: apt-get install libfilament-tools): brdfbake alone\n";
      useCmgen = false;
    }
    if (useCmgen) {
      const fs::path input = work / "sky.exr";
      writeFloatRgbExr(sky, input);
      std::cerr << "cmgen's job ...\n";
      const ChainRun cmgen = cmgenChain(sky, input, work, faceSize, subset, threads);
      const ChainRun ours = brdfbakeChain(sky, cmgen.roughness, faceSize, subset, threads);
      std::ostringstream job;
      job << "cmgen's job: " << cmgen.roughness.size() << " levels from " << faceSize
          << "^2 faces at cmgen's roughness";
      printRuns(job.str(), {cmgen, ours});
    }
    std::cerr << "brdfbake's job ...\n";
    const int levels = static_cast<int>(std::log2(faceSize)) + 1;
    std::ostringstream job;
    job << "brdfbake ibl's job: " << levels << " levels from " << faceSize << "^2 faces, R_k = k / (L - 1)";
    printRuns(job.str(), {brdfbakeChain(sky, ggxChainRoughness(levels), faceSize, subset, threads)});
    std::error_code ec;
    fs::remove_all(work, ec);
  } catch (const Error& e) {
    std::cerr << "ibl_bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
