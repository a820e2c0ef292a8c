// One meaning per flag on every command: -o names one file, --json is a run report, --quiet prints
// only errors, --threads and --max-error take the same values everywhere.
#include <gtest/gtest.h>
#include <brdfbake/io/image_io.hpp>
#include <nlohmann/json.hpp>

#include <fstream>

#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::q;
using test::runCli;

const std::string kPhongSpec = test::sourcePath("data_samples/specs/phong_eye.json");  // two maps
const std::string kTable = test::sourcePath("data_samples/tables/synthetic_two_lobes.astm");

TEST(Flags, BakeRefusesMinusOAndNamesOutDir) {
  test::TempDir dir;
  const auto r = runCli("bake " + q(kPhongSpec) + " -o " + q(dir / "single.exr"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("give the folder they go in with --out-dir DIR"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "single.exr"));
  const auto ok = runCli("bake " + q(kPhongSpec) + " --out-dir " + q(dir / "out") + " --quiet");
  ASSERT_EQ(ok.exitCode, 0) << ok.output;
  EXPECT_EQ(ok.output, "");
  EXPECT_TRUE(fs::is_regular_file(dir / "out" / "phong_eye.exr"));
  EXPECT_TRUE(fs::is_regular_file(dir / "out" / "phong_paraboloid.exr"));
}

TEST(Flags, ChartMinusOIsOneFileForATwoMapSpec) {
  if (test::run("command -v gnuplot").exitCode != 0) GTEST_SKIP() << "gnuplot not installed; skipping";
  test::TempDir dir;
  const auto r = runCli("chart " + q(kPhongSpec) + " -o " + q(dir / "chart.png") +
                        " --resolutions 16,32 --samples 1 --parameterizations sphere --quiet");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output, "");
  EXPECT_EQ(test::filesIn(dir.path()), std::vector<std::string>{"chart.png"});
  // Two stacked panels: 900 x 1200 pixels (PNG header: width and height at bytes 16..23).
  std::ifstream png(dir / "chart.png", std::ios::binary);
  unsigned char header[24] = {};
  png.read(reinterpret_cast<char*>(header), 24);
  const auto be32 = [&](int at) {
    return (header[at] << 24) | (header[at + 1] << 16) | (header[at + 2] << 8) | header[at + 3];
  };
  EXPECT_EQ(be32(16), 900);
  EXPECT_EQ(be32(20), 1200);
}

TEST(Flags, FitJsonIsARunReportHoldingTheFit) {
  test::TempDir dir;
  const auto r = runCli("fit " + q(kTable) + " --lobes 1 --elevation constant -o " + q(dir / "fit.json") + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto report = nlohmann::json::parse(r.out);
  EXPECT_EQ(report["table"], kTable);
  EXPECT_EQ(report["files"], nlohmann::json::array({(dir / "fit.json").string()}));
  EXPECT_EQ(report["fit"]["format"], "brdfbake.lobe_fit");
  std::ifstream in(dir / "fit.json");
  EXPECT_EQ(nlohmann::json::parse(in)["channels"], report["fit"]["channels"]) << "the report holds what was written";
}

TEST(Flags, QuietAndThreadsAreAcceptedByEveryCommandThatWorks) {
  test::TempDir dir;
  ASSERT_EQ(runCli("bake " + q(kPhongSpec) + " --out-dir " + q(dir.path()) + " --quiet --threads 1").exitCode, 0);
  const fs::path map = dir / "phong_paraboloid.exr";
  for (const std::string& command :
       {"convert " + q(map) + " --to cube --resolution 8 -o " + q(dir / "c.exr") + " --quiet --threads 1",
        "preview " + q(map) + " --size 16 -o " + q(dir / "p.png") + " --quiet",
        "prefilter " + q(map) + " --lobe irradiance --to sphere --resolution 8 -o " + q(dir / "i.exr") +
            " --quiet --threads 1"}) {
    const auto r = runCli(command);
    EXPECT_EQ(r.exitCode, 0) << command << "\n" << r.output;
    EXPECT_EQ(r.output, "") << command;
  }
  // Query commands still print what they exist to print.
  const auto sample = runCli("sample " + q(map) + " --dir 0,0,1 --quiet");
  ASSERT_EQ(sample.exitCode, 0) << sample.output;
  EXPECT_EQ(std::count(sample.output.begin(), sample.output.end(), ' '), 3) << sample.output;
}

TEST(Flags, MaxErrorHasOneRangeOnChartAndPrefilter) {
  test::TempDir dir;
  for (const std::string& command : {"chart " + q(kPhongSpec) + " --json --max-error 0.7",
                                     "prefilter " + q(test::sourcePath("data_samples/environments/sky_latlong.exr")) +
                                         " --lobe phong:10 --to sphere -o " + q(dir / "x.exr") + " --max-error 0.7"}) {
    const auto r = runCli(command);
    EXPECT_EQ(r.exitCode, 2) << command;
    EXPECT_NE(r.output.find("--max-error"), std::string::npos) << r.output;
  }
}

TEST(Flags, APlainImageNamesTheFromFlag) {
  test::TempDir dir;
  writeImage(Image(8, 4, Rgba(0.5, 0.5, 0.5, 1.0)), dir / "plain.exr");  // no brdfbake metadata
  const auto r = runCli("sample " + q(dir / "plain.exr") + " --dir 0,0,1");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("--from sphere|paraboloid|cube|latlong"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace brdfbake
