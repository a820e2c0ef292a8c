// Prefiltering speed against accuracy (issue 5's bar), and brdfbake's GGX path next to Filament's
// cmgen where it is installed.
//
//   build/bench/prefilter_bench [--quick] [--threads N] [--subset N] [--chart FILE.png] [--no-cmgen] [--cmft DIR]
//   [--chain-only]
//
// Environment: the generated sky (SkyEnvironment: sky, aureole, ground, a 1.5 degree sun of
// radiance ~2000) as a 1024 x 512 lat-long image (256 x 128 with --quick). For normalised Phong
// exponents 1, 10, 100, 1000, into a 256^2-per-hemisphere paraboloid map and a 256^2 sphere map,
// every method at several settings makes the whole map (timed, wall clock) and is compared with
// the reference on a random subset of output texels (--subset, default 256; prefilterTexelSubset
// and prefilterPointsError of env_accuracy.hpp, which `brdfbake chart` shares): the reference over
// all 131 072 (paraboloid) or 65 536 (sphere) texels would take minutes to hours, so its time is
// the subset's time scaled to the whole map. Error: RMS relative error per texel (weighted by
// the texels' solid angles) and its maximum, as docs/prefilter.md defines them.
//
// GGX: roughness 0.25 and 0.5 into 256^2 cube faces by brdfbake (auto, importance 1024) and by
// `cmgen --extract-blur=R -s 256 --no-mirror` (Filament's roughnessFilter, 1024 samples, fed the
// same environment as a 3-channel float EXR), each compared with brdfbake's reference at its own
// texel centres. cmgen's faces are the OpenGL faces of the frame (x, y, -z) (found by feeding it a
// direction-coded environment; see docs/prefilter.md). Skipped with a message if cmgen is absent.
//
// Gloss chain (--cmft DIR: a checkout of github.com/dariomanesku/cmft, or $CMFT_SOURCE; --chain-only runs this
// section alone): cmft's Phong chain (--glossScale 10 --glossBias 1 --mipCount 8, 256^2 faces, no edge fixup)
// by prefilterGlossChain and by cmft, which the bench builds with g++ in a temporary folder (never vendored;
// skipped with a message without the checkout or g++) and runs on the CPU with N - 1 = `--threads` workers;
// wall and CPU seconds (getrusage), and per level the RMS relative error against the reference sum at
// --subset random texels (cmft's texel centres, mapped to brdfbake's frame by negating z).
//
// The chart (gnuplot, time against error per exponent and for GGX) goes to
// docs/images/prefilter_speed_error.png unless --chart says otherwise; a markdown table of every
// point goes to stdout.
#include <brdfbake/core/error.hpp>
#include <brdfbake/env/env_accuracy.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/env/prefilter_stack.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/maps/cube_map.hpp>

#include <OpenImageIO/imageio.h>

#include <sys/resource.h>
#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <random>
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

struct Row {
  std::string group;   // "phong:100 paraboloid", "ggx:0.5 cube"
  std::string tool;    // "brdfbake" or "cmgen"
  std::string method;  // reference, auto, sh, direct, importance, cmgen
  std::string detail;
  double seconds = 0.0, rms = 0.0, max = 0.0, estimate = -1.0;
  bool extrapolated = false;
};

std::string format(double value, int precision = 3) {
  std::ostringstream out;
  out << std::setprecision(precision) << value;
  return out.str();
}

// The whole map by one configuration, timed, compared on the subset.
Row run(const Environment& environment, const PrefilterLobe& lobe, PrefilterOptions options,
        const PrefilterCheckPoints& subset, const std::vector<Rgb>& reference, double floor, const std::string& group,
        int threads) {
  const auto start = Clock::now();
  const PrefilteredMap map = prefilter(environment, lobe, options, Context({.threads = threads}));
  Row row;
  row.seconds = since(start);
  row.group = group;
  row.tool = "brdfbake";
  row.method = options.method == PrefilterMethod::Auto ? "auto" : std::string(toString(map.summary.method));
  row.detail = map.summary.detail;
  if (options.method == PrefilterMethod::Auto)
    row.detail = std::string(toString(map.summary.method)) + ": " + row.detail;
  if (map.summary.errorEstimated) row.estimate = map.summary.errorEstimate;
  const PrefilterError error =
      prefilterPointsError(prefilterValuesAt(map.levels[0], *map.map, subset), reference, subset.weights, floor);
  row.rms = error.rms;
  row.max = error.max;
  return row;
}

void ggxComparison(const Environment& environment, int faceSize, int subsetSize, int threads, bool useCmgen,
                   std::vector<Row>& rows) {
  const fs::path work = fs::temp_directory_path() / ("brdfbake-prefilter-bench-" + std::to_string(::getpid()));
  fs::create_directories(work);
  const fs::path input = work / "sky.exr";
  writeFloatRgbExr(environment, input);
  const CubeMap cube(faceSize);
  for (double roughness : {0.25, 0.5}) {
    const PrefilterLobe lobe = PrefilterLobe::ggx(roughness);
    const std::string group = lobe.name() + " cube";
    const double floor = prefilterErrorFloor(environment, lobe);
    PrefilterOptions options;
    options.parameterization = ParameterizationKind::Cube;
    options.resolution = faceSize;
    const PrefilterCheckPoints subset = prefilterTexelSubset(cube, lobe, options, subsetSize, 11);
    auto referenceStart = Clock::now();
    const auto reference = prefilterReferenceAt(environment, lobe, subset.axes, Context({.threads = threads}));
    Row ref;
    ref.group = group, ref.tool = "brdfbake", ref.method = "reference", ref.extrapolated = true;
    ref.seconds = since(referenceStart) * 6.0 * faceSize * faceSize / subset.axes.size();
    rows.push_back(ref);
    rows.push_back(run(environment, lobe, options, subset, reference, floor, group, threads));
    for (int samples : {256, 1024}) {
      PrefilterOptions o = options;
      o.method = PrefilterMethod::Importance;
      o.importanceSamples = samples;
      o.estimateError = false;
      o.interpolate = false;
      rows.push_back(run(environment, lobe, o, subset, reference, floor, group, threads));
    }
    for (double q : {2.0, 4.0}) {
      PrefilterOptions o = options;
      o.method = PrefilterMethod::Direct;
      o.directTexelsPerWidth = q;
      o.estimateError = false;
      o.interpolate = false;
      rows.push_back(run(environment, lobe, o, subset, reference, floor, group, threads));
    }
    if (!useCmgen) continue;
    const fs::path out = work / ("cmgen_" + format(roughness));
    fs::create_directories(out);
    const std::string command = "cmgen --quiet --no-mirror -s " + std::to_string(faceSize) +
                                " -f exr --extract=" + out.string() + " --extract-blur=" + format(roughness) + " " +
                                input.string() + " > /dev/null 2>&1";
    const auto start = Clock::now();
    const int status = std::system(command.c_str());
    const double seconds = since(start);
    if (status != 0) {
      std::cerr << "cmgen failed (" << status << "): " << command << "\n";
      continue;
    }
    // Faces px nx py ny pz nz in a folder named after the input.
    static const char* names[6] = {"px", "nx", "py", "ny", "pz", "nz"};
    std::vector<Image> faces;
    for (const char* name : names) faces.push_back(readImage(out / "sky" / (std::string(name) + ".exr")));
    std::mt19937 rng(11);
    std::vector<Vec3> axes;
    std::vector<Rgb> values;
    std::vector<double> weights;
    while (static_cast<int>(axes.size()) < subsetSize) {
      const int f = static_cast<int>(rng() % 6), x = static_cast<int>(rng() % faceSize),
                y = static_cast<int>(rng() % faceSize);
      axes.push_back(cmgenDirection(f, x, y, faceSize));
      values.push_back(faces[f].at(x, y).head<3>());
      const TexelRect r = cube.region(f);
      weights.push_back(cube.texelSolidAngle(r.x0 + x, r.y0 + y));
    }
    const auto cmgenReference = prefilterReferenceAt(environment, lobe, axes, Context({.threads = threads}));
    Row row;
    row.group = group, row.tool = "cmgen", row.method = "cmgen",
    row.detail = "roughnessFilter, 1024 samples, half-float faces";
    row.seconds = seconds;
    const PrefilterError error = prefilterPointsError(values, cmgenReference, weights, floor);
    row.rms = error.rms;
    row.max = error.max;
    rows.push_back(row);
  }
  std::error_code ec;
  fs::remove_all(work, ec);
}

// ---- the Phong gloss chain next to cmft -------------------------------------------------------

// CPU seconds (user + system) of this process and of its waited-for children.
double cpuSeconds(int who) {
  rusage usage{};
  getrusage(who, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + 1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// cmft's face F texel (x, y) of an n^2 face, in brdfbake's frame: cmft's texelCoordToVec
// (cubemaputils.h, s_faceUvVectors) gives (u, v, face) -> direction in cmft's frame, whose lat-long
// reading (latLongFromVec: u = (pi + atan2(x, z)) / 2pi, v = acos(y) / pi) is brdfbake's with z
// negated (latlong_map.cpp: the image centre looks down -z in brdfbake, +z in cmft).
Vec3 cmftDirection(int face, int x, int y, int n) {
  static const double uv[6][3][3] = {{{0, 0, -1}, {0, -1, 0}, {1, 0, 0}}, {{0, 0, 1}, {0, -1, 0}, {-1, 0, 0}},
                                     {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}},   {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}},
                                     {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}},  {{-1, 0, 0}, {0, -1, 0}, {0, 0, -1}}};
  const double u = 2.0 * (x + 0.5) / n - 1.0, v = 2.0 * (y + 0.5) / n - 1.0;
  Vec3 d;
  for (int c = 0; c < 3; ++c) d[c] = uv[face][0][c] * u + uv[face][1][c] * v + uv[face][2][c];
  d.normalize();
  return {d.x(), d.y(), -d.z()};
}

// cmft's RGBA32F DDS cube with mips: the header (and a DX10 header if its four-cc says so), then
// face after face, each with its levels (cmft's imageGetMipOffsets order). faces[f][k] is level k.
std::vector<std::vector<std::vector<float>>> readCmftDds(const fs::path& path, int faceSize, int levels) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 128 || std::string(bytes.data(), 4) != "DDS ")
    throw Error(Error::Kind::Io, path.string() + ": not a DDS file");
  std::size_t offset = 128 + (std::string(bytes.data() + 84, 4) == "DX10" ? 20 : 0);
  std::vector<std::vector<std::vector<float>>> faces(6);
  for (int f = 0; f < 6; ++f)
    for (int k = 0; k < levels; ++k) {
      const int n = std::max(1, faceSize >> k);
      std::vector<float> texels(static_cast<std::size_t>(n) * n * 4);
      const std::size_t size = texels.size() * sizeof(float);
      if (offset + size > bytes.size())
        throw Error(Error::Kind::Io, path.string() + ": shorter than a " + std::to_string(levels) + "-level cube");
      std::memcpy(texels.data(), bytes.data() + offset, size);
      offset += size;
      faces[f].push_back(std::move(texels));
    }
  return faces;
}

// Builds cmft from a source checkout with g++ alone (its own dependency/ folder holds what it
// includes), into `work`. Empty path (and a message) if it cannot.
fs::path buildCmft(const fs::path& source, const fs::path& work) {
  if (source.empty() || !fs::exists(source / "src" / "cmft" / "cubemapfilter.cpp")) {
    std::cerr << "cmft: no source checkout (--cmft DIR, a clone of github.com/dariomanesku/cmft): comparison skipped\n";
    return {};
  }
  if (!haveProgram("g++")) {
    std::cerr << "cmft: g++ not found: comparison skipped\n";
    return {};
  }
  const fs::path binary = work / "cmft";
  const std::string s = source.string();
  const std::string command = "g++ -O3 -std=c++11 -w -I" + s + "/include -I" + s + "/src -I" + s + "/src/cmft -I" + s +
                              "/dependency " + s + "/src/main.cpp " + s + "/src/cmft/*.cpp " + s +
                              "/src/cmft/common/*.cpp -o " + binary.string() + " -lpthread -ldl > " +
                              (work / "cmft_build.log").string() + " 2>&1";
  std::cerr << "building cmft (g++ -O3) ...\n";
  if (std::system(command.c_str()) != 0 || !fs::exists(binary)) {
    std::cerr << "cmft: build failed (" << (work / "cmft_build.log").string() << "): comparison skipped\n";
    return {};
  }
  return binary;
}

struct ChainLevel {
  double exponent = 0.0;
  int size = 0;
  std::vector<Vec3> axes;  // brdfbake frame
  std::vector<double> weights;
  std::vector<Rgb> reference;
  std::vector<std::array<int, 3>> texels;  // face, x, y
};

// Random texels of each level (cmft's face order and texel directions) with the reference sum.
std::vector<ChainLevel> chainCheckPoints(const Environment& environment, const std::vector<double>& exponents,
                                         int faceSize, int count, int threads) {
  std::vector<ChainLevel> levels;
  std::mt19937 rng(13);
  for (std::size_t k = 0; k < exponents.size(); ++k) {
    ChainLevel level;
    level.exponent = exponents[k];
    level.size = std::max(1, faceSize >> k);
    const CubeMap cube(level.size);
    for (int i = 0; i < count; ++i) {
      const int f = static_cast<int>(rng() % 6), x = static_cast<int>(rng() % level.size),
                y = static_cast<int>(rng() % level.size);
      level.texels.push_back({f, x, y});
      level.axes.push_back(cmftDirection(f, x, y, level.size));
      // A cube texel's solid angle depends only on its place in its face.
      const TexelRect r = cube.region(0);
      level.weights.push_back(cube.texelSolidAngle(r.x0 + x, r.y0 + y));
    }
    level.reference = prefilterReferenceAt(environment, PrefilterLobe::phong(level.exponent), level.axes,
                                           Context({.threads = threads}));
    levels.push_back(std::move(level));
  }
  return levels;
}

struct ChainResult {
  std::string tool, detail;
  double seconds = 0.0, cpu = 0.0;
  std::vector<PrefilterError> errors;  // per level
};

// The Phong gloss chain of cmft (--glossScale 10 --glossBias 1 --mipCount 8, 256 faces) made by
// brdfbake (prefilterGlossChain, auto to 1 %) and by cmft on the same 1024 x 512 sky (written as
// Radiance HDR), both compared with the reference sum at random texels of every level.
void cmftComparison(const Environment& environment, const fs::path& cmftSource, int faceSize, int subsetSize,
                    int threads) {
  const int mipCount = 8;
  const auto exponents = glossLevelExponents(mipCount, 10.0, 1.0);
  std::cerr << "gloss chain: reference at " << subsetSize << " texels per level ...\n";
  const auto levels = chainCheckPoints(environment, exponents, faceSize, subsetSize, threads);
  std::vector<ChainResult> results;
  auto errorsOf = [&](const std::function<Rgb(std::size_t level, const std::array<int, 3>& texel)>& value) {
    std::vector<PrefilterError> errors;
    for (std::size_t k = 0; k < levels.size(); ++k) {
      std::vector<Rgb> values;
      for (const auto& t : levels[k].texels) values.push_back(value(k, t));
      errors.push_back(
          prefilterPointsError(values, levels[k].reference, levels[k].weights,
                               prefilterErrorFloor(environment, PrefilterLobe::phong(levels[k].exponent))));
    }
    return errors;
  };
  {
    std::vector<PrefilterLobe> lobes;
    for (double n : exponents) lobes.push_back(PrefilterLobe::phong(n));
    PrefilterOptions options;
    options.parameterization = ParameterizationKind::Cube;
    options.resolution = faceSize;
    options.cubeEdgeFixup = false;  // as cmft's --edgeFixup none: every texel its own value
    const double cpu0 = cpuSeconds(RUSAGE_SELF);
    const auto start = Clock::now();
    const PrefilteredMap chain = prefilterGlossChain(environment, lobes, options, Context({.threads = threads}));
    ChainResult r;
    r.seconds = since(start);
    r.cpu = cpuSeconds(RUSAGE_SELF) - cpu0;
    r.tool = "brdfbake";
    r.detail =
        "prefilterGlossChain, auto to 1 % (largest estimate " + format(100.0 * chain.summary.errorEstimate, 2) + " %)";
    r.errors = errorsOf([&](std::size_t k, const std::array<int, 3>& t) {
      const CubeMap cube(levels[k].size);
      // brdfbake's face holding cmft's texel direction, read at that direction's texel.
      const auto address = cube.getAddressFor(levels[k].axes[&t - levels[k].texels.data()]);
      const int x = std::clamp(static_cast<int>(address.pixel.x()), 0, cube.width() - 1);
      const int y = std::clamp(static_cast<int>(address.pixel.y()), 0, cube.height() - 1);
      return Rgb(chain.levels[k].at(x, y).head<3>());
    });
    results.push_back(r);
    for (const auto& c : chain.summary.candidates)
      std::cerr << "  brdfbake " << (c.chosen ? "chose " : "tried ") << c.detail << ": setup " << format(c.seconds)
                << " s, estimate " << format(100.0 * c.errorEstimate, 2) << " %\n";
    std::cerr << "  brdfbake total " << format(chain.summary.seconds) << " s: probes and estimates "
              << format(chain.summary.estimateSeconds) << " s, output " << format(chain.summary.outputSeconds)
              << " s\n";
  }
  const fs::path work = fs::temp_directory_path() / ("brdfbake-cmft-bench-" + std::to_string(::getpid()));
  fs::create_directories(work);
  if (const fs::path cmft = buildCmft(cmftSource, work); !cmft.empty()) {
    const fs::path input = work / "sky.hdr";
    writeFloatRgbExr(environment, input);  // 3-channel float: Radiance HDR here
    // --numCpuProcessingThreads N runs N - 1 workers: N = threads + 1.
    const int workers = threads > 0 ? threads : 2;
    const std::string command =
        cmft.string() + " --input " + input.string() +
        " --filter radiance --lightingModel phong --mipCount 8 --glossScale 10 --glossBias 1 --srcFaceSize " +
        std::to_string(faceSize) + " --dstFaceSize " + std::to_string(faceSize) +
        " --excludeBase false --edgeFixup none --useOpenCL false --numCpuProcessingThreads " +
        std::to_string(workers + 1) + " --outputNum 1 --output0 " + (work / "out").string() +
        " --output0params dds,rgba32f,cubemap --silent > " + (work / "cmft_run.log").string() + " 2>&1";
    const double cpu0 = cpuSeconds(RUSAGE_CHILDREN);
    const auto start = Clock::now();
    const int status = std::system(command.c_str());
    ChainResult r;
    r.seconds = since(start);
    r.cpu = cpuSeconds(RUSAGE_CHILDREN) - cpu0;
    if (status != 0) {
      std::cerr << "cmft failed (" << status << "): " << command << "\n";
    } else {
      const auto faces = readCmftDds(work / "out.dds", faceSize, mipCount);
      r.tool = "cmft";
      r.detail = "CPU, " + std::to_string(workers) + " worker(s), its 256^2 cube of the sky as source";
      r.errors = errorsOf([&](std::size_t k, const std::array<int, 3>& t) {
        const float* p = faces[t[0]][k].data() + 4 * (static_cast<std::size_t>(t[2]) * levels[k].size + t[1]);
        return Rgb(p[0], p[1], p[2]);
      });
      results.push_back(r);
    }
  }
  std::error_code ec;
  fs::remove_all(work, ec);
  std::cout << "\nPhong gloss chain (cmft --glossScale 10 --glossBias 1 --mipCount 8), " << faceSize << "^2 cube, "
            << environment.image.width() << "x" << environment.image.height() << " sky, threads "
            << (threads > 0 ? threads : 0) << " (0: all); RMS relative error against the reference sum at "
            << subsetSize << " random texels per level\n\n"
            << "| tool | seconds (wall) | CPU seconds | worst level RMS | per level RMS (exponent) | setting "
               "|\n|---|---:|---:|---:|---|---|\n";
  for (const auto& r : results) {
    double worst = 0.0;
    std::ostringstream perLevel;
    for (std::size_t k = 0; k < r.errors.size(); ++k) {
      worst = std::max(worst, r.errors[k].rms);
      perLevel << (k ? ", " : "") << format(100.0 * r.errors[k].rms, 2) << " % (" << format(levels[k].exponent, 4)
               << ")";
    }
    std::cout << "| " << r.tool << " | " << format(r.seconds) << " | " << format(r.cpu) << " | "
              << format(100.0 * worst, 3) << " % | " << perLevel.str() << " | " << r.detail << " |\n";
  }
}

void chart(const std::vector<Row>& rows, const fs::path& png, const std::vector<std::string>& groups) {
  if (!haveProgram("gnuplot")) {
    std::cerr << "gnuplot not found: no chart written\n";
    return;
  }
  const fs::path data = fs::temp_directory_path() / ("brdfbake-prefilter-chart-" + std::to_string(::getpid()) + ".dat");
  {
    std::ofstream out(data);
    // One gnuplot data block per (panel, series): index = panel * 5 + series.
    const std::vector<std::string> series{"sh", "direct", "importance", "auto", "cmgen"};
    for (const auto& panel : groups) {
      for (const auto& s : series) {
        out << "# " << panel << " " << s << "\n";
        bool any = false;
        for (const auto& r : rows) {
          if (r.group.rfind(panel + " ", 0) != 0 || r.method != s) continue;
          const bool sphere = r.group.find("sphere") != std::string::npos;
          out << r.seconds << " " << std::max(r.rms, 1e-6) << " " << (sphere ? 1 : 0) << "\n";
          any = true;
        }
        if (!any) out << "nan nan 0\n";
        out << "\n\n";
      }
    }
  }
  std::ostringstream script;
  script << "set terminal pngcairo size 1500,950 font 'sans,10'\n"
         << "set output '" << png.string() << "'\n"
         << "set multiplot layout 2,3 title 'Prefiltering a 1024x512 sky: time against RMS relative error (wall clock, "
         << "filled = paraboloid 2x256^2 or cube 6x256^2, open = sphere 256^2)'\n"
         << "set logscale xy\nset grid\nset xlabel 'seconds'\nset ylabel 'RMS relative error'\nset key bottom left\n"
         << "set format y '10^{%L}'\nset yrange [1e-6:10]\n";
  int panelIndex = 0;
  for (const auto& panel : groups) {
    double referenceSeconds = 0.0;
    for (const auto& r : rows)
      if (r.group.rfind(panel + " ", 0) == 0 && r.method == "reference")
        referenceSeconds = std::max(referenceSeconds, r.seconds);
    script << "set title '" << panel << " (reference about " << static_cast<long>(std::lround(referenceSeconds))
           << " s, off the chart)'\n";
    script << "unset arrow\nset arrow from graph 0, first 0.01 to graph 1, first 0.01 nohead dt 2 lc rgb 'gray40'\n";
    const int base = panelIndex * 5;
    script << "plot '" << data.string() << "' index " << base
           << " using 1:($3==0?$2:1/0) with points pt 7 ps 1.3 lc rgb '#1f77b4' title 'sh', "
           << "'' index " << base << " using 1:($3==1?$2:1/0) with points pt 6 ps 1.3 lc rgb '#1f77b4' notitle, "
           << "'' index " << base + 1
           << " using 1:($3==0?$2:1/0) with points pt 5 ps 1.3 lc rgb '#2ca02c' title 'direct', "
           << "'' index " << base + 1 << " using 1:($3==1?$2:1/0) with points pt 4 ps 1.3 lc rgb '#2ca02c' notitle, "
           << "'' index " << base + 2
           << " using 1:($3==0?$2:1/0) with points pt 9 ps 1.3 lc rgb '#ff7f0e' title 'importance', "
           << "'' index " << base + 2 << " using 1:($3==1?$2:1/0) with points pt 8 ps 1.3 lc rgb '#ff7f0e' notitle, "
           << "'' index " << base + 3
           << " using 1:($3==0?$2:1/0) with points pt 13 ps 2.2 lc rgb '#d62728' title 'auto', "
           << "'' index " << base + 3 << " using 1:($3==1?$2:1/0) with points pt 12 ps 2.2 lc rgb '#d62728' notitle, "
           << "'' index " << base + 4 << " using 1:2 with points pt 3 ps 2.2 lc rgb 'black' title 'cmgen'\n";
    ++panelIndex;
  }
  script << "unset multiplot\n";
  FILE* pipe = popen("gnuplot", "w");
  if (!pipe) {
    std::cerr << "cannot run gnuplot\n";
    return;
  }
  const std::string text = script.str();
  std::fwrite(text.data(), 1, text.size(), pipe);
  if (pclose(pipe) != 0)
    std::cerr << "gnuplot failed\n";
  else
    std::cerr << "wrote " << png.string() << "\n";
  std::error_code ec;
  fs::remove(data, ec);
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, useCmgen = true, chainOnly = false;
  int threads = 0, subsetSize = 256;
  fs::path cmftSource = std::getenv("CMFT_SOURCE") ? std::getenv("CMFT_SOURCE") : "";
  fs::path png = "docs/images/prefilter_speed_error.png";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick")
      quick = true;
    else if (a == "--no-cmgen")
      useCmgen = false;
    else if (a == "--threads" && i + 1 < argc)
      threads = std::stoi(argv[++i]);
    else if (a == "--subset" && i + 1 < argc)
      subsetSize = std::stoi(argv[++i]);
    else if (a == "--chart" && i + 1 < argc)
      png = argv[++i];
    else if (a == "--cmft" && i + 1 < argc)
      cmftSource = argv[++i];
    else if (a == "--chain-only")
      chainOnly = true;
    else {
      std::cerr << "usage: prefilter_bench [--quick] [--threads N] [--subset N] [--chart FILE.png] [--no-cmgen] "
                   "[--cmft DIR] [--chain-only]\n";
      return 2;
    }
  }
  try {
    const int rowsOfSky = quick ? 128 : 512, outputResolution = quick ? 64 : 256;
    auto start = Clock::now();
    const Environment sky = bakeEnvironment(SkyEnvironment(), ParameterizationKind::LatLong, rowsOfSky, "sky", 16,
                                            Context({.threads = threads}));
    std::cerr << "sky " << sky.image.width() << "x" << sky.image.height() << " in " << since(start) << " s\n";
    if (chainOnly) {
      cmftComparison(sky, cmftSource, outputResolution, subsetSize, threads);
      return 0;
    }
    std::vector<Row> rows;
    std::vector<std::string> groups;
    for (double exponent : {1.0, 10.0, 100.0, 1000.0}) {
      const PrefilterLobe lobe = PrefilterLobe::phong(exponent);
      groups.push_back(lobe.name());
      const double floor = prefilterErrorFloor(sky, lobe);
      for (auto kind : {ParameterizationKind::Paraboloid, ParameterizationKind::Sphere}) {
        const std::string group = lobe.name() + " " + std::string(toString(kind));
        PrefilterOptions options;
        options.parameterization = kind;
        options.resolution = outputResolution;
        const auto map = makeParameterization(kind, outputResolution);
        const PrefilterCheckPoints subset = prefilterTexelSubset(*map, lobe, options, subsetSize, 7);
        start = Clock::now();
        const auto reference = prefilterReferenceAt(sky, lobe, subset.axes, Context({.threads = threads}));
        Row ref;
        ref.group = group, ref.tool = "brdfbake", ref.method = "reference", ref.extrapolated = true;
        ref.seconds = since(start) * map->width() * map->height() / subset.axes.size();
        rows.push_back(ref);
        std::cerr << group << ": reference ~" << ref.seconds << " s\n";
        rows.push_back(run(sky, lobe, options, subset, reference, floor, group, threads));
        std::cerr << "  auto " << rows.back().seconds << " s, rms " << rows.back().rms << " (estimate "
                  << rows.back().estimate << ")\n";
        auto fixed = [&](PrefilterMethod method, int order, int samples, double q) {
          PrefilterOptions o = options;
          o.method = method, o.shOrder = order, o.importanceSamples = samples, o.directTexelsPerWidth = q;
          o.estimateError = false;
          o.interpolate = false;  // each method alone, at every output texel
          rows.push_back(run(sky, lobe, o, subset, reference, floor, group, threads));
          std::cerr << "  " << rows.back().method << " " << rows.back().detail << ": " << rows.back().seconds
                    << " s, rms " << rows.back().rms << "\n";
        };
        for (int order : {8, 16, 32, 64}) fixed(PrefilterMethod::SphericalHarmonics, order, 0, 0.0);
        for (double q : {2.0, 4.0, 8.0}) fixed(PrefilterMethod::Direct, 0, 0, q);
        for (int samples : {64, 256, 1024}) fixed(PrefilterMethod::Importance, 0, samples, 0.0);
      }
    }
    if (useCmgen && !haveProgram("cmgen")) {
      std::cerr << "cmgen not found (Debian: apt-get install libfilament-tools): GGX comparison without it\n";
      useCmgen = false;
    }
    ggxComparison(sky, outputResolution, subsetSize, threads, useCmgen, rows);
    groups.push_back("ggx:0.25");
    groups.push_back("ggx:0.5");

    std::cout << "| lobe, map | tool | method | setting | seconds | RMS rel. error | max rel. error | estimate | "
                 "speedup vs reference |\n"
              << "|---|---|---|---|---:|---:|---:|---:|---:|\n";
    for (const auto& r : rows) {
      double referenceSeconds = 0.0;
      for (const auto& q : rows)
        if (q.group == r.group && q.method == "reference") referenceSeconds = q.seconds;
      std::cout << "| " << r.group << " | " << r.tool << " | " << r.method << " | " << r.detail << " | "
                << format(r.seconds) << (r.extrapolated ? " (scaled)" : "") << " | "
                << (r.method == "reference" ? "0" : format(100.0 * r.rms, 2) + " %") << " | "
                << (r.method == "reference" ? "0" : format(100.0 * r.max, 2) + " %") << " | "
                << (r.estimate >= 0.0 ? format(100.0 * r.estimate, 2) + " %" : "") << " | "
                << (r.method == "reference" ? "1" : format(referenceSeconds / r.seconds, 3)) << " |\n";
    }
    chart(rows, png, groups);
    cmftComparison(sky, cmftSource, outputResolution, subsetSize, threads);
  } catch (const Error& e) {
    std::cerr << "prefilter_bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
