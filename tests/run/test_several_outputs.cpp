// Several outputs from one computation ("outputs" in a spec, repeated -o; docs/spec.md) and the texel
// format of texture outputs ("texel_format"): the files read back agree with each other through readers
// that do not share the writer (ktx-parse from npm looks KTX2 texels up the Vulkan way), the map is made
// once, a format that cannot hold the map is refused before any work, and RGB9E5 texels hold the map's
// values within that format's rounding.
#include <gtest/gtest.h>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/io/texture.hpp>
#include <brdfbake/maps/map_mips.hpp>
#include <brdfbake/run/convert_output.hpp>
#include <brdfbake/run/ibl_job.hpp>
#include <brdfbake/run/prefilter_job.hpp>
#include <brdfbake/run/spec_runner.hpp>

#include <cmath>

#include "node_readers.hpp"
#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;

const std::string kSky = test::sourcePath("data_samples/environments/sky_latlong.exr");

// Texel centres of every face of an n x n cube level: a few per face.
std::vector<Vec3> someTexelCentres(int n) {
  std::vector<Vec3> directions;
  for (int face = 0; face < 6; ++face)
    for (int j : {0, n / 2, n - 1})
      for (int i : {0, (n - 1) / 3, n - 1}) directions.push_back(test::vulkanTexelCentre(face, i, j, n));
  return directions;
}

// The texel of `map` (a level read back) holding `direction`.
Rgba texelAt(const MapFile& map, const Vec3& direction) {
  const Vec2 p = map.parameterization->getAddressFor(direction).pixel;
  return map.image.at(std::min(map.image.width() - 1, static_cast<int>(p.x())),
                      std::min(map.image.height() - 1, static_cast<int>(p.y())));
}

PrefilterFiles chainRequest(const fs::path& output, int resolution) {
  PrefilterFiles r;
  r.environment = kSky;
  r.request.glossChain = GlossChain{};  // GGX, every level
  r.request.parameterization = ParameterizationKind::Cube;
  r.request.resolution = resolution;
  r.outputs.mipLayout = MipLayout::Tiled;
  r.outputs.files = {output};
  return r;
}

// How many times the job's tasks finished (progress reaches 1, which ProgressCounter always reports): a
// map made twice finishes twice.
int finishesOf(const PrefilterFiles& request) {
  int finishes = 0;
  runPrefilter(request, Context({.progress = [&finishes](const std::string&, double fraction) {
                 finishes += fraction > 1.0 - 1e-9 ? 1 : 0;
               }}));
  return finishes;
}

TEST(SeveralOutputs, OneGgxChainWrittenAsExrKtx2AndDdsAgreesInEveryLevel) {
  test::TempDir dir;
  const int n = 16;
  PrefilterFiles r = chainRequest(dir / "sky.exr", n);
  r.outputs.files.insert(r.outputs.files.end(), {dir / "sky.ktx2", dir / "sky.dds"});
  const MapResult result = runPrefilter(r);
  const nlohmann::json entry = result.toJson();
  ASSERT_EQ(entry["outputs"].size(), 3u);
  for (const char* name : {"sky.exr", "sky.ktx2", "sky.dds"}) EXPECT_TRUE(fs::exists(dir / name)) << name;
  // Half floats (KTX2, DDS) against the EXR's float: within binary16's rounding, 2^-11 relative.
  const int levels = mipLevelCount(n);
  for (int k = 0; k < levels; ++k) {
    const MapFile exr = readMap(dir / "sky.exr", k), dds = readMap(dir / "sky.dds", k);
    ASSERT_EQ(dds.image.width(), exr.image.width());
    for (const Vec3& d : someTexelCentres(std::max(1, n >> k))) {
      const Rgba a = texelAt(exr, d), b = texelAt(dds, d);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(b[c], a[c], std::abs(a[c]) * 4.9e-4 + 1e-7) << "level " << k;
    }
  }
  if (!test::haveNodePackage("ktx-parse")) GTEST_SKIP() << test::missingNodePackage("ktx-parse");
  // ktx-parse reads level k's texels at the Vulkan texel centres of that level's faces.
  for (int k = 0; k < levels; ++k) {
    const std::vector<Vec3> directions = someTexelCentres(std::max(1, n >> k));
    const nlohmann::json ktx = test::inspectKtx2(dir / "sky.ktx2", directions);
    ASSERT_EQ(ktx["vkFormat"], 97);  // R16G16B16A16_SFLOAT, the default
    ASSERT_EQ(ktx["faceCount"], 6);
    ASSERT_EQ(ktx["levelCount"], levels);
    const MapFile exr = readMap(dir / "sky.exr", k);
    for (std::size_t i = 0; i < directions.size(); ++i) {
      const Rgba a = texelAt(exr, directions[i]);
      for (int c = 0; c < 3; ++c) {
        const double v = ktx["lookups"][k][i][c].get<double>();
        EXPECT_NEAR(v, a[c], std::abs(a[c]) * 4.9e-4 + 1e-7) << "level " << k << " direction " << i;
      }
    }
  }
}

TEST(SeveralOutputs, TheMapIsMadeOnceForAllItsFiles) {
  test::TempDir dir;
  const int once = finishesOf(chainRequest(dir / "one.exr", 16));
  PrefilterFiles three = chainRequest(dir / "three.exr", 16);
  three.outputs.files.insert(three.outputs.files.end(), {dir / "three.ktx2", dir / "three.dds"});
  EXPECT_GT(once, 0);
  EXPECT_EQ(finishesOf(three), once);  // three files, the same work as for one
}

// A spec of one mirror cube map whose outputs and texel format are `keys`, run in `dir`.
SpecRunResult runMirrorSpec(const fs::path& dir, const nlohmann::json& keys) {
  nlohmann::json map = {
      {"parameterization", "cube"}, {"resolution", 8}, {"environment", {{"file", kSky}, {"lobe", "mirror"}}}};
  map.update(keys);
  SpecRunOptions options;
  options.document = {{"maps", nlohmann::json::array({map})}};
  options.outDir = dir;
  return runSpec(options);
}

void expectRefused(const nlohmann::json& keys, const std::string& jsonPath, const std::string& words) {
  test::TempDir dir;
  try {
    runMirrorSpec(dir.path(), keys);
    FAIL() << "accepted " << keys.dump();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(jsonPath), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(dir.path())) << "a refused spec wrote something";
}

TEST(SeveralOutputs, FormatsThatCannotHoldTheMapAreRefusedBeforeAnyWork) {
  expectRefused({{"output", "a.exr"}, {"outputs", {"a.exr", "a.png"}}}, "maps[0].outputs", "not both");
  expectRefused({{"outputs", nlohmann::json::array()}}, "maps[0].outputs", "at least one");
  expectRefused({{"outputs", {"a.exr", "a.bmp"}}}, "maps[0].outputs[1]", "a.bmp");
  expectRefused({{"outputs", {"a.exr", "b/../a.exr"}}}, "maps[0].outputs[1]", "same file as maps[0].outputs[0]");
  // A whole chain in one file: PNG holds one image.
  nlohmann::json chain = {
      {"outputs", {"c.ktx2", "c.png"}},
      {"environment",
       {{"file", kSky}, {"lobe", "ggx"}, {"gloss_chain", nlohmann::json::object()}, {"mip_layout", "tiled"}}}};
  expectRefused(chain, "maps[0].outputs[1]", "a whole mip chain in one file");
  // Texel formats: a name the library does not know, one DDS cannot store, none of the outputs a texture.
  expectRefused({{"outputs", {"t.exr", "t.ktx2"}}, {"texel_format", "rgb8"}}, "maps[0].texel_format",
                "must be one of rgba16f, rgba32f, rgb16f, rgb32f, rgb9e5, rg11b10f");
  expectRefused({{"outputs", {"t.ktx2", "t.dds"}}, {"texel_format", "rgb16f"}}, "maps[0].outputs[1]",
                "DDS has no 3-channel half-float format");
  expectRefused({{"outputs", {"t.exr", "t.png"}}, {"texel_format", "rgb9e5"}}, "maps[0].texel_format",
                "none of the map's outputs");
}

TEST(TexelFormat, Rgb9e5Ktx2HoldsTheMapWithinItsRounding) {
  test::TempDir dir;
  const SpecRunResult result =
      runMirrorSpec(dir.path(), {{"outputs", {"m.exr", "m.ktx2"}}, {"texel_format", "rgb9e5"}});
  ASSERT_FALSE(result.firstError) << result.firstError->what();
  // The library's reader sees the format in the header; the EXR beside it is float.
  EXPECT_EQ(readTextureHeaderOf(dir / "m.ktx2").format, TexelFormat::Rgb9e5);
  if (!test::haveNodePackage("ktx-parse")) GTEST_SKIP() << test::missingNodePackage("ktx-parse");
  const std::vector<Vec3> directions = someTexelCentres(8);
  const nlohmann::json ktx = test::inspectKtx2(dir / "m.ktx2", directions);
  EXPECT_EQ(ktx["vkFormat"], 123);  // VK_FORMAT_E5B9G9R9_UFLOAT_PACK32
  const MapFile exr = readMap(dir / "m.exr");
  for (std::size_t i = 0; i < directions.size(); ++i) {
    const Rgba a = texelAt(exr, directions[i]);
    // One exponent for the three channels: each is rounded to a step of 2^(e - 8) with 2^e <= max < 2^(e + 1),
    // so the error is at most half a step, max * 2^-9 (Vulkan spec, "Shared Exponent Conversion").
    const double largest = std::max({a[0], a[1], a[2]});
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(ktx["lookups"][0][i][c].get<double>(), a[c], largest * std::ldexp(1.0, -9) + 1e-9) << i;
    }
  }
}

TEST(SeveralOutputs, ConvertWritesTheOneResampledMapInEachFormat) {
  test::TempDir dir;
  ConvertOptions options;
  options.source.path = kSky;
  options.source.from = ParameterizationKind::LatLong;
  options.to = ParameterizationKind::Cube;
  options.resolution = 8;
  options.samplesPerTexel = 1;
  options.outputs.files = {dir / "s.exr", dir / "s.dds"};
  options.outputs.texelFormat = TexelFormat::Rgba32Float;  // the DDS only: float32 keeps the EXR's values exactly
  const ConvertResult result = convertOutput(options);
  EXPECT_EQ(readTextureHeaderOf(dir / "s.dds").format, TexelFormat::Rgba32Float);
  const MapFile exr = readMap(dir / "s.exr"), dds = readMap(dir / "s.dds");
  for (const Vec3& d : someTexelCentres(8)) {
    const Rgba a = texelAt(exr, d), b = texelAt(dds, d);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(b[c], a[c]);
  }
  options.outputs.files = {dir / "t.exr", dir / "t.png"};
  EXPECT_THROW(convertOutput(options), Error);  // a texel format and no texture output
  EXPECT_FALSE(fs::exists(dir / "t.exr"));
}

TEST(TexelFormat, IblWritesEveryTextureInTheFormatAsked) {
  test::TempDir dir;
  IblFiles options;
  options.environment = kSky;
  options.outputs.folder = dir.path();
  options.outputs.stem.clear();  // the environment's
  options.request.resolution = 8;
  options.request.irradianceResolution = 4;
  options.request.skyboxResolution = 8;
  options.request.dfgSize = 8;
  options.outputs.texelFormat = TexelFormat::Rgb9e5;
  runIbl(options);
  for (const char* file :
       {"sky_latlong_ggx.ktx2", "sky_latlong_irradiance.ktx2", "sky_latlong_skybox.ktx2", "sky_latlong_dfg.ktx2"}) {
    EXPECT_EQ(readTextureHeaderOf(dir / file).format, TexelFormat::Rgb9e5) << file;
  }
  options.outputs.format = "exr";
  options.outputs.folder = dir / "exr";
  EXPECT_THROW(runIbl(options), Error);  // EXR stores floats: no texel format
}

}  // namespace
}  // namespace brdfbake
