// `brdfbake chart` on prefiltered environment maps as a user meets it: an end-to-end run into a
// CSV, and bad flags. The sweep, its errors, skipped combinations and the drawn chart are tested
// through the library: tests/run/test_run_chart.cpp.
#include <gtest/gtest.h>
#include <brdfbake/core/math.hpp>
#include <brdfbake/env/env_accuracy.hpp>
#include <brdfbake/env/environment.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "chart_support.hpp"
#include "pareto_check.hpp"
#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::readCsv;
using test::runCli;
using test::writeChartSpec;

using test::q;

const std::string kSky = test::sourcePath("data_samples/environments/sky_latlong.exr");
const std::string kFurnace = test::sourcePath("data_samples/environments/furnace_latlong.exr");

TEST(ChartEnvironment, BadFlagsExitTwoAndWriteNothing) {
  test::TempDir dir;
  writeChartSpec(dir / "f.json", kFurnace, "phong:20");
  EXPECT_EQ(runCli("chart " + q(dir / "f.json") + " --csv " + q(dir / "x.csv") + " --methods sh,fast").exitCode, 2);
  EXPECT_EQ(runCli("chart " + q(dir / "f.json") + " --csv " + q(dir / "x.csv") + " --subset 3").exitCode, 2);
  EXPECT_EQ(runCli("chart " + q(dir / "f.json") + " --csv " + q(dir / "x.csv") + " --environment-error mean").exitCode,
            2);
  const auto nothing = runCli("chart " + q(dir / "f.json"));
  EXPECT_EQ(nothing.exitCode, 2);
  EXPECT_NE(nothing.output.find("--csv"), std::string::npos) << nothing.output;
  EXPECT_FALSE(fs::exists(dir / "x.csv"));
}

// End to end: the tool charts an environment map into a CSV (what the points hold is tested
// through the library: tests/run/test_run_chart.cpp).
TEST(ChartEnvironment, ChartsAFurnaceIntoACsvEndToEnd) {
  test::TempDir dir;
  writeChartSpec(dir / "f.json", kFurnace, "phong:20");
  const auto result = runCli("chart " + q(dir / "f.json") + " --csv " + q(dir / "f.csv") +
                             " --resolutions 8 --parameterizations cube --methods sh --subset 16 --threads 2 --quiet");
  ASSERT_EQ(result.exitCode, 0) << result.output;
  EXPECT_TRUE(result.output.empty()) << result.output;
  const auto rows = readCsv(dir / "f.csv");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].at("parameterization"), "cube");
  EXPECT_LT(std::stod(rows[0].at("rms")), 1e-6);  // the furnace stays 1 under a normalised lobe
}

}  // namespace
}  // namespace brdfbake
