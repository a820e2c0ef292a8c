// Commands that read or write no image start without loading OpenImageIO and its ~200 libraries;
// image commands load it (through the module brdfbake_image_oiio, beside libbrdfbake_io) on first
// use, and say which file is missing when it cannot be loaded. Shared builds only: a static build
// links OpenImageIO into the tool, and these tests skip.
#include <gtest/gtest.h>
#include <brdfbake/core/math.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <vector>

#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::q;
using test::runCli;

// The command with the dynamic loader's file trace (LD_DEBUG=files, on stderr) in the output.
test::CommandResult runCliTracingLibraries(const std::string& arguments) {
  return test::run("LD_DEBUG=files " + std::string(BRDFBAKE_CLI) + " " + arguments);
}

#define BRDFBAKE_REQUIRE_IMAGE_MODULE() \
  if (std::string(BRDFBAKE_IMAGE_MODULE).empty()) GTEST_SKIP() << "static build: OpenImageIO is linked into the tool"

TEST(ImageLoading, CommandsWithoutImagesDoNotLoadOpenImageIO) {
  BRDFBAKE_REQUIRE_IMAGE_MODULE();
  test::TempDir dir;
  const std::string table = q(test::sourcePath("data_samples/tables/synthetic_two_lobes.astm"));
  const std::vector<std::string> commands = {
      "--version", "--help", "fit --help",
      "fit " + table + " --lobes 1 --held-out off --quiet -o " + q(dir / "fit.json"),
      "eval " + q(dir / "fit.json") + " --wi 0,0,1 --wo 0,0,1"};
  for (const std::string& arguments : commands) {
    SCOPED_TRACE(arguments);
    const auto result = runCliTracingLibraries(arguments);
    EXPECT_EQ(result.exitCode, 0) << result.output;
    // The trace is on (the tool's own libraries are in it), and OpenImageIO is not.
    EXPECT_NE(result.output.find("libbrdfbake_io"), std::string::npos) << "no LD_DEBUG trace:\n" << result.output;
    EXPECT_EQ(result.output.find("libOpenImageIO"), std::string::npos) << "OpenImageIO was loaded";
    EXPECT_EQ(result.output.find(BRDFBAKE_IMAGE_MODULE), std::string::npos);
  }
}

TEST(ImageLoading, ImageCommandsLoadOpenImageIOOnFirstUse) {
  BRDFBAKE_REQUIRE_IMAGE_MODULE();
  test::TempDir dir;
  const auto bake = runCliTracingLibraries("bake " + q(test::sourcePath("data_samples/specs/phong_eye.json")) +
                                           " --out-dir " + q(dir.path()) + " --quiet");
  ASSERT_EQ(bake.exitCode, 0) << bake.output;
  EXPECT_NE(bake.output.find(BRDFBAKE_IMAGE_MODULE), std::string::npos);
  EXPECT_NE(bake.output.find("libOpenImageIO"), std::string::npos);
  // The map read back: Phong with exponent 50 lit from the eye, pow(r.z, 50) at the reflected
  // direction r (docs/conventions.md), within the bilinear lookup's error.
  const Vec3 r = Vec3(0, 0.3, 1).normalized();
  const auto sample = runCli("sample " + q(dir / "phong_eye.exr") + " --json --dir 0,0.3,1");
  ASSERT_EQ(sample.exitCode, 0) << sample.output;
  EXPECT_NEAR(nlohmann::json::parse(sample.out)["value"][0].get<double>(), std::pow(r.z(), 50), 0.01);
}

TEST(ImageLoading, AMissingModuleIsNamedWhenAnImageIsNeeded) {
  BRDFBAKE_REQUIRE_IMAGE_MODULE();
  test::TempDir dir;
  ASSERT_EQ(runCli("bake " + q(test::sourcePath("data_samples/specs/phong_eye.json")) + " --out-dir " + q(dir.path()) +
                   " --quiet")
                .exitCode,
            0);
  // The tool and its libraries copied into a folder without the module, and found there first.
  const fs::path copy = dir / "copy";
  fs::create_directories(copy);
  fs::copy_file(BRDFBAKE_CLI, copy / "brdfbake");
  for (const std::string library : {BRDFBAKE_TOOL_LIBRARIES})
    fs::copy_file(library, copy / fs::path(library).filename());
  const std::string tool = "LD_LIBRARY_PATH=" + q(copy) + " " + q(copy / "brdfbake");
  const auto version = test::run(tool + " --version");
  EXPECT_EQ(version.exitCode, 0) << version.output;
  const auto info = test::run(tool + " info " + q(dir / "phong_eye.exr"));
  EXPECT_EQ(info.exitCode, 3) << info.output;  // Error(Io)
  EXPECT_NE(info.output.find("cannot load the image module " + (copy / BRDFBAKE_IMAGE_MODULE).string()),
            std::string::npos)
      << info.output;
  EXPECT_NE(info.output.find("No such file"), std::string::npos) << info.output;  // dlerror()'s reason
}

}  // namespace
}  // namespace brdfbake
