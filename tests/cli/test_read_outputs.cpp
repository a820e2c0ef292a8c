// Every output of `bake` and `prefilter` reads back through `sample`, `info`, `convert` and
// `preview` with the value a renderer would get: each kind is made small, sampled at known
// directions and compared with an independent value (the exact model where the map is accurate,
// a furnace integral, the textbook Fresnel formula), then inspected, resampled and previewed.
#include <gtest/gtest.h>
#include <brdfbake/core/math.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/maps/image_io.hpp>

#include <nlohmann/json.hpp>
#include "map_function_support.hpp"

#include <fstream>
#include <random>
#include <sstream>

#include "test_support.hpp"

namespace brdfbake {
namespace {

using test::randomDirections;
namespace fs = std::filesystem;
using test::q;
using test::runCli;

const std::string kFurnace = test::sourcePath("data_samples/environments/furnace_latlong.exr");
const std::string kVaryingFit = test::sourcePath("data_samples/fits/synthetic_varying.json");

// Samples `output` at every direction in one process (--dirs) and returns the RGB values.
std::vector<Rgb> sampleAll(const fs::path& output, const std::vector<Vec3>& directions, const std::string& flags = "") {
  const fs::path file = output.parent_path() / (output.stem().string() + "_dirs.txt");
  {
    std::ofstream out(file);
    out.precision(17);
    out << "# directions for " << output.filename().string() << "\n\n";
    for (const Vec3& d : directions) out << d.x() << " " << d.y() << " " << d.z() << "\n";
  }
  const auto result = runCli("sample " + q(output) + " --dirs " + q(file) + " --json " + flags);
  EXPECT_EQ(result.exitCode, 0) << result.output;
  std::vector<Rgb> values;
  if (result.exitCode != 0) return values;
  const auto array = nlohmann::json::parse(result.out);
  EXPECT_EQ(array.size(), directions.size());
  for (const auto& entry : array) {
    const auto& v = entry["value"];
    values.emplace_back(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  }
  return values;
}

nlohmann::json infoOf(const fs::path& output, const std::string& flags = "") {
  const auto result = runCli("info " + q(output) + " --json " + flags);
  EXPECT_EQ(result.exitCode, 0) << result.output;
  return result.exitCode == 0 ? nlohmann::json::parse(result.out) : nlohmann::json::object();
}

void expectPreviews(const fs::path& output, const std::string& flags = "") {
  const fs::path png = output.parent_path() / (output.stem().string() + "_preview.png");
  const auto result = runCli("preview " + q(output) + " --size 32 --quiet " + flags + " -o " + q(png));
  EXPECT_EQ(result.exitCode, 0) << result.output;
  EXPECT_TRUE(fs::exists(png)) << png;
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

TEST(ReadOutputs, EveryBakedKindSamplesConvertsAndPreviews) {
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
  const auto baked = runCli("bake " + q(dir / "spec.json") + " --quiet");
  ASSERT_EQ(baked.exitCode, 0) << baked.output;
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
    const fs::path converted = dir / (std::string("conv_") + c.file);
    const auto convert =
        runCli("convert " + q(dir / c.file) + " --to latlong --resolution 64 --quiet -o " + q(converted));
    ASSERT_EQ(convert.exitCode, 0) << convert.output;
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
      expectPreviews(dir / c.file, "--view 0.3,0.2,1");
  }
  EXPECT_EQ(infoOf(dir / "c.exr")["files"].size(), 6u);
  EXPECT_EQ(infoOf(dir / "r.exr")["axis"], nlohmann::json({0.0, 0.0, 1.0}));

  // The fresnel model's 1-D texture: F(n.v) at --cos-view, no direction.
  for (const double c : {0.05, 0.3, 0.77, 1.0}) {
    const auto result = runCli("sample " + q(dir / "f_1d.exr") + " --cos-view " + std::to_string(c) + " --json");
    ASSERT_EQ(result.exitCode, 0) << result.output;
    const double f = nlohmann::json::parse(result.out)["value"][0].get<double>();
    // 32 texels: linear interpolation of a smooth F is within 2e-3 away from grazing.
    EXPECT_NEAR(f, dielectricFresnel(std::max(c, 0.5 / 32), 1.5), c < 0.1 ? 0.03 : 2e-3) << c;
  }
  EXPECT_EQ(infoOf(dir / "f_1d.exr")["kind"], "fresnel_table");
  expectPreviews(dir / "f_1d.exr");
  // --to sphere: the sphere map of F as seen from +z matches the fresnel model's own sphere map.
  ASSERT_EQ(
      runCli("convert " + q(dir / "f_1d.exr") + " --to sphere --resolution 32 --quiet -o " + q(dir / "f_conv.exr"))
          .exitCode,
      0);
  const std::vector<Vec3> front{Vec3(0, 0, 1), Vec3(0.3, 0.2, 0.9).normalized(), Vec3(-0.6, 0.1, 0.4).normalized()};
  const auto fromTable = sampleAll(dir / "f_conv.exr", front), fromModel = sampleAll(dir / "f.exr", front);
  ASSERT_EQ(fromTable.size(), front.size());
  for (std::size_t i = 0; i < front.size(); ++i) {
    const double nv = std::sqrt((1.0 + front[i].z()) / 2.0);
    EXPECT_NEAR(fromTable[i][0], dielectricFresnel(nv, 1.5), 3e-3) << front[i].transpose();
    EXPECT_NEAR(fromTable[i][0], fromModel[i][0], 3e-3) << front[i].transpose();
  }
}

TEST(ReadOutputs, PrefilterMipLevelsStacksAndFresnelMapsReadBack) {
  test::TempDir dir;
  // Mip levels of a furnace's irradiance: pi at every level, whether read from STEM_mipK.EXT or as
  // --mip-level K of STEM.EXT; cube faces at every level too.
  const auto mips =
      runCli("prefilter " + q(kFurnace) + " --lobe irradiance --to cube --faces --resolution 8 --mips --quiet -o " +
             q(dir / "irr.exr"));
  ASSERT_EQ(mips.exitCode, 0) << mips.output;
  const auto directions = randomDirections(12, 3);
  for (int level = 0; level < 4; ++level) {  // 8, 4, 2, 1 texels per face
    SCOPED_TRACE(level);
    std::vector<std::vector<Rgb>> reads{sampleAll(dir / "irr.exr", directions, "--mip-level " + std::to_string(level))};
    if (level > 0) reads.push_back(sampleAll(dir / ("irr_mip" + std::to_string(level) + "_posx.exr"), directions));
    for (const auto& values : reads) {
      ASSERT_EQ(values.size(), directions.size());
      for (const Rgb& v : values) EXPECT_NEAR(v[0], kPi, 1e-4 * kPi);
    }
  }
  EXPECT_EQ(infoOf(dir / "irr_mip1.exr")["resolution"], 4);
  const auto tooDeep = runCli("sample " + q(dir / "irr.exr") + " --mip-level 4 --dir 0,0,1");
  EXPECT_NE(tooDeep.exitCode, 0);
  EXPECT_NE(tooDeep.output.find("irr_mip4"), std::string::npos) << tooDeep.output;
  expectPreviews(dir / "irr.exr", "--mip-level 2 --view 0,1,1");

  // An elevation stack of a fitted model that varies with elevation, prefiltered from the furnace:
  // slice j holds C(u_j) (n(u_j) + 2) / (n(u_j) + 1) (the normalised lobe's integral times 1), and
  // a renderer blends neighbouring slices linearly in t = ln(u / min_cos) / ln(max_cos / min_cos).
  const auto stack = runCli("prefilter " + q(kFurnace) + " --lobe lobes:" + q(kVaryingFit) +
                            " --to paraboloid --resolution 16 --elevations 3 --json -o " + q(dir / "v.exr"));
  ASSERT_EQ(stack.exitCode, 0) << stack.output;
  const auto report = nlohmann::json::parse(stack.out);
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
    const auto values = sampleAll(dir / "v.exr", {r}, "--cos-view " + std::to_string(u));
    ASSERT_EQ(values.size(), 1u);
    EXPECT_NEAR(values[0][0], expected, 2e-3 * expected) << "t = " << t;
  }
  const auto stackInfo = infoOf(dir / "v.exr");
  EXPECT_EQ(stackInfo["kind"], "elevation_stack");
  EXPECT_EQ(stackInfo["slices"], 3);
  EXPECT_NEAR(stackInfo["min_cos"].get<double>(), minCos, 1e-12);
  // Without --cos-view the stack has no value; a map refuses --cos-view (one meaning per flag).
  const auto noCos = runCli("sample " + q(dir / "v.exr") + " --dir 0,0,1");
  EXPECT_EQ(noCos.exitCode, 2);
  EXPECT_NE(noCos.output.find("--cos-view"), std::string::npos) << noCos.output;
  const auto mapCos = runCli("sample " + q(dir / "irr.exr") + " --dir 0,0,1 --cos-view 0.5");
  EXPECT_EQ(mapCos.exitCode, 2);
  EXPECT_NE(mapCos.output.find("--cos-view"), std::string::npos) << mapCos.output;
  // Converted at one n.v: a 2-D map of that blend.
  const double uHalf = minCos * std::pow(maxCos / minCos, 0.25);
  ASSERT_EQ(runCli("convert " + q(dir / "v.exr") + " --cos-view " + std::to_string(uHalf) +
                   " --to latlong --resolution 8 --quiet -o " + q(dir / "v_at.exr"))
                .exitCode,
            0);
  const double quarter = 0.5 * furnaceValue(report["elevations"]["cos_theta"][0].get<double>()) +
                         0.5 * furnaceValue(report["elevations"]["cos_theta"][1].get<double>());
  const auto converted = sampleAll(dir / "v_at.exr", {r, Vec3(0, 1, 0)});
  ASSERT_EQ(converted.size(), 2u);
  for (const Rgb& v : converted) EXPECT_NEAR(v[0], quarter, 3e-3 * quarter);
  expectPreviews(dir / "v.exr", "--view 0,0.4,1");

  // The Fresnel decomposition: specular map, irradiance map (looked up at the normal), profile.
  const auto coat =
      runCli("prefilter " + q(kFurnace) + " --lobe phong:20 --fresnel-ior 1.5 --to sphere --resolution 16 --quiet -o " +
             q(dir / "coat.exr"));
  ASSERT_EQ(coat.exitCode, 0) << coat.output;
  for (const double c : {0.15625, 0.46875, 0.96875}) {  // texel centres (i + 0.5) / 16
    const auto values = runCli("sample " + q(dir / "coat_fresnel.exr") + " --cos-view " + std::to_string(c));
    ASSERT_EQ(values.exitCode, 0) << values.output;
    EXPECT_NEAR(std::stod(values.output), dielectricFresnel(c, 1.5), 1e-5) << c;
  }
  const auto withDir = runCli("sample " + q(dir / "coat_fresnel.exr") + " --cos-view 0.5 --dir 0,0,1");
  EXPECT_EQ(withDir.exitCode, 2);
  EXPECT_NE(withDir.output.find("n.v alone"), std::string::npos) << withDir.output;
  EXPECT_NEAR(sampleAll(dir / "coat_irradiance.exr", {Vec3(0, 0, 1)}).at(0)[0], kPi, 1e-3 * kPi);
  EXPECT_NEAR(sampleAll(dir / "coat.exr", {Vec3(0.1, 0.2, 1)}).at(0)[0], 1.0, 1e-3);
  EXPECT_EQ(infoOf(dir / "coat_fresnel.exr")["metadata"]["spec"]["prefilter"]["fresnel"]["role"], "table");
  expectPreviews(dir / "coat_fresnel.exr");
  expectPreviews(dir / "coat_irradiance.exr");
}

// One piece for a renderer: --tiled puts the mip chain into the output (levels equal to the separate
// files), spec "mip_layout": "tiled" does the same; --sh-output writes irradiance as 9 SH
// coefficients, read back by sample, info, convert and preview.
TEST(ReadOutputs, TiledMipChainsAndShIrradianceReadBack) {
  test::TempDir dir;
  const std::string sky = test::sourcePath("data_samples/environments/sky_latlong.exr");
  const std::string common = " --lobe phong:20 --to paraboloid --resolution 16 --mips --method sh --quiet";
  ASSERT_EQ(runCli("prefilter " + q(sky) + common + " -o " + q(dir / "files.exr")).exitCode, 0);
  const auto tiled = runCli("prefilter " + q(sky) + common + " --tiled -o " + q(dir / "tiled.exr"));
  ASSERT_EQ(tiled.exitCode, 0) << tiled.output;
  EXPECT_FALSE(fs::exists(dir / "tiled_mip1.exr"));
  const auto directions = randomDirections(10, 21);
  for (int level = 0; level < 5; ++level) {
    const std::string flag = "--mip-level " + std::to_string(level);
    const auto a = sampleAll(dir / "tiled.exr", directions, flag), b = sampleAll(dir / "files.exr", directions, flag);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i][0], b[i][0]) << level;
  }
  EXPECT_EQ(infoOf(dir / "tiled.exr")["metadata"]["mip_levels"], 5);
  expectPreviews(dir / "tiled.exr", "--mip-level 1 --view 0,0,1");
  for (const auto& [flags, message] : std::vector<std::pair<std::string, std::string>>{
           {" --lobe phong:20 --to cube --resolution 12 --mips --tiled", "power-of-two"},
           {" --lobe phong:20 --to cube --resolution 16 --tiled", "needs --mips"}}) {
    const auto refused = runCli("prefilter " + q(sky) + flags + " -o " + q(dir / "bad.exr"));
    EXPECT_EQ(refused.exitCode, 2) << refused.output;
    EXPECT_NE(refused.output.find(message), std::string::npos) << refused.output;
  }
  const auto png = runCli("prefilter " + q(sky) + " --lobe phong:20 --to cube --resolution 16 --mips --tiled -o " +
                          q(dir / "bad.png"));
  EXPECT_EQ(png.exitCode, 2);
  EXPECT_NE(png.output.find(".exr"), std::string::npos) << png.output;
  EXPECT_FALSE(fs::exists(dir / "bad.exr"));

  // In a spec: "mip_layout": "tiled" beside "mips", for prefiltered and silhouette maps.
  std::ofstream(dir / "spec.json") << R"({"maps": [
    {"output": "env.exr", "parameterization": "latlong", "resolution": 8,
     "environment": {"file": ")" << sky
                                   << R"(", "lobe": "irradiance", "mips": true, "mip_layout": "tiled"}},
    {"output": "sil.exr", "parameterization": "sphere", "resolution": 32, "samples_per_texel": 4, "mips": true,
     "mip_layout": "tiled", "material": {"model": "silhouette", "width": 15}}]})";
  const auto spec = runCli("bake " + q(dir / "spec.json") + " --quiet");
  ASSERT_EQ(spec.exitCode, 0) << spec.output;
  EXPECT_FALSE(fs::exists(dir / "env_mip1.exr"));
  EXPECT_FALSE(fs::exists(dir / "sil_mip1.exr"));
  EXPECT_EQ(infoOf(dir / "sil.exr")["metadata"]["mip_levels"], 6);
  EXPECT_EQ(runCli("sample " + q(dir / "sil.exr") + " --mip-level 5 --dir 0,0,1").exitCode, 0);
  std::ofstream(dir / "bad_spec.json")
      << R"({"maps": [{"output": "x.exr", "parameterization": "sphere", "resolution": 32,
     "mip_layout": "tiled", "material": {"model": "silhouette", "width": 15}}]})";
  const auto badSpec = runCli("bake " + q(dir / "bad_spec.json") + " --quiet");
  EXPECT_EQ(badSpec.exitCode, 2);
  EXPECT_NE(badSpec.output.find("maps[0].mip_layout"), std::string::npos) << badSpec.output;

  // SH irradiance: the furnace (radiance 1) gives 1 everywhere. A sky of radiance 1 above the horizon
  // (y > 0) has E(n)/pi = (1 + n.y)/2, which three bands hold exactly; its irradiance cube map,
  // computed by the reference sum (another method), agrees.
  const auto furnace =
      runCli("prefilter " + q(kFurnace) + " --lobe irradiance --to cube --resolution 8 --quiet --sh-output " +
             q(dir / "furnace_sh.json") + " -o " + q(dir / "furnace_irr.exr"));
  ASSERT_EQ(furnace.exitCode, 0) << furnace.output;
  for (const Rgb& v : sampleAll(dir / "furnace_sh.json", directions)) EXPECT_NEAR(v[0], 1.0, 1e-3);
  {
    Image hemisphere(256, 128);
    for (int y = 0; y < 128; ++y)
      for (int x = 0; x < 256; ++x)
        hemisphere.set(x, y, y < 64 ? Rgba(1, 1, 1, 1) : Rgba(0, 0, 0, 1));  // top rows: y > 0
    writeImage(hemisphere, dir / "hemisphere.exr");
  }
  ASSERT_EQ(runCli("prefilter " + q(dir / "hemisphere.exr") +
                   " --lobe irradiance --method reference --to cube --resolution 16 --quiet "
                   "--sh-output " +
                   q(dir / "sky_sh.json") + " -o " + q(dir / "sky_irr.exr"))
                .exitCode,
            0);
  const auto fromSh = sampleAll(dir / "sky_sh.json", directions), fromMap = sampleAll(dir / "sky_irr.exr", directions);
  ASSERT_EQ(fromSh.size(), fromMap.size());
  for (std::size_t i = 0; i < fromSh.size(); ++i) {
    const double exact = 0.5 * (1.0 + directions[i].y());
    EXPECT_NEAR(fromSh[i][0], exact, 1e-3) << directions[i].transpose();
    EXPECT_NEAR(fromMap[i][0] / kPi, exact, 1e-2) << directions[i].transpose();  // a 16-texel cube map, bilinear
  }
  const auto document = nlohmann::json::parse(std::ifstream(dir / "sky_sh.json"));
  EXPECT_EQ(document["bands"], 3);
  EXPECT_EQ(document["coefficients"].size(), 9u);
  EXPECT_NE(document["convention"].get<std::string>().find("1/pi"), std::string::npos);
  const auto info = infoOf(dir / "sky_sh.json");
  EXPECT_EQ(info["kind"], "sh_irradiance");
  EXPECT_EQ(info["indexed_by"], "normal");
  ASSERT_EQ(
      runCli("convert " + q(dir / "sky_sh.json") + " --to latlong --resolution 16 --quiet -o " + q(dir / "sh_ll.exr"))
          .exitCode,
      0);
  expectPreviews(dir / "sky_sh.json", "--view 0,1,1");
  const auto wrongLobe = runCli("prefilter " + q(sky) + " --lobe phong:20 --to cube --resolution 8 --sh-output " +
                                q(dir / "x.json") + " -o " + q(dir / "x.exr"));
  EXPECT_EQ(wrongLobe.exitCode, 2);
  EXPECT_NE(wrongLobe.output.find("--sh-output"), std::string::npos) << wrongLobe.output;
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
