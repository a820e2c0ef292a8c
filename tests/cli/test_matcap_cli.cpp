// `brdfbake matcap` as a user meets it: a PNG whose top is the bright top of the sky (read back by
// OpenImageIO, not by brdfbake), --json's error report, and bad flags and files refused with exit 2
// and nothing written.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::q;
using test::runCli;

const std::string kSky = test::sourcePath("data_samples/environments/sky_latlong.exr");

// `brdfbake matcap` of a white Lambertian sphere (albedo 0.8) under the sample sky into dir/white.png,
// 64 x 64, with `flags` added.
test::CommandResult matcapOfWhiteSphere(const test::TempDir& dir, const std::string& flags) {
  std::ofstream(dir / "white.json") << R"({"model": "phong", "diffuse": [0.8, 0.8, 0.8], "specular": [0, 0, 0],
                                           "exponent": 1})";
  return runCli("matcap " + q(dir / "white.json") + " " + q(kSky) + " --resolution 64 --samples-per-texel 4 " +
                "--threads 2 " + flags + " -o " + q(dir / "white.png"));
}

TEST(MatcapCli, APngShowsTheSkysBrightTopAtTheTop) {
  test::TempDir dir;
  // A white Lambertian sphere under the sky: brighter where it faces the zenith (+y, up).
  const auto result = matcapOfWhiteSphere(dir, "--json");
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const auto entry = nlohmann::json::parse(result.out);
  EXPECT_EQ(entry["status"], "written");
  EXPECT_EQ(entry["parameterization"], "sphere");
  EXPECT_LT(entry["under_environment"]["error_estimate"].get<double>(), 0.01);
  EXPECT_NE(entry["under_environment"]["error_metric"].get<std::string>().find("relative to the peak"),
            std::string::npos);

  auto in = OIIO::ImageInput::open((dir / "white.png").string());
  ASSERT_TRUE(in);
  const OIIO::ImageSpec& spec = in->spec();
  ASSERT_EQ(spec.width, 64);
  ASSERT_EQ(spec.height, 64);
  std::vector<float> pixels(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
  ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()));
  in->close();
  // Rows 8 and 55 through the middle column: the normals (0, +-0.73, 0.68).
  auto at = [&](int x, int y) { return pixels[(static_cast<std::size_t>(y) * spec.width + x) * spec.nchannels + 1]; };
  EXPECT_GT(at(32, 8), at(32, 55) + 0.1) << "top " << at(32, 8) << ", bottom " << at(32, 55);
}

TEST(MatcapCli, APngIsExposedSoItsBrightestPercentIsWhite) {
  // --exposure auto, the default for .png: the 99th percentile of the disc's brightest channel at
  // white, so about 1 % of the disc's texels saturate at 255; the stops are recorded in the file.
  test::TempDir dir;
  const auto result = matcapOfWhiteSphere(dir, "");
  ASSERT_EQ(result.exitCode, 0) << result.output;
  EXPECT_NE(result.out.find("(auto: the 99th percentile of the map at white)"), std::string::npos) << result.out;
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // the bytes as stored, not multiplied by alpha
  auto in = OIIO::ImageInput::open((dir / "white.png").string(), &config);
  ASSERT_TRUE(in);
  const OIIO::ImageSpec spec = in->spec();
  ASSERT_EQ(spec.nchannels, 4);
  std::vector<unsigned char> pixels(static_cast<std::size_t>(spec.width) * spec.height * 4);
  ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, pixels.data()));
  int disc = 0, white = 0;
  for (std::size_t i = 0; i < pixels.size(); i += 4) {
    if (pixels[i + 3] == 0) continue;
    ++disc;
    white += std::max({pixels[i], pixels[i + 1], pixels[i + 2]}) == 255;
  }
  ASSERT_GT(disc, 3000);  // pi 32^2 = 3217 texels of the 64 x 64 picture
  EXPECT_GE(white, disc / 200) << white << " of " << disc;
  EXPECT_LE(white, disc / 40) << white << " of " << disc;
  const auto metadata = nlohmann::json::parse(spec.get_string_attribute("brdfbake:metadata", "{}"));
  ASSERT_TRUE(metadata["spec"].contains("exposure")) << metadata.dump();
  EXPECT_LT(std::abs(metadata["spec"]["exposure"].get<double>()), 30.0);
}

TEST(MatcapCli, BadFlagsAndFilesExitTwoNamingThemAndWriteNothing) {
  test::TempDir dir;
  std::ofstream(dir / "phong.json") << R"({"model": "phong", "specular": [1, 1, 1], "exponent": 20})";
  const fs::path out = dir / "out";
  fs::create_directories(out);
  const std::string output = " -o " + q(out / "m.exr") + " --resolution 16";
  auto bad = runCli("matcap " + q(dir / "phong.json") + " " + q(kSky) + " --camera 10" + output);
  EXPECT_EQ(bad.exitCode, 2) << bad.output;
  EXPECT_NE(bad.err.find("--camera"), std::string::npos) << bad.err;
  bad = runCli("matcap " + q(dir / "phong.json") + " " + q(kSky) + " --camera 0,95" + output);
  EXPECT_EQ(bad.exitCode, 2) << bad.output;
  EXPECT_NE(bad.err.find("--camera"), std::string::npos) << bad.err;
  bad = runCli("matcap " + q(dir / "missing.json") + " " + q(kSky) + output);
  EXPECT_NE(bad.exitCode, 0) << bad.output;
  EXPECT_NE(bad.err.find("missing.json"), std::string::npos) << bad.err;
  std::ofstream(dir / "gooch.json") << R"({"model": "gooch"})";
  bad = runCli("matcap " + q(dir / "gooch.json") + " " + q(kSky) + output);
  EXPECT_EQ(bad.exitCode, 2) << bad.output;
  EXPECT_NE(bad.err.find("gooch.json"), std::string::npos) << bad.err;
  bad = runCli("matcap " + q(dir / "phong.json") + " " + q(dir / "nowhere.exr") + output);
  EXPECT_NE(bad.exitCode, 0) << bad.output;
  EXPECT_NE(bad.err.find("ENVIRONMENT"), std::string::npos) << bad.err;
  EXPECT_TRUE(test::filesIn(out).empty());
}

}  // namespace
}  // namespace brdfbake
