// Charts through the library (chartSpec): material maps and prefiltered environment maps swept
// over parameterization x resolution x samples or method, errors against closed forms (a
// furnace), the prefilter's own estimates and the reference, the Pareto front recomputed here, the
// CSV, skipped combinations, and the chart decoded. Moved from tests/cli/test_chart_environment.cpp
// and tests/cli/test_cli.cpp (Cli.ChartSweepsAndMarksTheParetoFront), which keep the flags.
#include <gtest/gtest.h>
#include <brdfbake/core/math.hpp>
#include <brdfbake/env/env_accuracy.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/run/chart.hpp>
#include <brdfbake/run/gnuplot.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "chart_support.hpp"
#include "pareto_check.hpp"
#include "run_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::readCsv;
using test::writeChartSpec;

const std::string kSky = test::sourcePath("data_samples/environments/sky_latlong.exr");
const std::string kFurnace = test::sourcePath("data_samples/environments/furnace_latlong.exr");

// chart SPEC with the environment sweep of the tool's --resolutions, --parameterizations, --methods.
ChartOptions chartOf(const fs::path& spec, std::vector<int> resolutions,
                     std::vector<ParameterizationKind> parameterizations = {},
                     std::vector<PrefilterMethod> methods = {}, int subset = 256) {
  ChartOptions options;
  options.spec = spec;
  options.resolutions = options.environmentResolutions = std::move(resolutions);
  if (!parameterizations.empty()) options.parameterizations = std::move(parameterizations);
  if (!methods.empty()) options.methods = std::move(methods);
  options.subset = subset;
  return options;
}

using K = ParameterizationKind;
using M = PrefilterMethod;

TEST(ChartJob, FurnaceGivesZeroErrorForEveryParameterizationResolutionAndMethod) {
  test::TempDir dir;
  writeChartSpec(dir / "f.json", kFurnace, "phong:20");
  ChartOptions options = chartOf(dir / "f.json", {8, 16}, {}, {}, 64);
  options.csv = dir / "f.csv";
  chartSpec(options, test::twoThreads());
  const auto rows = readCsv(dir / "f.csv");
  ASSERT_EQ(rows.size(), 4u * 2u * 4u);  // sphere, paraboloid, cube, latlong x 8, 16 x auto, sh, direct, importance
  std::set<std::string> combinations;
  for (const auto& row : rows) {
    combinations.insert(row.at("parameterization") + "/" + row.at("resolution") + "/" + row.at("method"));
    EXPECT_EQ(row.at("map"), "maps[0]");
    EXPECT_EQ(row.at("samples_per_texel"), "0");
    EXPECT_GT(std::stod(row.at("seconds")), 0.0);
    EXPECT_GT(std::stod(row.at("reference_seconds")), 0.0);
    // A constant environment stays 1 under every normalised lobe, in every method: the error is
    // rounding only, at texels and between them.
    EXPECT_LT(std::stod(row.at("rms")), 1e-6) << row.at("parameterization") << " " << row.at("method");
    EXPECT_LT(std::stod(row.at("max")), 1e-6) << row.at("parameterization") << " " << row.at("method");
    EXPECT_LT(std::stod(row.at("lookup_rms")), 1e-6) << row.at("parameterization") << " " << row.at("method");
    EXPECT_FALSE(row.at("detail").empty());
  }
  EXPECT_EQ(combinations.size(), rows.size());  // one row per combination, none twice
  for (const char* kind : {"sphere", "paraboloid", "cube", "latlong"})
    for (const char* n : {"8", "16"})
      for (const char* method : {"auto", "sh", "direct", "importance"})
        EXPECT_EQ(combinations.count(std::string(kind) + "/" + n + "/" + method), 1u)
            << kind << " " << n << " " << method;
}

TEST(ChartJob, SkyErrorsAreFiniteBoundedAndAgreeWithThePrefiltersEstimates) {
  test::TempDir dir;
  writeChartSpec(dir / "s.json", kSky, "phong:100");
  ChartOptions options = chartOf(dir / "s.json", {16, 32}, {K::Sphere, K::Paraboloid});
  options.csv = dir / "s.csv";
  const auto points = chartSpec(options, test::twoThreads()).toJson();
  ASSERT_EQ(points.size(), 2u * 2u * 4u);
  std::map<std::string, nlohmann::json> byKey;
  for (const auto& p : points) {
    ASSERT_FALSE(p.contains("skipped")) << p.dump();
    const std::string key = p["parameterization"].get<std::string>() + "/" +
                            std::to_string(p["resolution"].get<int>()) + "/" + p["method"].get<std::string>();
    byKey[key] = p;
    const double rms = p["rms"].get<double>(), max = p["max"].get<double>(), lookup = p["lookup_rms"].get<double>();
    EXPECT_TRUE(std::isfinite(rms) && std::isfinite(max) && std::isfinite(lookup)) << key;
    EXPECT_GT(rms, 0.0) << key;  // the sky is no furnace
    EXPECT_GE(max, rms) << key;
    // Each method picks its setting for the 1 % bound; importance, the weakest on a sun, may not
    // reach it (docs/prefilter.md) but stays within a few percent.
    EXPECT_LT(rms, p["method"] == "importance" ? 0.06 : 0.02) << key;
    // Fast methods estimate their own error from probes before they make the map. The estimate is
    // the largest of three RMS errors (over solid angle, weighted by value, near bright texels), so
    // it is at least the RMS measured on 256 texels over solid angle within a factor of 3, and at
    // most 4 times it (or both are below 0.2 %).
    ASSERT_TRUE(p["estimate"].is_number()) << key;
    const double estimate = p["estimate"].get<double>();
    if (rms > 2e-3 || estimate > 2e-3) {
      EXPECT_LT(rms, 3.0 * estimate) << key;
      EXPECT_GT(rms, estimate / 4.0) << key;
    }
    if (p["method"] == "auto") {
      EXPECT_TRUE(p["met_bound"].get<bool>()) << key;
    }
    EXPECT_GT(p["reference_seconds"].get<double>(), 0.0) << key;
  }
  // The Pareto front recomputed from each point's time and RMS error (tests/support/pareto_check.hpp).
  test::expectParetoFlagsMatch(points);
  // Between texels a bilinear lookup also interpolates: its error is larger than at the texels,
  // and in a paraboloid map it falls with the resolution (measured 24 % at 16, 3.6 % at 32). (Not
  // compared for sphere maps: which directions near the rim are skipped depends on the resolution,
  // and the sun's reflection falls there.)
  for (const char* kind : {"sphere", "paraboloid"}) {
    const std::string k = kind;
    EXPECT_GT(byKey.at(k + "/16/direct")["lookup_rms"].get<double>(),
              2.0 * byKey.at(k + "/16/direct")["rms"].get<double>())
        << k;
  }
  EXPECT_LT(byKey.at("paraboloid/32/direct")["lookup_rms"].get<double>(),
            0.5 * byKey.at("paraboloid/16/direct")["lookup_rms"].get<double>());
  // The CSV holds the same points, with the method column.
  const auto rows = readCsv(dir / "s.csv");
  ASSERT_EQ(rows.size(), points.size());
  for (const auto& row : rows) {
    const auto& p = byKey.at(row.at("parameterization") + "/" + row.at("resolution") + "/" + row.at("method"));
    EXPECT_NEAR(std::stod(row.at("rms")), p["rms"].get<double>(), 1e-5 * p["rms"].get<double>());
    EXPECT_EQ(row.at("pareto"), p["pareto"].get<bool>() ? "1" : "0");
  }
}

TEST(ChartJob, MirrorMapsAndBadCombinationsAreSkippedWithANote) {
  test::TempDir dir;
  // A filtered map, then a mirror map (no reference to chart against).
  writeChartSpec(dir / "m.json", kFurnace, "irradiance",
                 R"(, {"output": "mirror.exr", "parameterization": "sphere", "resolution": 16,
                  "environment": {"file": ")" +
                     kFurnace + R"(", "lobe": "mirror"}})");
  const ChartResult result =
      chartSpec(chartOf(dir / "m.json", {8}, {K::LatLong}, {M::SphericalHarmonics, M::Direct}, 32), test::twoThreads());
  const auto entries = result.toJson();
  ASSERT_EQ(entries.size(), 3u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(entries[i]["map"], "maps[0]");
    // Irradiance E/pi of the furnace is 1 everywhere, which every method reproduces.
    EXPECT_LT(entries[i]["rms"].get<double>(), 1e-6);
  }
  EXPECT_EQ(entries[2]["map"], "maps[1]");
  EXPECT_TRUE(entries[2]["skipped"].get<bool>());
  EXPECT_NE(entries[2]["note"].get<std::string>().find("mirror"), std::string::npos);
  // The text report gives the note.
  EXPECT_NE(result.briefReport().find("note: maps[1]"), std::string::npos) << result.briefReport();

  // Fitted lobes that vary with elevation make a stack of maps, not one: skipped with a note.
  writeChartSpec(dir / "v.json", kFurnace, "irradiance",
                 R"(, {"output": "v.exr", "parameterization": "sphere", "resolution": 16,
                  "environment": {"file": ")" +
                     kFurnace + R"(", "lobe": "lobes:)" + test::sourcePath("data_samples/fits/synthetic_varying.json") +
                     R"("}})");
  const auto varyingEntries =
      chartSpec(chartOf(dir / "v.json", {8}, {K::LatLong}, {M::SphericalHarmonics}, 16), test::twoThreads()).toJson();
  ASSERT_EQ(varyingEntries.size(), 2u);
  EXPECT_TRUE(varyingEntries[1]["skipped"].get<bool>());
  EXPECT_NE(varyingEntries[1]["note"].get<std::string>().find("vary with elevation"), std::string::npos);

  // A combination the prefilter refuses (a map over the size limit) is skipped, the rest charted.
  writeChartSpec(dir / "big.json", kFurnace, "phong:10");
  const auto bigEntries =
      chartSpec(chartOf(dir / "big.json", {8, 10000}, {K::LatLong}, {M::SphericalHarmonics}, 16), test::twoThreads())
          .toJson();
  ASSERT_EQ(bigEntries.size(), 2u);
  EXPECT_EQ(bigEntries[0]["resolution"], 8);
  EXPECT_FALSE(bigEntries[0].contains("skipped"));
  EXPECT_EQ(bigEntries[1]["resolution"], 10000);
  EXPECT_TRUE(bigEntries[1]["skipped"].get<bool>());
  EXPECT_NE(bigEntries[1]["note"].get<std::string>().find("GiB"), std::string::npos) << bigEntries[1].dump();
}

TEST(ChartJob, DrawsOnePanelPerMapAsAPictureOf900By600PixelsEach) {
  if (!findGnuplot()) GTEST_SKIP() << "gnuplot not installed; the CSV and JSON paths are tested above";
  // Two maps (an environment and a material): two panels stacked, 900 x 1200 pixels; each panel
  // is a chart, not a blank page: far more than a handful of its pixels differ from white.
  test::TempDir dir;
  writeChartSpec(dir / "s.json", kSky, "phong:10",
                 R"(, {"output": "p.exr", "parameterization": "sphere", "material": {"model": "phong", "exponent": 20},
                  "lights": [{"direction": [0, 1, 1]}]})");
  ChartOptions options = chartOf(dir / "s.json", {16}, {K::Sphere, K::Cube}, {M::Auto, M::SphericalHarmonics}, 32);
  options.samplesPerTexel = {1};
  options.lookups = 2000;
  options.lookupError = true;
  options.chart = dir / "c.png";
  const ChartResult result = chartSpec(options, test::twoThreads());
  EXPECT_EQ(result.panels, 2);
  EXPECT_EQ(result.chart, dir / "c.png");
  const Image chart = readImage(dir / "c.png");
  ASSERT_EQ(chart.width(), 900);
  ASSERT_EQ(chart.height(), 1200);
  for (int panel = 0; panel < 2; ++panel) {
    int inked = 0;
    for (int y = panel * 600; y < (panel + 1) * 600; ++y)
      for (int x = 0; x < 900; ++x) inked += chart.at(x, y).head<3>().minCoeff() < 0.5;
    EXPECT_GT(inked, 2000) << "panel " << panel;  // axes, tick labels, points, title
  }
}

TEST(ChartJob, MaterialMapsSweepAndMarkTheParetoFront) {
  test::TempDir dir;
  std::ofstream(dir / "s.json") << R"({"maps": [{"output": "m.exr", "parameterization": "sphere",
      "material": {"model": "phong", "exponent": 20}, "lights": [{"direction": [0, 1, 1]}]}]})";
  ChartOptions options;
  options.spec = dir / "s.json";
  options.csv = dir / "c.csv";
  options.resolutions = {16, 64};
  options.samplesPerTexel = {1, 4};
  options.parameterizations = {K::Sphere, K::Paraboloid};
  options.lookups = 2000;
  const auto points = chartSpec(options, test::twoThreads()).toJson();
  ASSERT_EQ(points.size(), 8u);
  for (const auto& p : points) {
    EXPECT_GT(p["rms"].get<double>(), 0.0);
    EXPECT_GE(p["max"].get<double>(), p["rms"].get<double>());
  }
  // The Pareto front recomputed from each point's time and RMS error (tests/support/pareto_check.hpp).
  test::expectParetoFlagsMatch(points);
  // Four times the resolution cuts the error of every map by far more than half.
  auto rms = [&](const std::string& kind, int n, int spt) {
    for (const auto& p : points)
      if (p["parameterization"] == kind && p["resolution"] == n && p["samples_per_texel"] == spt)
        return p["rms"].get<double>();
    return -1.0;
  };
  EXPECT_LT(rms("sphere", 64, 4), 0.3 * rms("sphere", 16, 4));
  EXPECT_LT(rms("paraboloid", 64, 4), 0.3 * rms("paraboloid", 16, 4));
  std::ifstream csv(dir / "c.csv");
  int lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, 9);
}

// The library pieces the chart and bench/prefilter_bench share.
TEST(ChartJob, TexelSubsetsAndPointErrors) {
  const auto lobe = PrefilterLobe::phong(10);
  PrefilterOptions options;
  options.parameterization = ParameterizationKind::Sphere;
  // A map with fewer texels than asked for is taken whole: its solid angles sum to 4 pi.
  const auto small = makeParameterization(ParameterizationKind::Sphere, 8);
  const auto whole = prefilterTexelSubset(*small, lobe, options, 1000, 1);
  double sum = 0.0;
  for (double w : whole.weights) sum += w;
  EXPECT_NEAR(sum, 4.0 * kPi, 1e-6);
  EXPECT_LE(whole.size(), 64u);
  // A larger one is drawn: the count asked for, axes on the unit sphere, reproducible by seed.
  const auto large = makeParameterization(ParameterizationKind::Sphere, 64);
  const auto a = prefilterTexelSubset(*large, lobe, options, 100, 7),
             b = prefilterTexelSubset(*large, lobe, options, 100, 7);
  ASSERT_EQ(a.size(), 100u);
  EXPECT_EQ(a.texels, b.texels);
  for (const Vec3& axis : a.axes) EXPECT_NEAR(axis.norm(), 1.0, 1e-12);
  // Relative errors: 1 % everywhere gives 1 % RMS and max; below the floor the floor divides.
  const std::vector<Rgb> reference(3, Rgb(1, 2, 2)), values(3, Rgb(1.01, 2.02, 2.02));
  const auto e = prefilterPointsError(values, reference, {1.0, 2.0, 3.0}, 1e-3);
  EXPECT_NEAR(e.rms, 0.01, 1e-12);
  EXPECT_NEAR(e.max, 0.01, 1e-12);
  const auto dark = prefilterPointsError({Rgb(0.001, 0, 0)}, {Rgb::Zero()}, {1.0}, 0.1);
  EXPECT_NEAR(dark.rms, 0.01, 1e-12);
  // Lookup sets of sphere maps avoid the rim.
  const auto lookups = prefilterLookupSet(*large, lobe, options, 500, 3);
  ASSERT_EQ(lookups.size(), 500u);
  EXPECT_TRUE(lookups.texels.empty());
  for (const Vec3& d : lookups.directions) EXPECT_GT(d.z(), -0.9);
}

}  // namespace
}  // namespace brdfbake
