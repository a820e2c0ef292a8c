// The command line as a user meets it: acceptance checks from the issue, exit codes, no output
// on bad input, machine-readable output.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/maps/image.hpp>
#include <nlohmann/json.hpp>

#include <fstream>

#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::runCli;

using test::q;

double sampleValue(const fs::path& map, const Vec3& d) {
  const auto result = runCli("sample " + q(map) + " --json --dir " + std::to_string(d.x()) + "," +
                             std::to_string(d.y()) + "," + std::to_string(d.z()));
  EXPECT_EQ(result.exitCode, 0) << result.output;
  return nlohmann::json::parse(result.out)["value"][0].get<double>();
}

// End to end: the tool bakes a spec and looks its maps up as a renderer does (the computation
// itself is tested through the library: tests/run/test_run_bake.cpp).
TEST(Cli, BakeAndSampleMatchTheAnalyticLobes) {
  test::TempDir dir;
  const auto result = runCli("bake " + q(test::sourcePath("data_samples/specs/phong_eye.json")) + " --out-dir " +
                             q(dir.path()) + " --quiet");
  ASSERT_EQ(result.exitCode, 0) << result.output;
  EXPECT_TRUE(result.output.empty()) << result.output;
  const Vec3 light = Vec3(1, 1, 1).normalized();
  for (const Vec3& r : {Vec3(0, 0, 1), Vec3(0.1, 0.2, 0.97).normalized(), light, Vec3(0.3, 0.5, 0.8).normalized()}) {
    EXPECT_NEAR(sampleValue(dir / "phong_eye.exr", r), std::pow(std::max(0.0, r.z()), 50), 0.01) << r.transpose();
    EXPECT_NEAR(sampleValue(dir / "phong_paraboloid.exr", r), std::pow(std::max(0.0, r.dot(light)), 50), 0.01)
        << r.transpose();
  }
}

TEST(Cli, BadSpecsExitTwoNameTheJsonPathAndWriteNothing) {
  test::TempDir dir;
  const fs::path spec = dir / "bad.json";
  std::ofstream(spec) << R"({"maps": [
    {"output": "good.exr", "parameterization": "sphere", "resolution": 16,
     "material": {"model": "phong", "exponent": 5}, "lights": [{"direction": "eye"}]},
    {"output": "bad.exr", "parameterization": "sphere", "resolution": 16,
     "material": {"model": "phong", "exponent": -3}, "lights": [{"direction": "eye"}]}]})";
  const auto result = runCli("bake " + q(spec));
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_NE(result.output.find("maps[1].material.exponent: must be > 0, got -3"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir / "good.exr"));  // validated whole before anything is baked
  EXPECT_FALSE(fs::exists(dir / "bad.exr"));
}

TEST(Cli, RefusesAnOversizeMapBeforeWritingAnything) {
  test::TempDir dir;
  const fs::path spec = dir / "huge.json";
  std::ofstream(spec) << R"({"maps": [
    {"output": "small.exr", "parameterization": "sphere", "resolution": 8,
     "material": {"model": "phong", "exponent": 5}, "lights": [{"direction": "eye"}]},
    {"output": "huge.exr", "parameterization": "sphere", "resolution": 16384,
     "material": {"model": "phong", "exponent": 5}, "lights": [{"direction": "eye"}]}]})";
  const auto result = runCli("bake " + q(spec));
  EXPECT_EQ(result.exitCode, 4) << result.output;
  EXPECT_NE(result.output.find("GiB"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("--allow-large"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir / "small.exr"));
}

TEST(Cli, BadFlagsExitTwo) {
  test::TempDir dir;
  EXPECT_EQ(runCli("").exitCode, 2);
  EXPECT_EQ(runCli("frobnicate").exitCode, 2);
  EXPECT_EQ(runCli("bake").exitCode, 2);
  EXPECT_EQ(runCli("bake x.json --threads -2").exitCode, 2);
  const auto dirResult = runCli("sample " + q(dir / "m.exr") + " --dir 1,2");
  EXPECT_EQ(dirResult.exitCode, 2);
  EXPECT_NE(dirResult.output.find("--dir"), std::string::npos) << dirResult.output;
  EXPECT_EQ(runCli("sample " + q(dir / "m.exr") + " --dir 0,0,0").exitCode, 2);
  EXPECT_EQ(runCli("convert a.exr --to spherical -o b.exr").exitCode, 2);
  const auto missing = runCli("info " + q(dir / "none.exr"));
  EXPECT_EQ(missing.exitCode, 3);
  EXPECT_NE(missing.output.find("none.exr"), std::string::npos);
}

// The preview's pixels are checked through the library
// (BakeJob.APreviewShowsTheMapAtTheAnalyticReflectionOnEveryObject); here the tool's flags: every object and size
// writes a PNG, a wrong view or object exits 2.
TEST(Cli, PreviewFlagsWriteAPngOrExitTwo) {
  test::TempDir dir;
  ASSERT_EQ(runCli("bake " + q(test::sourcePath("data_samples/specs/phong_eye.json")) + " --out-dir " + q(dir.path()) +
                   " --quiet")
                .exitCode,
            0);
  for (const std::string flags : {"--object teapot", "--object torus --per-vertex --segments 8", "--resolution 64"}) {
    const auto result = runCli("preview " + q(dir / "phong_eye.exr") + " -o " + q(dir / "p.png") + " " + flags);
    ASSERT_EQ(result.exitCode, 0) << flags << "\n" << result.output;
    const Image png = readImage(dir / "p.png");
    EXPECT_EQ(png.width(), png.height()) << flags;
    if (flags == "--resolution 64") {
      EXPECT_EQ(png.width(), 64);
    }
    fs::remove(dir / "p.png");
  }
  // A paraboloid map can be seen from any view; a sphere map only from +z.
  EXPECT_EQ(
      runCli("preview " + q(dir / "phong_paraboloid.exr") + " -o " + q(dir / "side.png") + " --view 1,0.5,0").exitCode,
      0);
  const auto wrongView = runCli("preview " + q(dir / "phong_eye.exr") + " -o " + q(dir / "x.png") + " --view 1,0,0");
  EXPECT_EQ(wrongView.exitCode, 2);
  EXPECT_NE(wrongView.output.find("eye space"), std::string::npos) << wrongView.output;
  EXPECT_EQ(runCli("preview " + q(dir / "phong_eye.exr") + " -o " + q(dir / "x.png") + " --object cube").exitCode, 2);
  EXPECT_EQ(runCli("preview " + q(dir / "phong_eye.exr") + " -o " + q(dir / "phong_eye.exr")).exitCode, 2);
  EXPECT_FALSE(fs::exists(dir / "x.png"));
}

// The sweep and its Pareto front: ChartJob.MaterialMapsSweepAndMarkTheParetoFront (tests/run).
TEST(Cli, ChartRefusesBadChartFilesAndListsWithExitTwo) {
  test::TempDir dir;
  std::ofstream(dir / "s.json") << R"({"maps": [{"output": "m.exr", "parameterization": "sphere",
      "material": {"model": "phong", "exponent": 20}, "lights": [{"direction": [0, 1, 1]}]}]})";
  EXPECT_EQ(runCli("chart " + q(dir / "s.json") + " -o " + q(dir / "c.jpg")).exitCode, 2);
  EXPECT_EQ(runCli("chart " + q(dir / "s.json") + " -o " + q(dir / "d.png") + " --resolutions 16,x").exitCode, 2);
  EXPECT_EQ(runCli("chart " + q(dir / "s.json") + " -o " + q(dir / "d.png") + " --parameterizations disc").exitCode, 2);
  EXPECT_FALSE(fs::exists(dir / "d.png"));
}

TEST(Cli, InterpolationWritesWhatItsFlagsAskFor) {
  test::TempDir dir;
  const auto result = runCli("interpolation -o " + q(dir / "i.png") + " --sizes 2 --places 0,45,80 --json");
  ASSERT_EQ(result.exitCode, 0) << result.output;
  // -o is the one file written: the line chart only with its own flag.
  EXPECT_EQ(test::filesIn(dir.path()), std::vector<std::string>{"i.png"});
  const auto report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report["files"], nlohmann::json::array({(dir / "i.png").string()}));
  EXPECT_EQ(report["sweep"].size(), 3u);
  // The values against sums written out: InterpolationJob.ChartsBothSchemesAndTheLineExperiment (tests/run).
  EXPECT_GT(report["line"]["max_error_degrees"].get<double>(), 10.0);
  EXPECT_EQ(runCli("interpolation -o " + q(dir / "j.png") + " --sizes 0").exitCode, 2);
  EXPECT_EQ(runCli("interpolation -o " + q(dir / "j.png") + " --places 95").exitCode, 2);
  EXPECT_EQ(runCli("interpolation -o " + q(dir / "j.gif")).exitCode, 2);
  EXPECT_EQ(runCli("interpolation -o " + q(dir / "j.png") + " --line-chart " + q(dir / "j.gif")).exitCode, 2);
  EXPECT_EQ(runCli("interpolation --line-chart " + q(dir / "j.png") + " -o " + q(dir / "j.png")).exitCode, 2);
  const auto nothing = runCli("interpolation --sizes 2");
  EXPECT_EQ(nothing.exitCode, 2);
  EXPECT_NE(nothing.output.find("nothing to write"), std::string::npos) << nothing.output;
  EXPECT_FALSE(fs::exists(dir / "j.png"));

  // --line-chart writes the line chart, and nothing else is written beside either chart.
  const auto line = runCli("interpolation --line-chart " + q(dir / "line.svg") + " --sizes 2 --places 0 --quiet");
  ASSERT_EQ(line.exitCode, 0) << line.output;
  EXPECT_EQ(test::filesIn(dir.path()), (std::vector<std::string>{"i.png", "line.svg"}));
}

TEST(Cli, HelpTeaches) {
  const auto top = runCli("--help");
  EXPECT_EQ(top.exitCode, 0);
  EXPECT_NE(top.output.find("Exit status"), std::string::npos);
  EXPECT_NE(top.output.find("Examples"), std::string::npos);
  const auto bake = runCli("bake --help");
  EXPECT_EQ(bake.exitCode, 0);
  EXPECT_NE(bake.output.find("\"parameterization\""), std::string::npos);
}

}  // namespace
}  // namespace brdfbake
