// Prefiltered environment maps made through the library (prefilterEnvironment, runSpec), as a
// renderer or a script makes them: outputs against the library's reference sum and closed forms
// (a furnace), metadata, the errors naming the spec keys. (Moved from tests/cli/test_prefilter_cli.cpp,
// which keeps what is the tool's own: flags, exit statuses, messages naming flags.)
#include <gtest/gtest.h>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/run/prefilter_job.hpp>

#include <cmath>
#include <fstream>

#include "run_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;
using test::infoOf;
using test::prefilterFiles;
using test::sampleAt;

const std::string kSky = test::sourcePath("data_samples/environments/sky_latlong.exr");
const std::string kFurnace = test::sourcePath("data_samples/environments/furnace_latlong.exr");

TEST(PrefilterJob, GlossyParaboloidWithMipsMatchesTheReferenceAndRecordsItself) {
  test::TempDir dir;
  const fs::path out = dir / "glossy.exr";
  PrefilterFiles r = prefilterFiles(kSky, "phong:50", "paraboloid", 32, out);
  r.request.mips = true;
  const MapResult result = runPrefilter(r);
  const nlohmann::json report = result.toJson();
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
    const Rgb value = sampleAt(out, axes[i]);
    EXPECT_LT((value - reference[i]).matrix().norm() / reference[i].matrix().norm(), 0.03) << axes[i].transpose();
  }

  const auto metadata = infoOf(dir / "glossy_mip2.exr")["metadata"];
  EXPECT_EQ(metadata["resolution"], 8);
  EXPECT_EQ(metadata["spec"]["environment"]["file"], "sky_latlong.exr");  // no folder of this machine
  EXPECT_EQ(metadata["spec"]["prefilter"]["lobe"], "phong:50");
  EXPECT_EQ(metadata["spec"]["prefilter"]["max_error"], 0.01);
  EXPECT_EQ(metadata["spec"]["prefilter"]["mip_level"], 2);
}

TEST(PrefilterJob, GlossChainWritesOneLevelPerExponentEachMatchingTheReference) {
  // Gloss scale 6, bias 1, 3 levels: exponents 2^7 = 128, 2^4 = 16, 2^1 = 2 (cmft's mapping
  // worked by hand) at 16, 8 and 4 texels per face; each level's texel against the reference sum
  // with its own exponent.
  test::TempDir dir;
  const fs::path out = dir / "chain.exr";
  PrefilterFiles r = prefilterFiles(kSky, "mirror", "cube", 16, out);
  r.request.glossChain = GlossChain{GlossChain::Lobe::Phong, 6, 1, 3, false};
  const nlohmann::json report = runPrefilter(r).toJson();
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
  // Bad combinations name the request's field (the tool renames it to its flag: PrefilterCli).
  PrefilterFiles mips = r;
  mips.outputs.files = {dir / "x.exr"};
  mips.request.mips = true;
  const std::string mipsMessage = test::errorOf([&] { runPrefilter(mips); });
  EXPECT_EQ(mipsMessage.rfind("gloss_chain: ", 0), 0u) << mipsMessage;
  PrefilterFiles scale = r;
  scale.outputs.files = {dir / "x.exr"};
  scale.request.glossChain->scale = 30;  // 2^31: past the largest exponent
  const std::string scaleMessage = test::errorOf([&] { runPrefilter(scale); });
  EXPECT_EQ(scaleMessage.rfind("gloss_chain: ", 0), 0u) << scaleMessage;
  EXPECT_FALSE(fs::exists(dir / "x.exr"));
}

TEST(PrefilterJob, FurnaceIrradianceIsOne) {
  test::TempDir dir;
  for (const char* to : {"sphere", "cube", "latlong"}) {
    const fs::path out = dir / (std::string("furnace_") + to + ".exr");
    EXPECT_TRUE(runPrefilter(prefilterFiles(kFurnace, "irradiance", to, 8, out)).written);
    for (const Vec3& d : {Vec3(0, 0, 1), Vec3(0.3, -0.8, 0.2).normalized(), Vec3(1, 1, 1).normalized()}) {
      EXPECT_NEAR(sampleAt(out, d)[1], 1.0, 1e-3) << to;  // E/pi
    }
  }
}

TEST(PrefilterJob, SpecsBakeEnvironmentMaps) {
  test::TempDir dir;
  const auto report = test::bakeSpec(test::sourcePath("data_samples/specs/prefilter_sky.json"), dir.path());
  ASSERT_EQ(report["maps"].size(), 4u);
  for (const auto& map : report["maps"]) {
    EXPECT_TRUE(fs::exists(map["output"].get<std::string>())) << map.dump();
    EXPECT_EQ(map["bake_path"].get<std::string>().rfind("prefilter:", 0), 0u);
    EXPECT_LE(map["prefilter"]["error_estimate"].is_null() ? 0.0 : map["prefilter"]["error_estimate"].get<double>(),
              0.01);
  }
  // Mirror sphere map of the coloured cube: the centre reflects +z, the blue face.
  const Rgb centre = sampleAt(dir / "colored_cube_mirror_sphere.exr", Vec3(0, 0, 1));
  EXPECT_LT((centre - Rgb(0, 0, 1)).abs().maxCoeff(), 1e-3) << centre.transpose();

  // A lobe and a material together (a material is lit by the environment, a lobe prefilters it
  // without one): the JSON path named, nothing written.
  const fs::path bad = dir / "bad.json";
  std::ofstream(bad) << R"({"maps": [{"output": "x.exr", "parameterization": "sphere", "resolution": 8,
      "environment": {"file": ")"
                     << kSky << R"(", "lobe": "phong:10"},
      "material": {"model": "phong", "exponent": 5}}]})";
  SpecRunOptions options;
  options.spec = bad;
  EXPECT_NE(test::errorOf([&] { runSpec(options); }).find("maps[0].environment.lobe: with a \"material\""),
            std::string::npos);
  std::ofstream(bad) << R"({"maps": [{"output": "x.exr", "parameterization": "sphere", "resolution": 8,
      "environment": {"file": ")"
                     << kSky << R"(", "lobe": "phong:-1"}}]})";
  EXPECT_NE(test::errorOf([&] { runSpec(options); }).find("maps[0].environment.lobe"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "x.exr"));
}

TEST(PrefilterJob, FittedLobesFromAFitFile) {
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
  ASSERT_TRUE(runPrefilter(prefilterFiles(kFurnace, "lobes:" + (dir / "fit.json").string(), "cube", 4, out)).written);
  // Furnace: C (n + 2)/(n + 1) per channel.
  EXPECT_NEAR(sampleAt(out, Vec3(0.2, 0.3, -1).normalized())[0], 0.5 * 42.0 / 41.0, 1e-3);
  // Elevations are for varying models only.
  PrefilterFiles constantStack =
      prefilterFiles(kFurnace, "lobes:" + (dir / "fit.json").string(), "cube", 4, dir / "c.exr");
  constantStack.request.elevations = 4;
  EXPECT_NE(test::errorOf([&] { runPrefilter(constantStack); }).find("elevations"), std::string::npos);

  // A varying model makes a stack of maps over elevation: STEM_elev0.EXT ..., each recording its
  // elevation; on the furnace slice j holds C(u_j) (n(u_j) + 2)/(n(u_j) + 1).
  fit.fit.model.elevation = LobeElevation::Varying;
  fit.fit.model.minCos = 0.25;
  for (auto& channel : fit.fit.model.channels) channel.lobes[0] = {{0.5, 0.3, 0.2}, {40.0, 20.0, 10.0}};
  writeFitFile(dir / "varying.json", fit);
  const fs::path stack = dir / "v.exr";
  PrefilterFiles varying = prefilterFiles(kFurnace, "lobes:" + (dir / "varying.json").string(), "latlong", 4, stack);
  varying.request.elevations = 3;
  const nlohmann::json report = runPrefilter(varying).toJson();
  ASSERT_EQ(report["files"].size(), 3u);
  ASSERT_EQ(report["elevations"]["slices"], 3);
  EXPECT_FALSE(fs::exists(stack));
  for (int j = 0; j < 3; ++j) {
    const fs::path slice = dir / ("v_elev" + std::to_string(j) + ".exr");
    const double u = report["elevations"]["cos_theta"][j].get<double>();
    EXPECT_NEAR(u, 0.25 * std::pow(4.0, j / 2.0), 1e-12);
    const double c = fit.fit.model.weight(0, 0, u), n = fit.fit.model.exponent(0, 0, u);
    EXPECT_NEAR(sampleAt(slice, Vec3(0.2, 0.3, -1).normalized())[0], c * (n + 2.0) / (n + 1.0), 1e-3) << j;
    const auto elevation = infoOf(slice)["metadata"]["spec"]["prefilter"]["elevation"];
    EXPECT_EQ(elevation["slice"], j);
    EXPECT_NEAR(elevation["cos_theta"].get<double>(), u, 1e-15);
  }
  // Bad slice counts name the key.
  for (int bad : {1, 0, 65}) {
    PrefilterFiles refused =
        prefilterFiles(kFurnace, "lobes:" + (dir / "varying.json").string(), "cube", 4, dir / "w.exr");
    refused.request.elevations = bad;
    EXPECT_NE(test::errorOf([&] { runPrefilter(refused); }).find("elevations"), std::string::npos) << bad;
  }
  EXPECT_FALSE(fs::exists(dir / "w_elev0.exr"));
}

// The unpolarised Fresnel reflectance of a dielectric of relative index eta at cos theta = c
// (Cook & Torrance 1982 Eq. 9; Heidrich 2000 Eq. 13), typed out.
double fresnelFormula(double c, double eta) {
  const double g = std::sqrt(eta * eta + c * c - 1.0);
  const double a = (g - c) / (g + c), b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
  return 0.5 * a * a * (1.0 + b * b);
}

TEST(PrefilterJob, FresnelDecompositionHoldsTheSpecularTheIrradianceAndTheFresnelFormula) {
  // A mirror lobe with a dielectric of index 1.5 combined by "mix" on the sky: three files, the
  // specular map (the mirror lobe: the sky itself, against the reference sum at texel centres),
  // the irradiance map (against the reference sum of the cosine lobe) and the Fresnel table
  // (F at n.v = (i + 0.5) / N, against the formula typed out), with metadata saying how a renderer
  // combines them. On the furnace, specular 1 and irradiance E/pi 1 everywhere.
  test::TempDir dir;
  PrefilterFiles r = prefilterFiles(kFurnace, "mirror", "latlong", 8, dir / "coat.exr");
  r.request.fresnel = FresnelTerm::dielectric(Rgb::Constant(1.5));
  r.request.combine = FresnelCombine::Mix;
  const nlohmann::json report = runPrefilter(r).toJson();
  ASSERT_EQ(report["files"].size(), 3u);
  std::vector<std::string> names;
  for (const auto& file : report["files"]) names.push_back(fs::path(file.get<std::string>()).filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"coat.exr", "coat_fresnel.exr", "coat_irradiance.exr"}));
  EXPECT_EQ(report["fresnel"]["combine"], "mix");
  EXPECT_EQ(report["fresnel"]["irradiance_prefilter"]["lobe"], "irradiance");
  const Vec3 d = Vec3(0.3, -0.8, 0.2).normalized();
  EXPECT_NEAR(sampleAt(dir / "coat.exr", d)[0], 1.0, 1e-3);
  EXPECT_NEAR(sampleAt(dir / "coat_irradiance.exr", d)[0], 1.0, 1e-3);
  const Image table = readImage(dir / "coat_fresnel.exr");
  ASSERT_EQ(table.width(), 8);
  ASSERT_EQ(table.height(), 1);
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(table.at(i, 0)[0], fresnelFormula((i + 0.5) / 8.0, 1.5), 1e-6) << i;
  // F(1) = ((eta - 1) / (eta + 1))^2 = 0.04 at normal incidence: the last texel is near it.
  EXPECT_NEAR(table.at(7, 0)[0], 0.04, 2e-3);
  for (const char* file : {"coat.exr", "coat_irradiance.exr"}) {
    const auto fresnel = infoOf(dir / file)["metadata"]["spec"]["prefilter"]["fresnel"];
    EXPECT_EQ(fresnel["combine"], "mix") << file;
    EXPECT_EQ(fresnel["table"], "coat_fresnel.exr") << file;
    EXPECT_NE(fresnel["formula"].get<std::string>().find("(1 - F(n.v))"), std::string::npos) << file;
  }

  // On the sky: each file against the reference sums at texel centres of a lat-long map of 16.
  PrefilterFiles sky = prefilterFiles(kSky, "mirror", "latlong", 16, dir / "sky.exr");
  sky.request.fresnel = FresnelTerm::dielectric(Rgb::Constant(1.5));
  sky.request.combine = FresnelCombine::Mix;
  sky.request.method =
      PrefilterMethod::Reference;  // every texel summed at its centre: no fast method's error to allow for
  ASSERT_TRUE(runPrefilter(sky).written);
  const Environment environment = loadEnvironment(kSky);
  const auto map = makeParameterization(ParameterizationKind::LatLong, 16);
  std::vector<Vec3> axes;
  for (const Vec2& p : {Vec2(4.5, 3.5), Vec2(16.5, 8.5), Vec2(27.5, 5.5), Vec2(9.5, 12.5)})
    axes.push_back(*map->getDirectionFor(p));
  const auto irradiance = prefilterReferenceAt(environment, PrefilterLobe::irradiance(), axes);
  const MapFile specular = readMap(dir / "sky.exr"), diffuse = readMap(dir / "sky_irradiance.exr");
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const MapAddress a = map->getAddressFor(axes[i]);
    const int x = static_cast<int>(a.pixel.x()), y = static_cast<int>(a.pixel.y());
    // The mirror lobe's texel is the environment averaged over the texel's footprint: the mean
    // of the radiance at 32 x 32 points of the texel, weighted by their solid angle (sin theta);
    // within 5 %, the spread of the weightings a footprint may use across one texel.
    Rgb expected = Rgb::Zero();
    double weight = 0.0;
    for (int u = 0; u < 32; ++u)
      for (int v = 0; v < 32; ++v) {
        const Vec3 direction = *map->getDirectionFor(Vec2(x + (u + 0.5) / 32, y + (v + 0.5) / 32));
        const double w = std::sqrt(std::max(0.0, 1.0 - direction.y() * direction.y()));  // sin theta, theta from +y
        expected += w * environment.radiance(direction.normalized());
        weight += w;
      }
    expected /= weight;
    EXPECT_LT((specular.image.at(x, y).head<3>() - expected).matrix().norm(), 0.05 * expected.matrix().norm())
        << axes[i].transpose();
    EXPECT_LT((diffuse.image.at(x, y).head<3>() - irradiance[i]).matrix().norm(), 0.01 * irradiance[i].matrix().norm())
        << axes[i].transpose();
  }

  // Refused, naming the key: an irradiance lobe, combine alone, a bad combine, a non-positive index.
  auto refused = [&](const std::string& lobe, std::optional<double> ior, FresnelCombine combine) {
    PrefilterFiles bad = prefilterFiles(kFurnace, lobe, "cube", 8, dir / "bad.exr");
    if (ior) bad.request.fresnel = FresnelTerm::dielectric(Rgb::Constant(*ior));
    bad.request.combine = combine;
    const std::string message = test::errorOf([&] { runPrefilter(bad); });
    EXPECT_TRUE(message.rfind("fresnel: ", 0) == 0 || message.rfind("combine: ", 0) == 0) << message;
  };
  refused("irradiance", 1.5, FresnelCombine::Add);
  refused("mirror", std::nullopt, FresnelCombine::Mix);
  EXPECT_THROW(parseFresnelCombine("over"), Error);
  EXPECT_THROW(FresnelTerm::dielectric(Rgb::Constant(-2.0)), Error);
  EXPECT_FALSE(fs::exists(dir / "bad.exr"));
  EXPECT_FALSE(fs::exists(dir / "bad_irradiance.exr"));
}

TEST(PrefilterJob, SpecsMakeStacksAndFresnelDecompositions) {
  test::TempDir dir;
  const auto report = test::bakeSpec(test::sourcePath("data_samples/specs/prefilter_decomposition.json"), dir.path());
  ASSERT_EQ(report["maps"].size(), 2u);
  for (const auto& map : report["maps"]) {
    for (const auto& file : map["files"]) EXPECT_TRUE(fs::exists(file.get<std::string>())) << file;
  }
  EXPECT_EQ(report["maps"][0]["elevations"]["slices"], 8);
  EXPECT_EQ(report["maps"][0]["files"].size(), 8u);
  EXPECT_EQ(report["maps"][1]["fresnel"]["combine"], "mix");
  EXPECT_EQ(report["maps"][1]["files"].size(), 3u);

  // Bad keys name their JSON path; nothing is written.
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
    SpecRunOptions options;
    options.document = nlohmann::json::parse(R"({"maps": [{"output": "x.exr", "parameterization": "sphere",
        "resolution": 8, "environment": {"file": ")" +
                                             kSky + R"(", )" + keys + "}}]}");
    options.outDir = dir.path();
    const std::string message = test::errorOf([&] { runSpec(options); });
    EXPECT_NE(message.find(expected), std::string::npos) << keys << ": " << message;
  }
  EXPECT_FALSE(fs::exists(dir / "x.exr"));
  EXPECT_FALSE(fs::exists(dir / "x_elev0.exr"));
}

}  // namespace
}  // namespace brdfbake
