// The matcap job (run/matcap_job.hpp) called as a script would: a material file and an environment
// file in, a map on disk out, checked against values the job did not produce (a Lambertian albedo
// under a white furnace; a small sun against the one-light map of the same material baked from a
// spec with "lights", at the light colour docs/conventions.md prescribes), and bad input refused
// naming the file or key, with nothing written.
#include <brdfbake/bake/map_function.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/run/matcap_job.hpp>

#include <cmath>
#include <fstream>

#include "map_function_support.hpp"
#include "test_support.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
using test::SunOnly;
using test::TempDir;

// The environment's image written plainly (lat-long by its 2:1 shape).
fs::path writeEnvironment(const Environment& environment, const fs::path& path) {
  Image plain = environment.image;
  plain.metadata = nlohmann::json::object();
  writeImage(plain, path);
  return path;
}

fs::path writeText(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

// The texels of two sphere maps both fully covered (alpha 1).
template <class F>
void forCoveredTexels(const Image& a, const Image& b, F f) {
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      if (a.at(x, y)[3] >= 1.0 && b.at(x, y)[3] >= 1.0) f(x, y);
}

TEST(MatcapJob, AutoExposurePutsTheNinetyNinthPercentileOfTheCoveredTexelsAtWhite) {
  // 100 covered texels whose brightest channel is 1, 2, ..., 100 (in turn red, green, blue), and
  // uncovered ones (alpha 0) far brighter, which must not count: the 99th percentile of 100 values,
  // at index floor(0.99 x 99) = 98 of the sorted list, is 99, so the stops are -log2(99).
  Image image(20, 10, Rgba(1e6f, 1e6f, 1e6f, 0.0f));
  for (int i = 0; i < 100; ++i) {
    Rgba v(0.5f, 0.5f, 0.5f, 1.0f);
    v[i % 3] = static_cast<float>(i + 1);
    image.set(i % 10, i / 10, v);
  }
  EXPECT_NEAR(exposureFor(image), -std::log2(99.0), 1e-12);
  EXPECT_EQ(exposureFor(Image(4, 4, Rgba(0, 0, 0, 1))), 0.0);                  // a black map stays as it is
  EXPECT_EQ(exposureFor(Image(4, 4, Rgba(1e-30f, 1e-30f, 1e-30f, 1))), 30.0);  // within [-30, 30]
}

TEST(MatcapJob, AWhiteFurnaceShowsTheLambertianAlbedo) {
  TempDir dir;
  const fs::path furnace = writeEnvironment(
      bakeEnvironment(ConstantEnvironment(), ParameterizationKind::LatLong, 32, "furnace", 4), dir / "furnace.exr");
  const std::pair<const char*, const char*> materials[] = {
      {"phong", R"({"model": "phong", "diffuse": [0.5, 0.5, 0.5], "specular": [0, 0, 0], "exponent": 10})"},
      {"cook_torrance",
       R"({"model": "cook_torrance", "distribution": "ggx", "roughness": 0.3, "fresnel": {"schlick": [0.04, 0.04, 0.04]},
           "specular_weight": 0, "diffuse": [0.5, 0.5, 0.5]})"}};
  for (const auto& [name, json] : materials) {
    MatcapFiles request;
    request.material = writeText(dir / (std::string(name) + ".json"), json);
    request.environment = furnace;
    request.outputs.files = {dir / (std::string(name) + "_matcap.exr")};
    request.request.resolution = 32;
    const MapResult result = runMatcap(request, test::twoThreads());
    ASSERT_TRUE(result.written) << result.error;
    EXPECT_EQ(result.entry["bake_path"], "under_environment");
    EXPECT_LT(result.entry["under_environment"]["error_estimate"].get<double>(), 0.01);
    const MapFile map = readMap(request.outputs.files[0]);
    EXPECT_EQ(map.parameterization->kind(), ParameterizationKind::Sphere);
    double worst = 0.0;
    int covered = 0;
    forCoveredTexels(map.image, map.image, [&](int x, int y) {
      worst = std::max(worst, (map.image.at(x, y).head<3>() - 0.5).abs().maxCoeff());
      ++covered;
    });
    EXPECT_GT(covered, 600);           // most of the 32^2 disc
    EXPECT_LE(worst, 0.0025) << name;  // 0.5 within 0.5 %
  }
  // --exposure 1: twice the radiance.
  MatcapFiles request;
  request.material = dir / "phong.json";
  request.environment = furnace;
  request.outputs.files = {dir / "exposed.exr"};
  request.request.resolution = 16;
  request.request.exposure = 1.0;
  ASSERT_TRUE(runMatcap(request).written);
  const MapFile exposed = readMap(request.outputs.files[0]);
  EXPECT_NEAR(exposed.image.at(8, 8)[1], 1.0, 0.005);
}

TEST(MatcapJob, ASmallSunShowsWhatItsOneLightShows) {
  // A 0.5-degree sun of radiance 5000: irradiance P = Σ L Ω over the written environment's texels
  // (summed here). The one-light map of the same material is baked from a spec with "lights" (the
  // baker's directional-light path), at colour P / pi for Phong and P for Cook-Torrance.
  TempDir dir;
  const Vec3 sun = Vec3(0.3, 0.5, 0.6).normalized();
  const Environment environment =
      bakeEnvironment(SunOnly(sun, radians(0.5), 5000.0), ParameterizationKind::LatLong, 512, "sun", 16);
  const fs::path file = writeEnvironment(environment, dir / "sun.exr");
  double power = 0.0;
  for (int y = 0; y < environment.image.height(); ++y)
    for (int x = 0; x < environment.image.width(); ++x)
      power += environment.image.at(x, y)[0] * environment.map->texelSolidAngle(x, y);
  EXPECT_NEAR(power, 5000.0 * kTwoPi * (1.0 - std::cos(radians(0.5))), 0.03 * power);
  const std::pair<nlohmann::json, double> materials[] = {
      {{{"model", "phong"}, {"diffuse", {0.3, 0.2, 0.1}}, {"specular", {0.5, 0.5, 0.5}}, {"exponent", 50}}, 1.0 / kPi},
      {{{"model", "cook_torrance"},
        {"mode", "lighting"},
        {"distribution", "ggx"},
        {"roughness", 0.3},
        {"fresnel", {{"schlick", {0.955, 0.638, 0.538}}}},
        {"shadowing", "smith_separable"}},
       1.0}};
  int index = 0;
  for (const auto& [material, colorPerIrradiance] : materials) {
    const std::string name = material["model"].get<std::string>();
    MatcapFiles request;
    request.material = writeText(dir / (name + ".json"), material.dump());
    request.environment = file;
    request.outputs.files = {dir / (name + "_matcap.exr")};
    request.request.resolution = 64;
    request.request.samplesPerTexel = 4;
    ASSERT_TRUE(runMatcap(request, test::twoThreads()).written);
    const double color = power * colorPerIrradiance;
    SpecRunOptions oneLight;
    oneLight.outDir = dir.path();
    oneLight.document = {
        {"maps",
         {{{"output", "one_light_" + std::to_string(index++) + ".exr"},
           {"parameterization", "sphere"},
           {"resolution", 64},
           {"samples_per_texel", 4},
           {"material", material},
           {"lights", {{{"direction", {sun.x(), sun.y(), sun.z()}}, {"color", {color, color, color}}}}}}}}};
    const SpecRunResult expectedRun = runSpec(oneLight, test::twoThreads());
    ASSERT_FALSE(expectedRun.firstError);
    const Image matcap = readMap(request.outputs.files[0]).image, expected = readMap(expectedRun.maps[0].output).image;
    double peak = 0.0, sum = 0.0;
    int count = 0;
    forCoveredTexels(matcap, expected,
                     [&](int x, int y) { peak = std::max(peak, expected.at(x, y).head<3>().maxCoeff()); });
    forCoveredTexels(matcap, expected, [&](int x, int y) {
      sum += (matcap.at(x, y).head<3>() - expected.at(x, y).head<3>()).square().sum() / 3.0;
      ++count;
    });
    ASSERT_GT(count, 2500);
    EXPECT_LT(std::sqrt(sum / count) / peak, 0.02) << name << ": RMS over the visible disc, relative to the peak";
  }
}

TEST(MatcapJob, FitFilesAndMeasuredTablesAreLitThroughTheirBrdf) {
  // synthetic_two_lobes.astm is tabulated from known lobes (docs/fitting.md) and the fit.json of the
  // same name is lobes fitted to it, so the table's matcap (lobes fitted by the job) and the fit's
  // agree up to the two fits' differences.
  TempDir dir;
  std::vector<Image> images;
  const fs::path sky = test::sourcePath("data_samples/environments/sky_latlong.exr");
  for (const std::string material :
       {"data_samples/fits/synthetic_two_lobes.json", "data_samples/tables/synthetic_two_lobes.astm"}) {
    MatcapFiles request;
    request.material = test::sourcePath(material);
    request.environment = sky;
    request.outputs.files = {
        dir / (fs::path(material).stem().string() + fs::path(material).extension().string().substr(1) + ".exr")};
    request.request.resolution = 32;
    request.request.samplesPerTexel = 4;
    request.request.camera = CameraFrame::fromYawPitch(90.0, 10.0);
    const MapResult result = runMatcap(request, test::twoThreads());
    ASSERT_TRUE(result.written) << material;
    EXPECT_EQ(result.entry["under_environment"]["material"], images.empty() ? "lobes" : "measured") << material;
    const Image image = readMap(request.outputs.files[0]).image;
    double brightest = 0.0;
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) {
        ASSERT_TRUE(image.at(x, y).allFinite());
        brightest = std::max(brightest, image.at(x, y).head<3>().maxCoeff());
      }
    EXPECT_GT(brightest, 0.0) << material;
    images.push_back(image);
  }
  double peak = 0.0, sum = 0.0;
  int count = 0;
  forCoveredTexels(images[0], images[1],
                   [&](int x, int y) { peak = std::max(peak, images[0].at(x, y).head<3>().maxCoeff()); });
  forCoveredTexels(images[0], images[1], [&](int x, int y) {
    sum += (images[0].at(x, y).head<3>() - images[1].at(x, y).head<3>()).square().sum() / 3.0;
    ++count;
  });
  EXPECT_LT(std::sqrt(sum / count) / peak, 0.05) << "the fit's matcap against the table's, RMS relative to the peak";
}

TEST(MatcapJob, BadInputIsNamedAndNothingIsWritten) {
  TempDir dir;
  const fs::path sky = test::sourcePath("data_samples/environments/sky_latlong.exr");
  const fs::path out = dir / "out";
  fs::create_directories(out);
  auto errorOf = [&](MatcapFiles request) -> std::string {
    request.outputs.files = {out / "matcap.exr"};
    request.request.resolution = 16;
    try {
      runMatcap(request);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  MatcapFiles request;
  request.environment = sky;
  request.material = dir / "missing.json";
  EXPECT_NE(errorOf(request).find("missing.json"), std::string::npos);
  request.material = writeText(dir / "spec.json", R"({"maps": []})");
  EXPECT_NE(errorOf(request).find("a bake spec"), std::string::npos) << errorOf(request);
  request.material = writeText(dir / "gooch.json", R"({"model": "gooch"})");
  const std::string gooch = errorOf(request);
  EXPECT_EQ(gooch.rfind("material: gooch has no BRDF", 0), 0u) << gooch;
  request.material = writeText(dir / "phong.json", R"({"model": "phong", "specular": [1, 1, 1], "exponent": 20})");
  request.environment = dir / "no_sky.exr";
  EXPECT_EQ(errorOf(request).rfind("environment: ", 0), 0u) << errorOf(request);
  EXPECT_NE(errorOf(request).find("no_sky.exr"), std::string::npos) << errorOf(request);
  request.environment = writeText(dir / "not_an_image.exr", "hello");
  EXPECT_NE(errorOf(request).find("not_an_image.exr"), std::string::npos) << errorOf(request);
  request.environment = sky;
  EXPECT_EQ(test::errorOf([] { CameraFrame::fromYawPitch(0.0, 120.0); }).rfind("camera: ", 0), 0u);
  request.request.exposure = 40.0;
  EXPECT_EQ(errorOf(request).rfind("exposure: must be in [-30, 30]", 0), 0u) << errorOf(request);
  request.request.exposure = 0.0;
  request.request.maxError = 0.9;
  EXPECT_EQ(errorOf(request).rfind("max_error: ", 0), 0u) << errorOf(request);
  EXPECT_THROW(parseUnderEnvironmentMethod("fast"), Error);
  EXPECT_TRUE(test::filesIn(out).empty());
}

}  // namespace
}  // namespace brdfbake
