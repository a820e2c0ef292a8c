// The ibl job (run/ibl_job.hpp) against values it does not compute: environments with analytic
// filtered values (a constant, 1 + l.y, max(0, l.y)), read back by ktx-parse (npm, tests/js) looking
// texels up the Vulkan way at texel centres, and by the library's own reader for DDS and EXR.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/output/baked_output.hpp>
#include <brdfbake/run/ibl_job.hpp>
#include <brdfbake/run/prefilter_job.hpp>

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <regex>

#include "node_readers.hpp"
#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;

// An equirectangular environment (docs/conventions.md: y up, row 0 the top, theta = pi v) whose
// radiance depends on l.y only, written as an OpenEXR.
fs::path zonalEnvironment(const fs::path& path, const std::function<double(double)>& radiance) {
  const int h = 128, w = 256;
  Image image(w, h, Rgba(0, 0, 0, 1));
  for (int y = 0; y < h; ++y) {
    const double v = radiance(std::cos(kPi * (y + 0.5) / h));
    for (int x = 0; x < w; ++x) image.set(x, y, Rgba(v, v, v, 1));
  }
  writeImage(image, path);
  return path;
}

// The GGX split-sum lobe about r (n = v = r): w(theta) ~ D(cos(theta / 2)) max(0, cos theta), theta
// the angle from r. Its mean cosine: what filtering 1 + b (l.e) multiplies b (r.e) by.
double ggxMeanCosine(double roughness) {
  if (roughness == 0.0) return 1.0;
  const double a2 = std::pow(roughness, 4.0);
  double mass = 0.0, first = 0.0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double t = 0.5 * kPi * (i + 0.5) / n, c = std::cos(t), h = std::cos(0.5 * t);
    const double f = h * h * (a2 - 1.0) + 1.0, w = c * std::sin(t) / (f * f);
    mass += w, first += w * c;
  }
  return first / mass;
}

IblFiles smallFiles(const fs::path& environment, const fs::path& outDir) {
  IblFiles files;
  files.environment = environment;
  files.outputs.folder = outDir;
  files.outputs.stem.clear();  // the environment's
  files.request.resolution = 16;
  files.request.irradianceResolution = 8;
  files.request.skyboxResolution = 16;
  files.request.dfgSize = 8;
  return files;
}

TEST(Ibl, AConstantEnvironmentGivesItsRadianceAtEveryLevelAndTheFilesTheirRoles) {
  test::TempDir dir;
  const fs::path env = zonalEnvironment(dir / "white.exr", [](double) { return 2.0; });
  const IblReport result = runIbl(smallFiles(env, dir / "out"));
  const nlohmann::json report = result.toJson();
  std::map<std::string, fs::path> byRole;
  for (const auto& file : report["files"]) byRole[file["role"]] = file["file"].get<std::string>();
  for (const char* role : {"specular", "irradiance", "irradiance_sh", "skybox", "dfg"}) {
    ASSERT_TRUE(byRole.count(role)) << role << "\n" << report.dump(1);
    EXPECT_TRUE(fs::exists(byRole[role])) << role;
  }
  EXPECT_EQ(byRole["specular"], dir / "out" / "white_ggx.ktx2");
  EXPECT_EQ(byRole["dfg"].extension(), ".ktx2");
  for (const fs::path& file : result.files) EXPECT_TRUE(fs::exists(file)) << file;
  EXPECT_FALSE(result.briefReport().empty());
  // Every level of the chain: the furnace's radiance 2 (the lobes are normalised), read by the library.
  for (int level = 0; level < 5; ++level) {
    const MapFile map = readMap(byRole["specular"], level);
    for (const Vec3& d : {Vec3(1, 0.2, 0.1), Vec3(-0.3, -1, 0.4), Vec3(0.1, 0.5, -1)})
      EXPECT_NEAR(sampleBilinear(map.image, *map.parameterization, d)[0], 2.0, 2e-3) << level;
    const nlohmann::json values = levelValues(map.image.metadata, level);
    EXPECT_DOUBLE_EQ(values["roughness"].get<double>(), level / 4.0) << values.dump();
  }
  // Irradiance E/pi of a constant radiance is that radiance, in the cube and the SH.
  OpenOutputOptions open;
  for (const char* role : {"irradiance", "irradiance_sh"}) {
    const BakedOutput output = BakedOutput::open(byRole[role], open);
    EXPECT_NEAR(output.lookup(Vec3(0.2, 0.9, -0.3))[0], 2.0, 2e-3) << role;
  }
}

TEST(Ibl, KtxParseReadsTheChainAsGgxOfALinearEnvironmentAtEveryLevelAndFace) {
  if (!test::haveNodePackage("ktx-parse")) GTEST_SKIP() << test::missingNodePackage("ktx-parse");
  test::TempDir dir;
  // L = 1 + l.y: filtering with a normalised lobe of mean cosine kappa gives 1 + kappa r.y exactly.
  const fs::path env = zonalEnvironment(dir / "linear.exr", [](double y) { return 1.0 + y; });
  runIbl(smallFiles(env, dir / "out"));
  const int levels = 5;
  std::vector<Vec3> directions;
  std::vector<int> levelOf;
  for (int k = 0; k < levels; ++k) {
    const int n = 16 >> k;
    for (int face = 0; face < 6; ++face)
      for (int j = 0; j < n; j += std::max(1, n / 4))
        for (int i = 0; i < n; i += std::max(1, n / 4))
          directions.push_back(test::vulkanTexelCentre(face, i, j, n)), levelOf.push_back(k);
  }
  const nlohmann::json ktx = test::inspectKtx2(dir / "out" / "linear_ggx.ktx2", directions);
  EXPECT_EQ(ktx["vkFormat"], 97);  // R16G16B16A16_SFLOAT
  EXPECT_EQ(ktx["faceCount"], 6);
  ASSERT_EQ(ktx["levelCount"], levels);
  const nlohmann::json meta = nlohmann::json::parse(ktx["keyValue"]["brdfbake.metadata"].get<std::string>());
  ASSERT_EQ(meta["level_values"].size(), static_cast<std::size_t>(levels)) << meta.dump();
  for (int k = 0; k < levels; ++k) {
    const double roughness = k / (levels - 1.0), kappa = ggxMeanCosine(roughness);
    EXPECT_DOUBLE_EQ(meta["level_values"][k]["roughness"].get<double>(), roughness);
    double worst = 0.0;
    for (std::size_t d = 0; d < directions.size(); ++d) {
      if (levelOf[d] != k) continue;
      const double expected = 1.0 + kappa * directions[d].y();
      worst = std::max(worst, std::abs(ktx["lookups"][k][d][0].get<double>() - expected));
    }
    // Absolute, against radiance from 0 to 2 (mean 1): each level is made to 1 % RMS relative error.
    EXPECT_LT(worst, 0.02) << "level " << k << " (roughness " << roughness << ")";
  }
}

TEST(Ibl, KtxParseReadsTheSkysChainAsTheReferenceSumAtEveryLevel) {
  if (!test::haveNodePackage("ktx-parse")) GTEST_SKIP() << test::missingNodePackage("ktx-parse");
  // The sample sky (a sun of radiance ~2000): each level's texels, read by ktx-parse at Vulkan texel
  // centres, against the reference sum of ggx:R_k there (brute force over every environment texel).
  test::TempDir dir;
  const fs::path sky = test::sourcePath("data_samples/environments/sky_latlong.exr");
  IblFiles options = smallFiles(sky, dir / "out");
  options.request.resolution = 32;
  runIbl(options);
  const Environment environment = loadEnvironment(sky);
  const int levels = 6;
  std::vector<Vec3> directions;
  std::vector<int> levelOf;
  for (int k = 1; k < levels; ++k) {
    const int n = 32 >> k;
    for (int face = 0; face < 6; ++face)
      for (int j = 0; j < n; j += std::max(1, n / 4))
        for (int i = 0; i < n; i += std::max(1, n / 4))
          directions.push_back(test::vulkanTexelCentre(face, i, j, n)), levelOf.push_back(k);
  }
  const nlohmann::json ktx = test::inspectKtx2(dir / "out" / "sky_latlong_ggx.ktx2", directions);
  ASSERT_EQ(ktx["levelCount"], levels);
  for (int k = 1; k < levels; ++k) {
    std::vector<Vec3> axes;
    std::vector<Rgb> values;
    for (std::size_t d = 0; d < directions.size(); ++d) {
      if (levelOf[d] != k) continue;
      axes.push_back(directions[d]);
      const auto& v = ktx["lookups"][k][d];
      values.push_back(Rgb(v[0].get<double>(), v[1].get<double>(), v[2].get<double>()));
    }
    const std::vector<Rgb> reference = prefilterReferenceAt(environment, PrefilterLobe::ggx(k / 5.0), axes);
    double sum = 0.0;
    for (std::size_t i = 0; i < axes.size(); ++i) {
      const double e = (values[i] - reference[i]).matrix().norm() / reference[i].matrix().norm();
      sum += e * e;
    }
    EXPECT_LT(std::sqrt(sum / axes.size()), 0.02) << "level " << k;  // each level is made to 1 % RMS
  }
}

TEST(Ibl, IrradianceOfACosineLobeSkyMatchesTheAnalyticValue) {
  test::TempDir dir;
  // L = max(0, l.y): E(n)/pi = (2 / (3 pi)) ((pi - g) cos g + sin g), g the angle from +y; its three
  // bands (Funk-Hecke, Legendre moments 1/2, 1/3, 1/8 of max(0, m)): 1/4 + (1/3) c + (5/64)(3c^2 - 1)/2.
  const fs::path env = zonalEnvironment(dir / "lobe.exr", [](double y) { return std::max(0.0, y); });
  IblFiles options = smallFiles(env, dir / "out");
  options.outputs.format = "exr";
  options.request.irradianceResolution = 16;
  runIbl(options);
  OpenOutputOptions open;
  const BakedOutput cube = BakedOutput::open(dir / "out" / "lobe_irradiance.exr", open);
  const BakedOutput sh = BakedOutput::open(dir / "out" / "lobe_sh.json", open);
  for (const Vec3& n : {Vec3(0, 1, 0), Vec3(0.3, 0.5, 0.2), Vec3(1, 0, 0), Vec3(0.2, -0.7, 0.5), Vec3(0, -1, 0)}) {
    const double c = n.normalized().y(), g = std::acos(c);
    const double exact = 2.0 / (3.0 * kPi) * ((kPi - g) * c + std::sin(g));
    const double bands = 0.25 + c / 3.0 + 5.0 / 64.0 * 0.5 * (3.0 * c * c - 1.0);
    EXPECT_NEAR(cube.lookup(n)[0], exact, 0.01 * (2.0 / 3.0)) << n.transpose();
    EXPECT_NEAR(sh.lookup(n)[0], bands, 2e-3) << n.transpose();
  }
}

TEST(Ibl, DdsAndFolderChoicesAndBadInputLeaveNothingBehind) {
  test::TempDir dir;
  const fs::path env = zonalEnvironment(dir / "sky.exr", [](double y) { return 1.0 + y; });
  IblFiles options = smallFiles(env, dir / "dds");
  options.outputs.format = "dds";
  options.outputs.stem = "s";
  const IblReport result = runIbl(options);
  for (const char* name : {"s_ggx.dds", "s_irradiance.dds", "s_skybox.dds", "s_dfg.dds", "s_sh.json"})
    EXPECT_TRUE(fs::exists(dir / "dds" / name)) << name;
  const MapFile top = readMap(dir / "dds" / "s_ggx.dds", 4);  // the last level, roughness 1
  EXPECT_NEAR(sampleBilinear(top.image, *top.parameterization, Vec3(0, 1, 0))[0], 1.0 + ggxMeanCosine(1.0), 0.03);

  auto expectRefused = [&](IblFiles bad, const std::string& named) {
    bad.outputs.folder = dir / "bad";
    try {
      runIbl(bad);
      ADD_FAILURE() << "no error for " << named;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(named), std::string::npos) << error.what();
    }
    EXPECT_FALSE(fs::exists(dir / "bad")) << named;  // nothing made, not even the folder
  };
  IblFiles bad = options;
  bad.outputs.format = "png";
  expectRefused(bad, "format: ");
  bad = options, bad.request.resolution = 24;
  expectRefused(bad, "resolution: ");
  bad = options, bad.request.levels = 3;
  expectRefused(bad, "levels: ");
  bad = options, bad.outputs.stem = "a/b";
  expectRefused(bad, "stem: ");
  bad = options, bad.environment = dir / "missing.exr";
  expectRefused(bad, "missing.exr");
  // Not an image: refused naming the file, before any output.
  {
    std::ofstream(dir / "junk.exr") << "not an image";
    bad = options, bad.environment = dir / "junk.exr";
    expectRefused(bad, "junk.exr");
  }
}

TEST(Ibl, CmgenShLinesFollowCmgensFormula) {
  // L = 1 + l.y: E(n)/pi = 1 + (2/3) n.y exactly, so in cmgen's formula E/pi = sh[0] + sh[1] y + sh[2] z +
  // sh[3] x + sh[4] yx + sh[5] yz + sh[6] (3z^2 - 1) + sh[7] zx + sh[8] (x^2 - y^2): sh[0] = 1, sh[1] = 2/3.
  test::TempDir dir;
  const fs::path env = zonalEnvironment(dir / "linear.exr", [](double y) { return 1.0 + y; });
  IblFiles options = smallFiles(env, dir / "out");
  options.outputs.shCmgen = true;
  const IblReport result = runIbl(options);
  std::ifstream in(dir / "out" / "linear_sh.txt");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::regex line(
      R"(\(\s*([-0-9.e]+),\s*([-0-9.e]+),\s*([-0-9.e]+)\); // L(\d)(-?\d), irradiance, pre-scaled base)");
  std::vector<double> sh;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), line); it != std::sregex_iterator(); ++it)
    sh.push_back(std::stod((*it)[1]));
  ASSERT_EQ(sh.size(), 9u) << text;
  const double expected[9] = {1.0, 2.0 / 3.0, 0, 0, 0, 0, 0, 0, 0};
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(sh[static_cast<std::size_t>(i)], expected[i], 2e-3) << i << "\n" << text;
  bool listed = false;
  const nlohmann::json report = result.toJson();
  for (const auto& file : report["files"]) listed = listed || file["role"] == "irradiance_sh_cmgen";
  EXPECT_TRUE(listed);
}

TEST(Ibl, PrefilterMakesTheGgxChainAndRefusesBadChainKeys) {
  test::TempDir dir;
  PrefilterFiles request;
  request.environment = zonalEnvironment(dir / "white.exr", [](double) { return 1.0; });
  request.request.glossChain = GlossChain{};  // ggx, every level
  request.request.parameterization = ParameterizationKind::Cube;
  request.request.resolution = 8;
  request.outputs.mipLayout = MipLayout::Tiled;
  request.outputs.files = {dir / "chain.ktx2"};
  const MapResult made = runPrefilter(request);
  ASSERT_TRUE(made.written) << made.error;
  EXPECT_EQ(made.entry["gloss_chain"]["kind"], "ggx");
  for (int level = 0; level < 4; ++level) {
    const MapFile map = readMap(dir / "chain.ktx2", level);
    EXPECT_DOUBLE_EQ(levelValues(map.image.metadata, level)["roughness"].get<double>(), level / 3.0);
    EXPECT_NEAR(sampleBilinear(map.image, *map.parameterization, Vec3(0.3, -0.2, 1))[0], 1.0, 2e-3) << level;
  }
  auto expectRefused = [&](const nlohmann::json& document, const std::string& named) {
    SpecRunOptions run;
    run.document = document;
    run.outDir = dir / "bad";
    try {
      const SpecRunResult result = runSpec(run);
      ADD_FAILURE() << "accepted: " << document.dump() << (result.firstError ? result.firstError->what() : "");
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(named), std::string::npos) << error.what();
    }
    EXPECT_FALSE(fs::exists(dir / "bad" / "x.exr")) << named;
  };
  const nlohmann::json base = {
      {"output", "x.exr"},
      {"parameterization", "cube"},
      {"resolution", 8},
      {"environment", {{"file", request.environment.string()}, {"lobe", "ggx"}, {"gloss_chain", {{"scale", 4}}}}}};
  expectRefused({{"maps", {base}}}, "gloss_chain.scale");
  nlohmann::json irradiance = base;
  irradiance["environment"] = {{"file", request.environment.string()}, {"lobe", "irradiance"}, {"sh_format", "cmgen"}};
  expectRefused({{"maps", {irradiance}}}, "sh_format");
  irradiance["environment"]["sh_output"] = "sh.json";
  expectRefused({{"maps", {irradiance}}}, "sh_output");  // cmgen's lines go to a .txt
  irradiance["environment"]["sh_format"] = "spherical";
  expectRefused({{"maps", {irradiance}}}, "sh_format");
  request.request.lobeModel =
      std::make_shared<const LobeModel>(readFitFile(test::sourcePath("data_samples/fits/synthetic_two_lobes.json"))
                                            .fit.model);  // a chain sets every level's lobe
  try {
    runPrefilter(request);
    ADD_FAILURE() << "fitted lobes beside the chain were accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("lobe"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace brdfbake
