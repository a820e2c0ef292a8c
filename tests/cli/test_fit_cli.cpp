// `brdfbake fit` and `brdfbake eval` as a user meets them: eval's output lines, errors naming file
// and line, exit codes, the default output name. The fits and values themselves are tested through
// the library: tests/run/test_run_fit.cpp.
#include <gtest/gtest.h>
#include <brdfbake/core/math.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

#include "fit_formula.hpp"
#include "test_support.hpp"

namespace brdfbake {
namespace {
using test::cornellDirection;
namespace fs = std::filesystem;
using test::fitFormula;
using test::readJsonFile;
using test::runCli;

using test::q;

TEST(FitCli, EvalPairsPrintsOneLinePerInputLine) {
  test::TempDir dir;
  const fs::path fitFile = test::sourcePath("data_samples/fits/synthetic_two_lobes.json");
  std::ofstream(dir / "pairs.txt") << "0.5236 0 0.5236 3.14159\n# a comment\n\n1.0 0 0.3 -1.0\n";
  const auto result = runCli("eval " + q(fitFile) + " --pairs " + q(dir / "pairs.txt"));
  ASSERT_EQ(result.exitCode, 0) << result.output;
  std::istringstream lines(result.output);
  std::vector<std::string> out;
  for (std::string line; std::getline(lines, line);) out.push_back(line);
  ASSERT_EQ(out.size(), 4u) << result.output;
  EXPECT_EQ(out[1], "# a comment");
  EXPECT_EQ(out[2], "");
  const auto document = readJsonFile(fitFile);
  std::istringstream first(out[0]);
  for (std::size_t c = 0; c < 3; ++c) {
    double v = 0;
    first >> v;
    EXPECT_NEAR(v, fitFormula(document, c, cornellDirection(0.5236, 0), cornellDirection(0.5236, 3.14159)),
                1e-6 * std::max(1.0, v));
  }
}

TEST(FitCli, EvalPairsWithABadLineNamesFileAndLine) {
  test::TempDir dir;
  std::ofstream(dir / "pairs.txt") << "0.5 0 0.5 3.1\n0.5 0 zero 3.1\n";
  const auto result = runCli("eval " + q(test::sourcePath("data_samples/fits/synthetic_two_lobes.json")) + " --pairs " +
                             q(dir / "pairs.txt"));
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_NE(result.output.find("pairs.txt:2:"), std::string::npos) << result.output;
  std::ofstream(dir / "three.txt") << "0.5 0 0.5\n";
  const auto three = runCli("eval " + q(test::sourcePath("data_samples/fits/synthetic_two_lobes.json")) + " --pairs " +
                            q(dir / "three.txt"));
  EXPECT_EQ(three.exitCode, 2) << three.output;
  EXPECT_NE(three.output.find("three.txt:1: expected 4 numbers"), std::string::npos) << three.output;
}

TEST(FitCli, BadFlagsExitTwo) {
  const std::string table = q(test::sourcePath("data_samples/tables/synthetic_two_lobes.astm"));
  const std::string fit = q(test::sourcePath("data_samples/fits/synthetic_two_lobes.json"));
  for (const std::string& arguments :
       {"fit " + table + " --lobes 9", "fit " + table + " --lobes two", "fit " + table + " --elevation sideways",
        "fit " + table + " --channels spectral", "fit " + table + " --format xyz", "fit " + table + " --max-exponent 0",
        "fit " + table + " --max-exponent high", "fit " + table + " --max-exponent 1e6",
        "fit " + table + " --varying-prior -0.1", "fit " + table + " --varying-prior strong",
        "fit " + table + " --varying-prior 2", "eval " + fit, "eval " + fit + " --wi 0,0,1",
        "eval " + fit + " --wi 0,0,1 --wo 1,2", "eval " + fit + " --wi 0,0,1 --wo 0,0,1 --pairs x.txt",
        std::string("fit")}) {
    const auto result = runCli(arguments);
    EXPECT_EQ(result.exitCode, 2) << arguments << "\n" << result.output;
  }
  EXPECT_EQ(runCli("fit /nonexistent/table.astm").exitCode, 3);
}

TEST(FitCli, ReportWithoutGnuplotFailsBeforeTheFit) {
  test::TempDir dir;
  const auto result = test::run("BRDFBAKE_GNUPLOT= " + std::string(BRDFBAKE_CLI) + " fit " +
                                q(test::sourcePath("data_samples/tables/synthetic_two_lobes.astm")) + " -o " +
                                q(dir / "fit.json") + " --report " + q(dir / "fit.png"));
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_NE(result.output.find("gnuplot"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir / "fit.json"));
}

TEST(FitCli, WithoutOutputTheFitIsWrittenToTheCurrentFolder) {
  test::TempDir dir;
  const auto result = test::run("cd " + q(dir.path()) + " && " + BRDFBAKE_CLI + " fit " +
                                q(test::sourcePath("data_samples/tables/synthetic_two_lobes.astm")) +
                                " --lobes 1 --elevation constant");
  ASSERT_EQ(result.exitCode, 0) << result.output;
  EXPECT_NE(result.output.find("wrote synthetic_two_lobes_fit.json"), std::string::npos) << result.output;
  EXPECT_EQ(readJsonFile(dir / "synthetic_two_lobes_fit.json")["format"], "brdfbake.lobe_fit");
}

TEST(FitCli, AVaryingPriorGivenIsTheOneUsed) {
  // A number fixes the prior (nothing weaker is tried): fit.json records it, and a far stronger prior
  // holds the lobe's elevation profile flatter than a far weaker one.
  test::TempDir dir;
  const std::string table = q(test::sourcePath("data_samples/tables/synthetic_two_lobes.astm"));
  double spread[2];
  const double priors[2] = {1.0, 0.0};
  for (int i = 0; i < 2; ++i) {
    const fs::path out = dir / ("fit" + std::to_string(i) + ".json");
    const auto result = runCli("fit " + table + " --lobes 1 --kind mirror --elevation varying --held-out off " +
                               "--varying-prior " + std::to_string(priors[i]) + " -o " + q(out) + " --quiet");
    ASSERT_EQ(result.exitCode, 0) << result.output;
    const auto json = readJsonFile(out);
    EXPECT_EQ(json["fit"]["varying_prior"].get<double>(), priors[i]);
    const auto exponent = json["channels"][0]["lobes"][0]["exponent"];
    ASSERT_EQ(exponent.size(), 3u);
    spread[i] = std::abs(std::log(exponent[0].get<double>() / exponent[2].get<double>()));
  }
  EXPECT_LT(spread[0], spread[1]) << "a stronger prior should keep the exponent's profile flatter";
}

}  // namespace
}  // namespace brdfbake
