// `brdfbake prefilter` and prefiltered maps in specs, as a user meets them: outputs checked against
// the library's reference sum, metadata, exit codes for bad flags and bad environments.
#include <gtest/gtest.h>
#include <brdfbake/brdf/fresnel.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/maps/image_io.hpp>
#include <brdfbake/maps/map_file.hpp>
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

TEST(PrefilterCli, GlossyParaboloidWithMipsMatchesTheReferenceAndRecordsItself) {
  test::TempDir dir;
  const fs::path out = dir / "glossy.exr";
  const auto result =
      runCli("prefilter " + q(kSky) + " --lobe phong:50 --to paraboloid --resolution 32 --mips --json -o " + q(out));
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const auto report = nlohmann::json::parse(result.out);
  // The map's entry, as bake --json prints it: the prefilter's summary under "prefilter".
  EXPECT_EQ(report["status"], "written");
  EXPECT_EQ(report["prefilter"]["lobe"], "phong:50");
  EXPECT_TRUE(report["prefilter"]["error_estimated"].get<bool>());
  EXPECT_LT(report["prefilter"]["error_estimate"].get<double>(), 0.01);
  EXPECT_GT(report["prefilter"]["filter_seconds"].get<double>(), 0.0);
  EXPECT_GT(report["write_seconds"].get<double>(), 0.0);
  EXPECT_EQ(report["environment"]["parameterization"], "latlong");  // from the 2:1 aspect ratio
  ASSERT_EQ(report["files"].size(), 6u);                            // 32, 16, 8, 4, 2, 1 texels
  EXPECT_TRUE(fs::exists(dir / "glossy_mip5.exr"));

  // The map against the reference sum at texel centres of the front hemisphere (texel (8, 8) etc).
  const Environment sky = loadEnvironment(kSky);
  const auto lobe = PrefilterLobe::phong(50);
  std::vector<Vec3> axes;
  const auto map = makeParameterization(ParameterizationKind::Paraboloid, 32);
  for (const Vec2& p : {Vec2(8.5, 8.5), Vec2(16.5, 16.5), Vec2(20.5, 10.5), Vec2(40.5, 12.5), Vec2(50.5, 20.5)})
    axes.push_back(*map->getDirectionFor(p));
  const auto reference = prefilterReferenceAt(sky, lobe, axes);
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const Rgb value = sampleMap(out, axes[i]);
    EXPECT_LT((value - reference[i]).matrix().norm() / reference[i].matrix().norm(), 0.03) << axes[i].transpose();
  }

  const auto info = runCli("info " + q(dir / "glossy_mip2.exr") + " --json");
  ASSERT_EQ(info.exitCode, 0) << info.output;
  const auto metadata = nlohmann::json::parse(info.out)["metadata"];
  EXPECT_EQ(metadata["resolution"], 8);
  EXPECT_EQ(metadata["spec"]["environment"]["file"], kSky);
  EXPECT_EQ(metadata["spec"]["prefilter"]["lobe"], "phong:50");
  EXPECT_EQ(metadata["spec"]["prefilter"]["max_error"], 0.01);
  EXPECT_EQ(metadata["spec"]["prefilter"]["mip_level"], 2);
}

TEST(PrefilterCli, GlossChainWritesOneLevelPerExponentEachMatchingTheReference) {
  // --gloss-scale 6 --gloss-bias 1 --mip-count 3: exponents 2^7 = 128, 2^4 = 16, 2^1 = 2 (cmft's
  // mapping worked by hand) at 16, 8 and 4 texels per face; each level's texel against the
  // reference sum with its own exponent.
  test::TempDir dir;
  const fs::path out = dir / "chain.exr";
  const auto result = runCli("prefilter " + q(kSky) +
                             " --lobe phong --gloss-scale 6 --gloss-bias 1 --mip-count 3 --to cube "
                             "--resolution 16 --no-edge-fixup --json -o " +
                             q(out));
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const auto report = nlohmann::json::parse(result.out);
  ASSERT_EQ(report["gloss_chain"]["levels"].size(), 3u);
  EXPECT_EQ(report["gloss_chain"]["levels"][0]["lobe"], "phong:128");
  EXPECT_EQ(report["gloss_chain"]["levels"][1]["lobe"], "phong:16");
  EXPECT_EQ(report["gloss_chain"]["levels"][2]["lobe"], "phong:2");
  EXPECT_EQ(report["files"].size(), 3u);
  EXPECT_FALSE(fs::exists(dir / "chain_mip3.exr"));
  const Environment sky = loadEnvironment(kSky);
  const double exponents[3] = {128.0, 16.0, 2.0};
  for (int level = 0; level < 3; ++level) {
    const fs::path file = level == 0 ? out : dir / ("chain_mip" + std::to_string(level) + ".exr");
    const MapFile map = readMap(file);
    const auto cube = makeParameterization(ParameterizationKind::Cube, 16 >> level);
    ASSERT_EQ(map.image.width(), cube->width());
    // Texel centres on the +z face's middle row and one near a corner of the +y face.
    std::vector<Vec2> texels{Vec2(cube->width() / 2 + 0.5, cube->height() / 2 + 0.5),
                             Vec2(cube->width() / 4 + 0.5, 0.5)};
    for (const Vec2& t : texels) {
      const auto axis = cube->getDirectionFor(t);
      if (!axis) continue;
      const Rgb reference = prefilterReferenceAt(sky, PrefilterLobe::phong(exponents[level]), {*axis})[0];
      const Rgb value = map.image.at(static_cast<int>(t.x()), static_cast<int>(t.y())).head<3>();
      EXPECT_LT((value - reference).matrix().norm() / reference.matrix().norm(), 0.03)
          << "level " << level << " " << axis->transpose();
    }
  }
  // Bad combinations name the flag.
  EXPECT_EQ(
      runCli("prefilter " + q(kSky) + " --lobe phong:10 --gloss-scale 6 --to cube -o " + q(dir / "x.exr")).exitCode, 2);
  const auto mips =
      runCli("prefilter " + q(kSky) + " --lobe phong --gloss-scale 6 --mips --to cube -o " + q(dir / "x.exr"));
  EXPECT_EQ(mips.exitCode, 2);
  EXPECT_NE(mips.output.find("--gloss-scale"), std::string::npos) << mips.output;
}

TEST(PrefilterCli, FurnaceIrradianceIsPi) {
  test::TempDir dir;
  for (const char* to : {"sphere", "cube", "latlong"}) {
    const fs::path out = dir / (std::string("furnace_") + to + ".exr");
    const auto result =
        runCli("prefilter " + q(kFurnace) + " --lobe irradiance --to " + to + " --resolution 8 --quiet -o " + q(out));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    EXPECT_TRUE(result.output.empty()) << result.output;
    for (const Vec3& d : {Vec3(0, 0, 1), Vec3(0.3, -0.8, 0.2).normalized(), Vec3(1, 1, 1).normalized()}) {
      EXPECT_NEAR(sampleMap(out, d)[1], kPi, 1e-3 * kPi) << to;
    }
  }
}

TEST(PrefilterCli, SpecsBakeEnvironmentMaps) {
  test::TempDir dir;
  const auto result = runCli("bake " + q(test::sourcePath("data_samples/specs/prefilter_sky.json")) + " --out-dir " +
                             q(dir.path()) + " --json");
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const auto report = nlohmann::json::parse(result.out);
  ASSERT_EQ(report["maps"].size(), 4u);
  for (const auto& map : report["maps"]) {
    EXPECT_TRUE(fs::exists(map["output"].get<std::string>())) << map.dump();
    EXPECT_EQ(map["bake_path"].get<std::string>().rfind("prefilter:", 0), 0u);
    EXPECT_LE(map["prefilter"]["error_estimate"].is_null() ? 0.0 : map["prefilter"]["error_estimate"].get<double>(),
              0.01);
  }
  // Mirror sphere map of the coloured cube: the centre reflects +z, the blue face.
  const Rgb centre = sampleMap(dir / "colored_cube_mirror_sphere.exr", Vec3(0, 0, 1));
  EXPECT_LT((centre - Rgb(0, 0, 1)).abs().maxCoeff(), 1e-3) << centre.transpose();

  // Environment and material together: exit 2, the JSON path named, nothing written.
  const fs::path bad = dir / "bad.json";
  std::ofstream(bad) << R"({"maps": [{"output": "x.exr", "parameterization": "sphere", "resolution": 8,
      "environment": {"file": ")"
                     << kSky << R"(", "lobe": "phong:10"},
      "material": {"model": "phong", "exponent": 5}}]})";
  const auto refused = runCli("bake " + q(bad));
  EXPECT_EQ(refused.exitCode, 2) << refused.output;
  EXPECT_NE(refused.output.find("maps[0].material"), std::string::npos) << refused.output;
  std::ofstream(bad) << R"({"maps": [{"output": "x.exr", "parameterization": "sphere", "resolution": 8,
      "environment": {"file": ")"
                     << kSky << R"(", "lobe": "phong:-1"}}]})";
  const auto badLobe = runCli("bake " + q(bad));
  EXPECT_EQ(badLobe.exitCode, 2) << badLobe.output;
  EXPECT_NE(badLobe.output.find("maps[0].environment.lobe"), std::string::npos) << badLobe.output;
  EXPECT_FALSE(fs::exists(dir / "x.exr"));
}

TEST(PrefilterCli, FittedLobesFromAFitFile) {
  test::TempDir dir;
  FitFile fit;
  for (const char* name : {"R", "G", "B"}) {
    LobeChannel channel;
    channel.name = name;
    channel.lobes.push_back({{0.5}, {40.0}});
    fit.fit.model.channels.push_back(channel);
  }
  writeFitFile(dir / "fit.json", fit);
  const fs::path out = dir / "fitted.exr";
  const auto result = runCli("prefilter " + q(kFurnace) + " --lobe lobes:" + q(dir / "fit.json") +
                             " --to cube --resolution 4 --json -o " + q(out));
  ASSERT_EQ(result.exitCode, 0) << result.output;
  // Furnace: C (n + 2)/(n + 1) per channel.
  EXPECT_NEAR(sampleMap(out, Vec3(0.2, 0.3, -1).normalized())[0], 0.5 * 42.0 / 41.0, 1e-3);
  // --elevations is for varying models only.
  const auto constantStack = runCli("prefilter " + q(kFurnace) + " --lobe lobes:" + q(dir / "fit.json") +
                                    " --to cube --resolution 4 --elevations 4 -o " + q(dir / "c.exr"));
  EXPECT_EQ(constantStack.exitCode, 2) << constantStack.output;
  EXPECT_NE(constantStack.output.find("--elevations"), std::string::npos) << constantStack.output;

  // A varying model makes a stack of maps over elevation: STEM_elev0.EXT ..., each recording its
  // elevation; on the furnace slice j holds C(u_j) (n(u_j) + 2)/(n(u_j) + 1).
  fit.fit.model.elevation = LobeElevation::Varying;
  fit.fit.model.minCos = 0.25;
  for (auto& channel : fit.fit.model.channels) channel.lobes[0] = {{0.5, 0.3, 0.2}, {40.0, 20.0, 10.0}};
  writeFitFile(dir / "varying.json", fit);
  const fs::path stack = dir / "v.exr";
  const auto varying = runCli("prefilter " + q(kFurnace) + " --lobe lobes:" + q(dir / "varying.json") +
                              " --to latlong --resolution 4 --elevations 3 --json -o " + q(stack));
  ASSERT_EQ(varying.exitCode, 0) << varying.output;
  const auto report = nlohmann::json::parse(varying.out);
  ASSERT_EQ(report["files"].size(), 3u);
  ASSERT_EQ(report["elevations"]["slices"], 3);
  EXPECT_FALSE(fs::exists(stack));
  for (int j = 0; j < 3; ++j) {
    const fs::path slice = dir / ("v_elev" + std::to_string(j) + ".exr");
    const double u = report["elevations"]["cos_theta"][j].get<double>();
    EXPECT_NEAR(u, 0.25 * std::pow(4.0, j / 2.0), 1e-12);
    const double c = fit.fit.model.weight(0, 0, u), n = fit.fit.model.exponent(0, 0, u);
    EXPECT_NEAR(sampleMap(slice, Vec3(0.2, 0.3, -1).normalized())[0], c * (n + 2.0) / (n + 1.0), 1e-3) << j;
    const auto info = runCli("info " + q(slice) + " --json");
    ASSERT_EQ(info.exitCode, 0) << info.output;
    const auto elevation = nlohmann::json::parse(info.out)["metadata"]["spec"]["prefilter"]["elevation"];
    EXPECT_EQ(elevation["slice"], j);
    EXPECT_NEAR(elevation["cos_theta"].get<double>(), u, 1e-15);
  }
  // Bad slice counts: exit 2 naming the flag.
  for (const char* bad : {"1", "0", "65", "x"}) {
    const auto refused = runCli("prefilter " + q(kFurnace) + " --lobe lobes:" + q(dir / "varying.json") +
                                " --to cube --elevations " + bad + " -o " + q(dir / "w.exr"));
    EXPECT_EQ(refused.exitCode, 2) << bad << ": " << refused.output;
    EXPECT_NE(refused.output.find("--elevations"), std::string::npos) << refused.output;
  }
  EXPECT_FALSE(fs::exists(dir / "w_elev0.exr"));
}

TEST(PrefilterCli, FresnelDecompositionWritesThreeFilesAndSaysHowToCombineThem) {
  test::TempDir dir;
  const fs::path out = dir / "coat.exr";
  const auto result =
      runCli("prefilter " + q(kFurnace) +
             " --lobe mirror --fresnel-ior 1.5 --combine mix --to latlong --resolution 8 --json -o " + q(out));
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const auto report = nlohmann::json::parse(result.out);
  ASSERT_EQ(report["files"].size(), 3u);
  EXPECT_EQ(report["fresnel"]["combine"], "mix");
  EXPECT_EQ(report["fresnel"]["irradiance_prefilter"]["lobe"], "irradiance");
  // Furnace: specular 1, irradiance pi; the profile is the dielectric formula at texel centres.
  const Vec3 d = Vec3(0.3, -0.8, 0.2).normalized();
  EXPECT_NEAR(sampleMap(out, d)[0], 1.0, 1e-3);
  EXPECT_NEAR(sampleMap(dir / "coat_irradiance.exr", d)[0], kPi, 1e-3 * kPi);
  const Image table = readImage(dir / "coat_fresnel.exr");
  ASSERT_EQ(table.width(), 8);
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(table.at(i, 0)[0], fresnelDielectric((i + 0.5) / 8.0, 1.5), 1e-6) << i;
  for (const char* file : {"coat.exr", "coat_irradiance.exr"}) {
    const auto info = runCli("info " + q(dir / file) + " --json");
    ASSERT_EQ(info.exitCode, 0) << info.output;
    const auto fresnel = nlohmann::json::parse(info.out)["metadata"]["spec"]["prefilter"]["fresnel"];
    EXPECT_EQ(fresnel["combine"], "mix") << file;
    EXPECT_EQ(fresnel["table"], "coat_fresnel.exr") << file;
    EXPECT_NE(fresnel["formula"].get<std::string>().find("(1 - F(n.v))"), std::string::npos) << file;
  }
  // Refused: an irradiance lobe, --combine alone, a bad combine, a non-positive index.
  for (const std::string& flags :
       std::vector<std::string>{"--lobe irradiance --fresnel-ior 1.5", "--lobe mirror --combine mix",
                                "--lobe mirror --fresnel-ior 1.5 --combine over", "--lobe mirror --fresnel-ior -2"}) {
    const auto refused = runCli("prefilter " + q(kFurnace) + " " + flags + " --to cube -o " + q(dir / "bad.exr"));
    EXPECT_EQ(refused.exitCode, 2) << flags << ": " << refused.output;
    EXPECT_TRUE(refused.output.find("--fresnel-ior") != std::string::npos ||
                refused.output.find("--combine") != std::string::npos)
        << refused.output;
  }
  EXPECT_FALSE(fs::exists(dir / "bad.exr"));
  EXPECT_FALSE(fs::exists(dir / "bad_irradiance.exr"));
}

TEST(PrefilterCli, SpecsMakeStacksAndFresnelDecompositions) {
  test::TempDir dir;
  const auto result = runCli("bake " + q(test::sourcePath("data_samples/specs/prefilter_decomposition.json")) +
                             " --out-dir " + q(dir.path()) + " --json");
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const auto report = nlohmann::json::parse(result.out);
  ASSERT_EQ(report["maps"].size(), 2u);
  for (const auto& map : report["maps"]) {
    for (const auto& file : map["files"]) EXPECT_TRUE(fs::exists(file.get<std::string>())) << file;
  }
  EXPECT_EQ(report["maps"][0]["elevations"]["slices"], 8);
  EXPECT_EQ(report["maps"][0]["files"].size(), 8u);
  EXPECT_EQ(report["maps"][1]["fresnel"]["combine"], "mix");
  EXPECT_EQ(report["maps"][1]["files"].size(), 3u);

  // Bad keys name their JSON path; nothing is written.
  const fs::path bad = dir / "bad.json";
  const std::string fit = test::sourcePath("data_samples/fits/synthetic_varying.json");
  const std::vector<std::pair<std::string, std::string>> cases{
      {R"("lobe": "lobes:)" + fit + R"(", "elevations": 1)", "maps[0].environment.elevations: must be in [2, 64]"},
      {R"("lobe": "lobes:)" + fit + R"(", "elevations": 4.5)", "maps[0].environment.elevations: must be an integer"},
      {R"("lobe": "phong:10", "elevations": 4)", "maps[0].environment.elevations: only lobe models that vary"},
      {R"("lobe": "irradiance", "fresnel": {"ior": 1.5})",
       "maps[0].environment.fresnel: a Fresnel decomposition needs a specular lobe"},
      {R"("lobe": "mirror", "combine": "mix")", "maps[0].environment.combine: needs \"fresnel\""},
      {R"("lobe": "mirror", "fresnel": {"ior": 1.5}, "combine": "over")", "maps[0].environment.combine"},
      {R"("lobe": "mirror", "fresnel": {"ior": -1.5})", "maps[0].environment.fresnel.ior"}};
  for (const auto& [keys, expected] : cases) {
    std::ofstream(bad) << R"({"maps": [{"output": "x.exr", "parameterization": "sphere", "resolution": 8,
        "environment": {"file": ")"
                       << kSky << R"(", )" << keys << "}}]}";
    const auto refused = runCli("bake " + q(bad));
    EXPECT_EQ(refused.exitCode, 2) << keys << ": " << refused.output;
    EXPECT_NE(refused.output.find(expected), std::string::npos) << keys << ": " << refused.output;
  }
  EXPECT_FALSE(fs::exists(dir / "x.exr"));
  EXPECT_FALSE(fs::exists(dir / "x_elev0.exr"));
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
