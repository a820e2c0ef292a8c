// `brdfbake sample` as a user meets it: --dirs prints one line per direction, errors name FILE:LINE
// and the flags. Reading every output back is tested through the library (tests/run/test_run_outputs.cpp).
#include <gtest/gtest.h>
#include <brdfbake/core/math.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/io/image_io.hpp>

#include <nlohmann/json.hpp>

#include <fstream>
#include <random>
#include <sstream>

#include "test_support.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
using test::q;
using test::runCli;

const std::string kFurnace = test::sourcePath("data_samples/environments/furnace_latlong.exr");
const std::string kVaryingFit = test::sourcePath("data_samples/fits/synthetic_varying.json");

// What sample, info, convert and preview read back from every kind of output is tested through
// the library (tests/run/test_run_outputs.cpp); here the tool: --dirs output and the flags named
// in refusals.
TEST(ReadOutputs, NDotVFlagsAreNamedWhereTheyAreMissingOrNotUsed) {
  test::TempDir dir;
  ASSERT_EQ(runCli("prefilter " + q(kFurnace) + " --lobe lobes:" + q(kVaryingFit) +
                   " --to latlong --resolution 4 --elevations 2 --quiet -o " + q(dir / "v.exr"))
                .exitCode,
            0);
  ASSERT_EQ(runCli("prefilter " + q(kFurnace) +
                   " --lobe mirror --fresnel-ior 1.5 --to latlong --resolution 4 --quiet -o " + q(dir / "m.exr"))
                .exitCode,
            0);
  const auto noCos = runCli("sample " + q(dir / "v.exr") + " --dir 0,0,1");
  EXPECT_EQ(noCos.exitCode, 2);
  EXPECT_NE(noCos.output.find("--cos-view"), std::string::npos) << noCos.output;
  const auto mapCos = runCli("sample " + q(dir / "m.exr") + " --dir 0,0,1 --cos-view 0.5");
  EXPECT_EQ(mapCos.exitCode, 2);
  EXPECT_NE(mapCos.output.find("--cos-view"), std::string::npos) << mapCos.output;
  const auto withDir = runCli("sample " + q(dir / "m_fresnel.exr") + " --cos-view 0.5 --dir 0,0,1");
  EXPECT_EQ(withDir.exitCode, 2);
  EXPECT_NE(withDir.output.find("n.v alone"), std::string::npos) << withDir.output;
  const auto tooDeep = runCli("sample " + q(dir / "m.exr") + " --mip-level 4 --dir 0,0,1");
  EXPECT_NE(tooDeep.exitCode, 0);
  EXPECT_NE(tooDeep.output.find("m_mip4"), std::string::npos) << tooDeep.output;
}

// --dirs: one line per direction in the format of --dir, errors naming FILE:LINE.
TEST(ReadOutputs, DirectionsFileGivesOneLinePerDirectionAndNamesBadLines) {
  test::TempDir dir;
  ASSERT_EQ(
      runCli("prefilter " + q(kFurnace) + " --lobe mirror --to latlong --resolution 8 --quiet -o " + q(dir / "m.exr"))
          .exitCode,
      0);
  std::ofstream(dir / "good.txt") << "# three directions\n0 0 1\n\n  1 0 0   # x\n0 2.5 -1\n";
  const auto batch = runCli("sample " + q(dir / "m.exr") + " --dirs " + q(dir / "good.txt"));
  ASSERT_EQ(batch.exitCode, 0) << batch.output;
  std::string lines;
  for (const char* d : {"0,0,1", "1,0,0", "0,2.5,-1"})
    lines += runCli("sample " + q(dir / "m.exr") + " --dir " + d).output;
  EXPECT_EQ(batch.output, lines);  // the same lines as one --dir each
  const auto json =
      nlohmann::json::parse(runCli("sample " + q(dir / "m.exr") + " --dirs " + q(dir / "good.txt") + " --json").output);
  ASSERT_TRUE(json.is_array());
  ASSERT_EQ(json.size(), 3u);
  EXPECT_EQ(json[1]["line"], 4);
  EXPECT_EQ(json[2]["direction"], nlohmann::json({0.0, 2.5, -1.0}));
  EXPECT_NEAR(json[0]["value"][0].get<double>(), 1.0, 1e-4);  // the furnace is 1 everywhere

  for (const auto& [text, message] : std::vector<std::pair<std::string, std::string>>{
           {"0 0 1\n1 x 0\n", "bad.txt:2: 'x' is not a finite number"},
           {"0 0 1\n\n1 0\n", "bad.txt:3: expected three numbers"},
           {"# only\n0 0 0\n", "bad.txt:2: the direction must be non-zero"},
           {"1 2 3 4\n", "bad.txt:1: expected three numbers"},
           {"# nothing\n\n", "bad.txt: no directions"}}) {
    std::ofstream(dir / "bad.txt") << text;
    const auto refused = runCli("sample " + q(dir / "m.exr") + " --dirs " + q(dir / "bad.txt"));
    EXPECT_EQ(refused.exitCode, 2) << text << refused.output;
    EXPECT_NE(refused.output.find(message), std::string::npos) << refused.output;
  }
  const auto both = runCli("sample " + q(dir / "m.exr") + " --dir 0,0,1 --dirs " + q(dir / "good.txt"));
  EXPECT_EQ(both.exitCode, 2) << both.output;
  const auto missing = runCli("sample " + q(dir / "m.exr") + " --dirs " + q(dir / "none.txt"));
  EXPECT_NE(missing.exitCode, 0);
  EXPECT_NE(missing.output.find("none.txt"), std::string::npos) << missing.output;
}

}  // namespace
}  // namespace brdfbake
