// Every output of bake and prefilter read back through the library's jobs (sampleOutput,
// describeOutput, convertOutput, makePreview) with the value a renderer would get: each kind is
// made small, sampled at known directions and compared with an independent value (the exact
// model where the map is accurate, a furnace integral, the textbook Fresnel formula, a closed-form
// irradiance), then inspected, resampled and previewed (the preview decoded: an object drawn over
// the background). Moved from tests/cli/test_read_outputs.cpp, which keeps the tool's own part
// (--dirs output lines, flags named in refusals).
#include <gtest/gtest.h>
#include <brdfbake/core/math.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/run/convert_output.hpp>
#include <brdfbake/run/prefilter_job.hpp>
#include <brdfbake/run/preview_job.hpp>

#include <fstream>

#include "map_function_support.hpp"
#include "run_support.hpp"

namespace brdfbake {
namespace {

using test::infoOf;
using test::prefilterFiles;
using test::randomDirections;
namespace fs = std::filesystem;

const std::string kFurnace = test::sourcePath("data_samples/environments/furnace_latlong.exr");
const std::string kVaryingFit = test::sourcePath("data_samples/fits/synthetic_varying.json");

// The RGB values a renderer looks up in `output` at every direction (mip level, n.v as given).
std::vector<Rgb> sampleAll(const fs::path& output, const std::vector<Vec3>& directions, int mipLevel = 0,
                           std::optional<double> cosView = {}) {
  SampleOptions options;
  options.source.path = output;
  options.source.mipLevel = mipLevel;
  options.source.cosView = cosView;
  options.directions = directions;
  std::vector<Rgb> values;
  for (const auto& lookup : sampleOutput(options).lookups) values.push_back(lookup.value.head<3>());
  EXPECT_EQ(values.size(), directions.size());
  return values;
}

// F(n.v) of a Fresnel table: n.v alone, no direction.
double fresnelAt(const fs::path& table, double cosView) {
  SampleOptions options;
  options.source.path = table;
  options.source.cosView = cosView;
  return sampleOutput(options).lookups.at(0).value[0];
}

fs::path convertTo(const fs::path& input, ParameterizationKind to, int resolution, const fs::path& output,
                   std::optional<double> cosView = {}) {
  ConvertOptions options;
  options.source.path = input;
  options.source.cosView = cosView;
  options.to = to;
  options.resolution = resolution;
  options.outputs.files = {output};
  convertOutput(options);
  return output;
}

// A 32-pixel preview of `output` decoded: 32 x 32, and the object in the middle differs from the
// background in the corner (PreviewOptions::background, sRGB-encoded in the PNG).
void expectPreviews(const fs::path& output, const Vec3& view = Vec3::UnitZ(), int mipLevel = 0) {
  const fs::path png = output.parent_path() / (output.stem().string() + "_preview.png");
  PreviewJobOptions options;
  options.source.path = output;
  options.source.mipLevel = mipLevel;
  options.preview.resolution = 32;
  options.preview.view = view;
  options.output = png;
  makePreview(options);
  const Image image = readImage(png);
  ASSERT_EQ(image.width(), 32) << png;
  ASSERT_EQ(image.height(), 32) << png;
  EXPECT_GT((image.at(16, 16) - image.at(0, 0)).head<3>().abs().maxCoeff(), 0.02)
      << png << ": the object is not drawn over the background";
}

// Unpolarised Fresnel reflectance of a dielectric of relative index eta at cos theta = c
// (Cook & Torrance 1981, their F with g^2 = eta^2 + c^2 - 1), written out here as the
// independent value.
double dielectricFresnel(double c, double eta) {
  const double g = std::sqrt(eta * eta + c * c - 1.0);
  const double a = (g - c) / (g + c), b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
  return 0.5 * a * a * (1.0 + b * b);
}

// Phong lit by one light: (r.l)^10 at the reflected direction r. Maps of a wide lobe are accurate
// to well under 1 % of the peak at 64 texels.
constexpr double kExponent = 10.0;
double phong(const Vec3& r, const Vec3& light) { return std::pow(std::max(0.0, r.dot(light)), kExponent); }

TEST(OutputJobs, EveryBakedKindSamplesConvertsAndPreviews) {
  test::TempDir dir;
  const Vec3 light = Vec3(1, 1, 1).normalized();
  std::ofstream(dir / "spec.json") << R"({"maps": [
    {"output": "s.exr", "parameterization": "sphere", "resolution": 128, "samples_per_texel": 4,
     "material": {"model": "phong", "exponent": 10}, "lights": [{"direction": "eye"}]},
    {"output": "p.exr", "parameterization": "paraboloid", "resolution": 64, "samples_per_texel": 4,
     "material": {"model": "phong", "exponent": 10}, "lights": [{"direction": [1, 1, 1]}]},
    {"output": "l.exr", "parameterization": "latlong", "resolution": 64, "samples_per_texel": 4,
     "material": {"model": "phong", "exponent": 10}, "lights": [{"direction": [1, 1, 1]}]},
    {"output": "c.exr", "parameterization": "cube", "layout": "faces", "resolution": 32, "samples_per_texel": 4,
     "material": {"model": "phong", "exponent": 10}, "lights": [{"direction": [1, 1, 1]}]},
    {"output": "r.exr", "parameterization": "profile", "resolution": 128, "samples_per_texel": 4,
     "material": {"model": "phong", "exponent": 10}, "lights": [{"direction": "eye"}]},
    {"output": "f.exr", "parameterization": "sphere", "resolution": 32, "fresnel_table_output": "f_1d.exr",
     "material": {"model": "fresnel", "fresnel": {"ior": 1.5}, "combine": "add"}}]})";
  test::bakeSpec(dir / "spec.json");
  ASSERT_FALSE(fs::exists(dir / "c.exr"));  // six faces instead
  ASSERT_TRUE(fs::exists(dir / "c_negz.exr"));

  const auto directions = randomDirections(40, 7);
  struct Case {
    const char* file;
    Vec3 light;        // the lobe's axis: the light, or the view +z for eye-lit maps
    const char* kind;  // what info says
    const char* parameterization;
  };
  const Case cases[] = {{"s.exr", Vec3::UnitZ(), "map", "sphere"},
                        {"p.exr", light, "map", "paraboloid"},
                        {"l.exr", light, "map", "latlong"},
                        {"c.exr", light, "map", "cube"},       // STEM.EXT of the six faces
                        {"c_posy.exr", light, "map", "cube"},  // or any one face
                        {"r.exr", Vec3::UnitZ(), "radial_profile", "profile"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const auto values = sampleAll(dir / c.file, directions);
    ASSERT_EQ(values.size(), directions.size());
    for (std::size_t i = 0; i < directions.size(); ++i) {
      const Vec3& r = directions[i];
      if (c.light == Vec3::UnitZ() && r.z() < -0.5) continue;  // the sphere map's rim (and the profile's far end)
      EXPECT_NEAR(values[i][0], phong(r, c.light), 0.01) << r.transpose();
    }
    const auto info = infoOf(dir / c.file);
    EXPECT_EQ(info["kind"], c.kind);
    EXPECT_EQ(info["parameterization"], c.parameterization);
    // Resampled into a lat-long map, the value is still the model's (within the coarser map's error).
    const fs::path converted =
        convertTo(dir / c.file, ParameterizationKind::LatLong, 64, dir / (std::string("conv_") + c.file));
    const auto resampled = sampleAll(converted, directions);
    ASSERT_EQ(resampled.size(), directions.size());
    for (std::size_t i = 0; i < directions.size(); ++i) {
      const Vec3& r = directions[i];
      if (c.light == Vec3::UnitZ() && r.z() < -0.5) continue;
      EXPECT_NEAR(resampled[i][0], phong(r, c.light), 0.03) << r.transpose();
    }
    if (c.light == Vec3::UnitZ())
      expectPreviews(dir / c.file);  // eye space: the default view +z
    else
      expectPreviews(dir / c.file, Vec3(0.3, 0.2, 1));
  }
  EXPECT_EQ(infoOf(dir / "c.exr")["files"].size(), 6u);
  EXPECT_EQ(infoOf(dir / "r.exr")["axis"], nlohmann::json({0.0, 0.0, 1.0}));

  // The fresnel model's 1-D texture: F(n.v) at n.v, no direction.
  for (const double c : {0.05, 0.3, 0.77, 1.0}) {
    // 32 texels: linear interpolation of a smooth F is within 2e-3 away from grazing.
    EXPECT_NEAR(fresnelAt(dir / "f_1d.exr", c), dielectricFresnel(std::max(c, 0.5 / 32), 1.5), c < 0.1 ? 0.03 : 2e-3)
        << c;
  }
  EXPECT_EQ(infoOf(dir / "f_1d.exr")["kind"], "fresnel_table");
  expectPreviews(dir / "f_1d.exr");
  // To a sphere map: the sphere map of F as seen from +z matches the fresnel model's own sphere map.
  convertTo(dir / "f_1d.exr", ParameterizationKind::Sphere, 32, dir / "f_conv.exr");
  const std::vector<Vec3> front{Vec3(0, 0, 1), Vec3(0.3, 0.2, 0.9).normalized(), Vec3(-0.6, 0.1, 0.4).normalized()};
  const auto fromTable = sampleAll(dir / "f_conv.exr", front), fromModel = sampleAll(dir / "f.exr", front);
  ASSERT_EQ(fromTable.size(), front.size());
  for (std::size_t i = 0; i < front.size(); ++i) {
    const double nv = std::sqrt((1.0 + front[i].z()) / 2.0);
    EXPECT_NEAR(fromTable[i][0], dielectricFresnel(nv, 1.5), 3e-3) << front[i].transpose();
    EXPECT_NEAR(fromTable[i][0], fromModel[i][0], 3e-3) << front[i].transpose();
  }
}

TEST(OutputJobs, PrefilterMipLevelsStacksAndFresnelMapsReadBack) {
  test::TempDir dir;
  // Mip levels of a furnace's irradiance: pi at every level, whether read from STEM_mipK.EXT or as
  // mip level K of STEM.EXT; cube faces at every level too.
  PrefilterFiles mips = prefilterFiles(kFurnace, "irradiance", "cube", 8, dir / "irr.exr");
  mips.outputs.layout = CubeLayout::Faces;
  mips.request.mips = true;
  ASSERT_TRUE(runPrefilter(mips).written);
  const auto directions = randomDirections(12, 3);
  for (int level = 0; level < 4; ++level) {  // 8, 4, 2, 1 texels per face
    SCOPED_TRACE(level);
    std::vector<std::vector<Rgb>> reads{sampleAll(dir / "irr.exr", directions, level)};
    if (level > 0) reads.push_back(sampleAll(dir / ("irr_mip" + std::to_string(level) + "_posx.exr"), directions));
    for (const auto& values : reads) {
      ASSERT_EQ(values.size(), directions.size());
      for (const Rgb& v : values) EXPECT_NEAR(v[0], 1.0, 1e-4);  // E/pi
    }
  }
  EXPECT_EQ(infoOf(dir / "irr_mip1.exr")["resolution"], 4);
  EXPECT_NE(test::errorOf([&] { sampleAll(dir / "irr.exr", {Vec3::UnitZ()}, 4); }).find("irr_mip4"), std::string::npos);
  expectPreviews(dir / "irr.exr", Vec3(0, 1, 1), 2);

  // An elevation stack of a fitted model that varies with elevation, prefiltered from the furnace:
  // slice j holds C(u_j) (n(u_j) + 2) / (n(u_j) + 1) (the normalised lobe's integral times 1), and
  // a renderer blends neighbouring slices linearly in t = ln(u / min_cos) / ln(max_cos / min_cos).
  PrefilterFiles stack = prefilterFiles(kFurnace, "lobes:" + kVaryingFit, "paraboloid", 16, dir / "v.exr");
  stack.request.elevations = 3;
  const nlohmann::json report = runPrefilter(stack).toJson();
  const LobeModel model = readFitFile(kVaryingFit).fit.model;
  auto furnaceValue = [&](double u) {
    const double c = model.weight(0, 0, u), n = model.exponent(0, 0, u);
    return c * (n + 2.0) / (n + 1.0);
  };
  const double minCos = model.minCos, maxCos = model.maxCos;
  const Vec3 r = Vec3(0.2, 0.3, -1).normalized();
  for (double t : {0.0, 0.25, 0.5, 0.9, 1.0}) {
    const double u = minCos * std::pow(maxCos / minCos, t);
    // The slices at t = 0, 0.5, 1; between them the linear blend of the two.
    const double x = t * 2.0;
    const int j = std::min(static_cast<int>(x), 1);
    const double f = x - j;
    const double u0 = report["elevations"]["cos_theta"][j].get<double>(),
                 u1 = report["elevations"]["cos_theta"][j + 1].get<double>();
    const double expected = (1.0 - f) * furnaceValue(u0) + f * furnaceValue(u1);
    const auto values = sampleAll(dir / "v.exr", {r}, 0, u);
    ASSERT_EQ(values.size(), 1u);
    EXPECT_NEAR(values[0][0], expected, 2e-3 * expected) << "t = " << t;
  }
  const auto stackInfo = infoOf(dir / "v.exr");
  EXPECT_EQ(stackInfo["kind"], "elevation_stack");
  EXPECT_EQ(stackInfo["slices"], 3);
  EXPECT_NEAR(stackInfo["min_cos"].get<double>(), minCos, 1e-12);
  // Without n.v the stack has no value; a map refuses n.v (one meaning per option).
  EXPECT_THROW(sampleAll(dir / "v.exr", {Vec3::UnitZ()}), Error);
  EXPECT_THROW(sampleAll(dir / "irr.exr", {Vec3::UnitZ()}, 0, 0.5), Error);
  // Converted at one n.v: a 2-D map of that blend.
  const double uHalf = minCos * std::pow(maxCos / minCos, 0.25);
  convertTo(dir / "v.exr", ParameterizationKind::LatLong, 8, dir / "v_at.exr", uHalf);
  const double quarter = 0.5 * furnaceValue(report["elevations"]["cos_theta"][0].get<double>()) +
                         0.5 * furnaceValue(report["elevations"]["cos_theta"][1].get<double>());
  const auto converted = sampleAll(dir / "v_at.exr", {r, Vec3(0, 1, 0)});
  ASSERT_EQ(converted.size(), 2u);
  for (const Rgb& v : converted) EXPECT_NEAR(v[0], quarter, 3e-3 * quarter);

  // The Fresnel decomposition: specular map, irradiance map (looked up at the normal), profile.
  PrefilterFiles coat = prefilterFiles(kFurnace, "phong:20", "sphere", 16, dir / "coat.exr");
  coat.request.fresnel = FresnelTerm::dielectric(Rgb::Constant(1.5));
  ASSERT_TRUE(runPrefilter(coat).written);
  for (const double c : {0.15625, 0.46875, 0.96875}) {  // texel centres (i + 0.5) / 16
    EXPECT_NEAR(fresnelAt(dir / "coat_fresnel.exr", c), dielectricFresnel(c, 1.5), 1e-5) << c;
  }
  EXPECT_NEAR(sampleAll(dir / "coat_irradiance.exr", {Vec3(0, 0, 1)}).at(0)[0], 1.0, 1e-3);
  EXPECT_NEAR(sampleAll(dir / "coat.exr", {Vec3(0.1, 0.2, 1)}).at(0)[0], 1.0, 1e-3);
  EXPECT_EQ(infoOf(dir / "coat_fresnel.exr")["metadata"]["spec"]["prefilter"]["fresnel"]["role"], "table");
  expectPreviews(dir / "coat_fresnel.exr");
  expectPreviews(dir / "coat_irradiance.exr");
}

// One piece for a renderer: a tiled layout puts the mip chain into the output (levels equal to the
// separate files), spec "mip_layout": "tiled" does the same; an SH output writes irradiance as 9
// SH coefficients, read back by sample, info, convert and preview.
TEST(OutputJobs, TiledMipChainsAndShIrradianceReadBack) {
  test::TempDir dir;
  const std::string sky = test::sourcePath("data_samples/environments/sky_latlong.exr");
  auto glossy = [&](const fs::path& output, bool tiled) {
    PrefilterFiles r = prefilterFiles(sky, "phong:20", "paraboloid", 16, output);
    r.request.mips = true;
    r.request.method = PrefilterMethod::SphericalHarmonics;
    r.outputs.mipLayout = tiled ? MipLayout::Tiled : MipLayout::Files;
    ASSERT_TRUE(runPrefilter(r).written);
  };
  glossy(dir / "files.exr", false);
  glossy(dir / "tiled.exr", true);
  EXPECT_FALSE(fs::exists(dir / "tiled_mip1.exr"));
  const auto directions = randomDirections(10, 21);
  for (int level = 0; level < 5; ++level) {
    const auto a = sampleAll(dir / "tiled.exr", directions, level), b = sampleAll(dir / "files.exr", directions, level);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i][0], b[i][0]) << level;
  }
  EXPECT_EQ(infoOf(dir / "tiled.exr")["metadata"]["mip_levels"], 5);
  expectPreviews(dir / "tiled.exr", Vec3::UnitZ(), 1);
  PrefilterFiles notPowerOfTwo = prefilterFiles(sky, "phong:20", "cube", 12, dir / "bad.exr");
  notPowerOfTwo.request.mips = true, notPowerOfTwo.outputs.mipLayout = MipLayout::Tiled;
  EXPECT_NE(test::errorOf([&] { runPrefilter(notPowerOfTwo); }).find("power-of-two"), std::string::npos);
  PrefilterFiles noMips = prefilterFiles(sky, "phong:20", "cube", 16, dir / "bad.exr");
  noMips.outputs.mipLayout = MipLayout::Tiled;
  EXPECT_THROW(runPrefilter(noMips), Error);
  PrefilterFiles png = prefilterFiles(sky, "phong:20", "cube", 16, dir / "bad.png");
  png.request.mips = true, png.outputs.mipLayout = MipLayout::Tiled;
  EXPECT_NE(test::errorOf([&] { runPrefilter(png); }).find(".exr"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "bad.exr"));

  // In a spec: "mip_layout": "tiled" beside "mips", for prefiltered and silhouette maps.
  std::ofstream(dir / "spec.json") << R"({"maps": [
    {"output": "env.exr", "parameterization": "latlong", "resolution": 8,
     "environment": {"file": ")" << sky
                                   << R"(", "lobe": "irradiance", "mips": true, "mip_layout": "tiled"}},
    {"output": "sil.exr", "parameterization": "sphere", "resolution": 32, "samples_per_texel": 4, "mips": true,
     "mip_layout": "tiled", "material": {"model": "silhouette", "width": 15}}]})";
  test::bakeSpec(dir / "spec.json");
  EXPECT_FALSE(fs::exists(dir / "env_mip1.exr"));
  EXPECT_FALSE(fs::exists(dir / "sil_mip1.exr"));
  EXPECT_EQ(infoOf(dir / "sil.exr")["metadata"]["mip_levels"], 6);
  // The 1-texel level of the silhouette chain: the ring fills the disc, so the ring colour (0).
  EXPECT_NEAR(sampleAll(dir / "sil.exr", {Vec3::UnitZ()}, 5).at(0)[0], 0.0, 1e-6);
  std::ofstream(dir / "bad_spec.json")
      << R"({"maps": [{"output": "x.exr", "parameterization": "sphere", "resolution": 32,
     "mip_layout": "tiled", "material": {"model": "silhouette", "width": 15}}]})";
  SpecRunOptions badSpec;
  badSpec.spec = dir / "bad_spec.json";
  EXPECT_NE(test::errorOf([&] { runSpec(badSpec); }).find("maps[0].mip_layout"), std::string::npos);

  // SH irradiance: the furnace (radiance 1) gives 1 everywhere. A sky of radiance 1 above the horizon
  // (y > 0) has E(n)/pi = (1 + n.y)/2, which three bands hold exactly; its irradiance cube map,
  // computed by the reference sum (another method), agrees.
  PrefilterFiles furnace = prefilterFiles(kFurnace, "irradiance", "cube", 8, dir / "furnace_irr.exr");
  furnace.request.sh = true, furnace.sh = ShOutput{dir / "furnace_sh.json"};
  ASSERT_TRUE(runPrefilter(furnace).written);
  for (const Rgb& v : sampleAll(dir / "furnace_sh.json", directions)) EXPECT_NEAR(v[0], 1.0, 1e-3);
  {
    Image hemisphere(256, 128);
    for (int y = 0; y < 128; ++y)
      for (int x = 0; x < 256; ++x)
        hemisphere.set(x, y, y < 64 ? Rgba(1, 1, 1, 1) : Rgba(0, 0, 0, 1));  // top rows: y > 0
    writeImage(hemisphere, dir / "hemisphere.exr");
  }
  PrefilterFiles half =
      prefilterFiles((dir / "hemisphere.exr").string(), "irradiance", "cube", 16, dir / "sky_irr.exr");
  half.request.method = PrefilterMethod::Reference;
  half.request.sh = true, half.sh = ShOutput{dir / "sky_sh.json"};
  ASSERT_TRUE(runPrefilter(half).written);
  const auto fromSh = sampleAll(dir / "sky_sh.json", directions), fromMap = sampleAll(dir / "sky_irr.exr", directions);
  ASSERT_EQ(fromSh.size(), fromMap.size());
  for (std::size_t i = 0; i < fromSh.size(); ++i) {
    const double exact = 0.5 * (1.0 + directions[i].y());
    EXPECT_NEAR(fromSh[i][0], exact, 1e-3) << directions[i].transpose();
    EXPECT_NEAR(fromMap[i][0], exact, 1e-2) << directions[i].transpose();  // E/pi; a 16-texel cube map, bilinear
  }
  const auto document = test::readJsonFile(dir / "sky_sh.json");
  EXPECT_EQ(document["bands"], 3);
  EXPECT_EQ(document["coefficients"].size(), 9u);
  EXPECT_NE(document["convention"].get<std::string>().find("1/pi"), std::string::npos);
  const auto info = infoOf(dir / "sky_sh.json");
  EXPECT_EQ(info["kind"], "sh_irradiance");
  EXPECT_EQ(info["indexed_by"], "normal");
  // Converted to a lat-long map: still (1 + n.y) / 2 at the texels' directions.
  convertTo(dir / "sky_sh.json", ParameterizationKind::LatLong, 16, dir / "sh_ll.exr");
  const auto fromConverted = sampleAll(dir / "sh_ll.exr", directions);
  for (std::size_t i = 0; i < directions.size(); ++i)
    EXPECT_NEAR(fromConverted[i][0], 0.5 * (1.0 + directions[i].y()), 2e-2) << directions[i].transpose();
  expectPreviews(dir / "sky_sh.json", Vec3(0, 1, 1));
  PrefilterFiles wrongLobe = prefilterFiles(sky, "phong:20", "cube", 8, dir / "x.exr");
  wrongLobe.request.sh = true, wrongLobe.sh = ShOutput{dir / "x.json"};
  EXPECT_EQ(test::errorOf([&] { runPrefilter(wrongLobe); }).rfind("sh: ", 0), 0u);
}

}  // namespace
}  // namespace brdfbake
