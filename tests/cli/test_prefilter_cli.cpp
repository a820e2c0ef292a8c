// `brdfbake prefilter` as a user meets it: an end-to-end run, exit codes and messages naming the
// flags for bad flags and bad environments.
#include <gtest/gtest.h>
#include <brdfbake/brdf/fresnel.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/map_file.hpp>
#include <nlohmann/json.hpp>

#include <OpenImageIO/imageio.h>

#include <fstream>

#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::runCli;

using test::q;

const std::string kSky = test::sourcePath("data_samples/environments/sky_latlong.exr");
const std::string kFurnace = test::sourcePath("data_samples/environments/furnace_latlong.exr");

Rgb sampleMap(const fs::path& map, const Vec3& d) {
  std::ostringstream dir;
  dir.precision(17);
  dir << d.x() << "," << d.y() << "," << d.z();
  const auto result = runCli("sample " + q(map) + " --json --dir " + dir.str());
  EXPECT_EQ(result.exitCode, 0) << result.output;
  const auto value = nlohmann::json::parse(result.out)["value"];
  return {value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
}

// What prefiltering computes is tested through the library (tests/run/test_run_prefilter.cpp);
// here the tool: one end-to-end run, and refusals that name the flags (the library names the
// spec keys they stand for).
TEST(PrefilterCli, FurnaceIrradianceIsOneEndToEnd) {
  test::TempDir dir;
  const fs::path out = dir / "furnace_cube.exr";
  const auto result =
      runCli("prefilter " + q(kFurnace) + " --lobe irradiance --to cube --resolution 8 --quiet -o " + q(out));
  ASSERT_EQ(result.exitCode, 0) << result.output;
  EXPECT_TRUE(result.output.empty()) << result.output;
  for (const Vec3& d : {Vec3(0, 0, 1), Vec3(0.3, -0.8, 0.2).normalized()})
    EXPECT_NEAR(sampleMap(out, d)[1], 1.0, 1e-3);  // E/pi
}

TEST(PrefilterCli, RefusalsNameTheFlags) {
  test::TempDir dir;
  // Gloss chains.
  EXPECT_EQ(
      runCli("prefilter " + q(kSky) + " --lobe phong:10 --gloss-scale 6 --to cube -o " + q(dir / "x.exr")).exitCode, 2);
  const auto mips =
      runCli("prefilter " + q(kSky) + " --lobe phong --gloss-scale 6 --mips --to cube -o " + q(dir / "x.exr"));
  EXPECT_EQ(mips.exitCode, 2);
  EXPECT_NE(mips.output.find("--gloss-scale"), std::string::npos) << mips.output;
  // Elevation stacks: for varying models only, 2 to 64 slices.
  FitFile fit;
  for (const char* name : {"R", "G", "B"}) {
    LobeChannel channel;
    channel.name = name;
    channel.lobes.push_back({{0.5}, {40.0}});
    fit.fit.model.channels.push_back(channel);
  }
  writeFitFile(dir / "fit.json", fit);
  const auto constantStack = runCli("prefilter " + q(kFurnace) + " --lobe lobes:" + q(dir / "fit.json") +
                                    " --to cube --resolution 4 --elevations 4 -o " + q(dir / "c.exr"));
  EXPECT_EQ(constantStack.exitCode, 2) << constantStack.output;
  EXPECT_NE(constantStack.output.find("--elevations"), std::string::npos) << constantStack.output;
  fit.fit.model.elevation = LobeElevation::Varying;
  fit.fit.model.minCos = 0.25;
  for (auto& channel : fit.fit.model.channels) channel.lobes[0] = {{0.5, 0.3, 0.2}, {40.0, 20.0, 10.0}};
  writeFitFile(dir / "varying.json", fit);
  for (const char* bad : {"1", "0", "65", "x"}) {
    const auto refused = runCli("prefilter " + q(kFurnace) + " --lobe lobes:" + q(dir / "varying.json") +
                                " --to cube --elevations " + bad + " -o " + q(dir / "w.exr"));
    EXPECT_EQ(refused.exitCode, 2) << bad << ": " << refused.output;
    EXPECT_NE(refused.output.find("--elevations"), std::string::npos) << refused.output;
  }
  // Fresnel decompositions: an irradiance lobe, --combine alone, a bad combine, a non-positive index.
  for (const std::string& flags :
       std::vector<std::string>{"--lobe irradiance --fresnel-ior 1.5", "--lobe mirror --combine mix",
                                "--lobe mirror --fresnel-ior 1.5 --combine over", "--lobe mirror --fresnel-ior -2"}) {
    const auto refused = runCli("prefilter " + q(kFurnace) + " " + flags + " --to cube -o " + q(dir / "bad.exr"));
    EXPECT_EQ(refused.exitCode, 2) << flags << ": " << refused.output;
    EXPECT_TRUE(refused.output.find("--fresnel-ior") != std::string::npos ||
                refused.output.find("--combine") != std::string::npos)
        << refused.output;
  }
  // Tiled chains and SH outputs.
  for (const auto& [flags, message] : std::vector<std::pair<std::string, std::string>>{
           {" --lobe phong:20 --to cube --resolution 12 --mips --tiled", "power-of-two"},
           {" --lobe phong:20 --to cube --resolution 16 --tiled", "--tiled: a tiled file holds a whole mip chain"},
           {" --lobe phong:20 --to cube --resolution 8 --sh-output " + q(dir / "x.json"), "--sh-output"}}) {
    const auto refused = runCli("prefilter " + q(kSky) + flags + " -o " + q(dir / "bad.exr"));
    EXPECT_EQ(refused.exitCode, 2) << refused.output;
    EXPECT_NE(refused.output.find(message), std::string::npos) << refused.output;
  }
  for (const char* file : {"x.exr", "c.exr", "w_elev0.exr", "bad.exr", "bad_irradiance.exr"})
    EXPECT_FALSE(fs::exists(dir / file)) << file;
}

TEST(PrefilterCli, BadFlagsExitTwoAndBadEnvironmentsAreNamed) {
  test::TempDir dir;
  const std::string out = " -o " + q(dir / "out.exr");
  for (const std::string& flags : std::vector<std::string>{
           "--lobe phong:abc --to sphere", "--lobe cook --to sphere", "--lobe phong:10 --to nowhere",
           "--lobe phong:10 --to sphere --method bogus", "--lobe phong:10 --to sphere --max-error 2",
           "--lobe phong:10 --to cube --view 1,0,0", "--lobe phong:10 --to sphere --resolution 0",
           "--lobe mirror --to sphere --method sh"}) {
    const auto result = runCli("prefilter " + q(kSky) + " " + flags + out);
    EXPECT_EQ(result.exitCode, 2) << flags << ": " << result.output;
  }
  EXPECT_EQ(runCli("prefilter " + q(kSky) + " --lobe phong:10 --to sphere").exitCode, 2);  // no -o
  EXPECT_FALSE(fs::exists(dir / "out.exr"));

  // Unreadable: exit 3 naming the file.
  const auto missing = runCli("prefilter " + q(dir / "missing.exr") + " --lobe phong:10 --to sphere" + out);
  EXPECT_EQ(missing.exitCode, 3) << missing.output;
  EXPECT_NE(missing.output.find("missing.exr"), std::string::npos) << missing.output;
  // Wrong aspect ratio, and a NaN texel (written with OpenImageIO: brdfbake refuses to write one).
  auto writeExr = [&](const fs::path& path, int width, int height, bool nan) {
    std::vector<float> pixels(static_cast<std::size_t>(width) * height * 3, 1.0f);
    if (nan) pixels[3 * (2 * width + 5)] = std::nanf("");
    auto image = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(image && image->open(path.string(), OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(image->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) && image->close());
  };
  writeExr(dir / "odd.exr", 30, 20, false);
  const auto odd = runCli("prefilter " + q(dir / "odd.exr") + " --lobe phong:10 --to sphere" + out);
  EXPECT_EQ(odd.exitCode, 2) << odd.output;
  EXPECT_NE(odd.output.find("30 x 20"), std::string::npos) << odd.output;
  writeExr(dir / "nan.exr", 16, 8, true);
  const auto nan = runCli("prefilter " + q(dir / "nan.exr") + " --lobe phong:10 --to sphere" + out);
  EXPECT_EQ(nan.exitCode, 2) << nan.output;
  EXPECT_NE(nan.output.find("texel (5, 2) is NaN"), std::string::npos) << nan.output;
  EXPECT_FALSE(fs::exists(dir / "out.exr"));

  const auto help = runCli("prefilter --help");
  EXPECT_EQ(help.exitCode, 0);
  EXPECT_NE(help.output.find("irradiance"), std::string::npos);
  EXPECT_NE(help.output.find("--max-error"), std::string::npos);
}

}  // namespace
}  // namespace brdfbake

namespace brdfbake {
namespace {

// -o repeated writes one map in several formats; --texel-format names; help names the containers.
TEST(PrefilterCli, RepeatedOutputAndTexelFormatFlags) {
  test::TempDir dir;
  const auto both = runCli("prefilter " + q(kFurnace) + " --lobe irradiance --to cube --resolution 8 --quiet -o " +
                           q(dir / "f.exr") + " -o " + q(dir / "f.ktx2") + " --texel-format rg11b10f");
  ASSERT_EQ(both.exitCode, 0) << both.output;
  for (const char* file : {"f.exr", "f.ktx2"}) EXPECT_NEAR(sampleMap(dir / file, Vec3(0, 1, 0))[1], 1.0, 1e-3) << file;
  const auto unknown = runCli("prefilter " + q(kFurnace) + " --lobe irradiance --to cube -o " + q(dir / "g.ktx2") +
                              " --texel-format rgb8");
  EXPECT_EQ(unknown.exitCode, 2);
  EXPECT_NE(unknown.output.find("--texel-format: texel format must be one of rgba16f, rgba32f"), std::string::npos)
      << unknown.output;
  const auto png = runCli("prefilter " + q(kSky) + " --chain ggx --to cube --resolution 8 --tiled -o " +
                          q(dir / "c.exr") + " -o " + q(dir / "c.png"));
  EXPECT_EQ(png.exitCode, 2);
  EXPECT_NE(png.output.find("-o: " + (dir / "c.png").string() + ": a whole mip chain"), std::string::npos)
      << png.output;
  EXPECT_FALSE(fs::exists(dir / "c.exr"));  // refused before any work
  for (const char* command : {"prefilter", "matcap", "convert"}) {
    const auto help = runCli(std::string(command) + " --help");
    EXPECT_NE(help.output.find(".exr .hdr .tif .png .ktx2 .ktx .dds"), std::string::npos) << command;
    EXPECT_NE(help.output.find("rgb9e5"), std::string::npos) << command;
  }
  const auto ibl = runCli("ibl --help");
  EXPECT_NE(ibl.output.find("ktx2 (.ktx2) | ktx (.ktx) | dds (.dds) | exr (.exr)"), std::string::npos);
}

}  // namespace
}  // namespace brdfbake
