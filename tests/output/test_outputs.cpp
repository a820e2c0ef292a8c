// Outputs a renderer loads in one piece: a mip chain as one tiled, MIP-mapped OpenEXR (read back
// with OpenImageIO's own ImageInput and TextureSystem, level by level against the separate-file
// chain), and irradiance as 9 spherical-harmonic coefficients (against the closed forms of a
// constant and a hemispherical sky, and the documented basis polynomials).
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/env/sh_irradiance.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/maps/map_mips.hpp>
#include <brdfbake/output/baked_output.hpp>

#include "map_function_support.hpp"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <cstdio>
#include <random>
#include <sstream>

#include "test_support.hpp"

namespace brdfbake {
namespace {

using test::randomDirections;
namespace fs = std::filesystem;

// A lat-long environment of `rows` rows whose texels take f at their centres.
Environment latLongEnvironment(int rows, const std::function<Rgb(const Vec3&)>& f) {
  const auto map = makeParameterization(ParameterizationKind::LatLong, rows);
  Image image(map->width(), map->height());
  for (int y = 0; y < map->height(); ++y)
    for (int x = 0; x < map->width(); ++x) {
      const Rgb v = f(*map->getDirectionFor(Vec2(x + 0.5, y + 0.5)));
      image.set(x, y, Rgba(v[0], v[1], v[2], 1.0));
    }
  return makeEnvironment(std::move(image), ParameterizationKind::LatLong, "test");
}

// Reads level `level` of `path` with OpenImageIO directly (not through brdfbake).
std::vector<float> oiioLevel(const fs::path& path, int level, int& width, int& height) {
  auto in = OIIO::ImageInput::open(path.string());
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in || !in->seek_subimage(0, level)) return {};
  width = in->spec().width, height = in->spec().height;
  std::vector<float> pixels(static_cast<std::size_t>(width) * height * 4);
  EXPECT_TRUE(in->read_image(0, level, 0, 4, OIIO::TypeDesc::FLOAT, pixels.data())) << in->geterror();
  return pixels;
}

class TiledMips : public ::testing::TestWithParam<ParameterizationKind> {};

TEST_P(TiledMips, OneFileHoldsEveryLevelAsMaketxWritesIt) {
  const ParameterizationKind kind = GetParam();
  test::TempDir dir;
  const Environment sky = loadEnvironment(test::sourcePath("data_samples/environments/sky_latlong.exr"));
  PrefilterOptions options;
  options.parameterization = kind;
  options.resolution = kind == ParameterizationKind::Cube ? 8 : 16;
  options.mips = true;
  options.method = PrefilterMethod::SphericalHarmonics;
  const PrefilteredMap map = prefilter(sky, PrefilterLobe::phong(20), options);
  writePrefilteredMap(map, dir / "files.exr", {});
  writePrefilteredMap(map, dir / "tiled.exr", {}, CubeLayout::Cross, {}, MipLayout::Tiled);
  EXPECT_FALSE(fs::exists(dir / "tiled_mip1.exr"));

  // OpenImageIO sees one subimage, tiled 64 x 64, MIP-mapped down to 1 x 1 as OpenEXR lays it out.
  auto in = OIIO::ImageInput::open((dir / "tiled.exr").string());
  ASSERT_TRUE(in) << OIIO::geterror();
  EXPECT_EQ(in->spec().tile_width, 64);
  EXPECT_EQ(in->spec().tile_height, 64);
  EXPECT_EQ(in->spec().get_string_attribute("textureformat"), "Plain Texture");
  EXPECT_FALSE(in->seek_subimage(1, 0));  // one subimage
  int levels = 1;
  while (in->seek_subimage(0, levels)) ++levels;
  const int w = map.map->width(), h = map.map->height();
  const int expected = static_cast<int>(std::floor(std::log2(std::max(w, h)))) + 1;
  EXPECT_EQ(levels, expected);
  in->close();

  // Every map level equals the separate file's texels; the levels below the map's last hold its mean.
  const int mapLevels = static_cast<int>(map.levels.size());
  for (int level = 0; level < levels; ++level) {
    SCOPED_TRACE(level);
    int lw = 0, lh = 0;
    const std::vector<float> tiled = oiioLevel(dir / "tiled.exr", level, lw, lh);
    ASSERT_EQ(lw, std::max(1, w >> level));
    ASSERT_EQ(lh, std::max(1, h >> level));
    if (level < mapLevels) {
      const Image separate = readImage(mipLevelPath(dir / "files.exr", level));
      ASSERT_EQ(separate.width(), lw);
      for (int y = 0; y < lh; ++y)
        for (int x = 0; x < lw; ++x)
          for (int c = 0; c < 4; ++c) {
            ASSERT_EQ(tiled[(static_cast<std::size_t>(y) * lw + x) * 4 + c], separate.at(x, y)[c]) << x << "," << y;
          }
      // brdfbake reads the same level as a map of its own resolution.
      const MapFile file = readMap(dir / "tiled.exr", level);
      EXPECT_EQ(file.info.resolution, std::max(1, options.resolution >> level));
    } else {
      for (std::size_t i = 0; i + 4 <= tiled.size(); i += 4) EXPECT_FLOAT_EQ(tiled[i], tiled[0]);
      EXPECT_THROW(readMap(dir / "tiled.exr", level), Error);
    }
  }

  // OIIO's TextureSystem reads it: a bilinear lookup at a texel centre of level 0 returns the texel.
  // The process-wide shared system, never destroyed here: Debian's OpenImageIO 2.4
  // TextureSystem::destroy frees a private system with a mismatched sized delete, which
  // AddressSanitizer reports (new-delete-type-mismatch inside libOpenImageIO).
  OIIO::TextureSystem* ts = OIIO::TextureSystem::create(true);
  OIIO::TextureOpt opt;
  opt.interpmode = OIIO::TextureOpt::InterpBilinear;
  opt.mipmode = OIIO::TextureOpt::MipModeNoMIP;
  const Image level0 = readImage(dir / "files.exr");
  std::vector<std::pair<int, int>> texels;  // inside the map's domain (alpha 1: OIIO would premultiply by coverage)
  for (int y = 1; y < h && texels.size() < 6; y += std::max(1, h / 5))
    for (int x = 1; x < w && texels.size() < 6; x += std::max(1, w / 7))
      if (level0.at(x, y)[3] == 1.0f) texels.emplace_back(x, y);
  ASSERT_GE(texels.size(), 3u);
  for (const auto& [x, y] : texels) {
    float rgba[4] = {0, 0, 0, 0};
    const float s = (x + 0.5f) / w, t = (y + 0.5f) / h;
    ASSERT_TRUE(ts->texture(OIIO::ustring((dir / "tiled.exr").string()), opt, s, t, 0, 0, 0, 0, 4, rgba))
        << ts->geterror();
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(rgba[c], level0.at(x, y)[c], 1e-5 * std::abs(level0.at(x, y)[c]) + 1e-6) << x << "," << y;
  }
  ts->invalidate(OIIO::ustring((dir / "tiled.exr").string()));  // close the file before the folder goes
}

INSTANTIATE_TEST_SUITE_P(Kinds, TiledMips,
                         ::testing::Values(ParameterizationKind::Sphere, ParameterizationKind::Paraboloid,
                                           ParameterizationKind::Cube, ParameterizationKind::LatLong),
                         [](const auto& param) { return std::string(toString(param.param)); });

TEST(IrradianceQuantity, MapsWrittenBeforeTheConventionHoldEAndReadAsEOverPi) {
  // An irradiance cube as brdfbake wrote it before "irradiance_quantity": texels hold E (pi for a
  // furnace). Lookups return E/pi, and describe() says so; a map that states E/pi is read as is.
  test::TempDir dir;
  const CubeMap cube(4);
  const Image furnaceE(cube.width(), cube.height(), Rgba(kPi, kPi, kPi, 1));
  MapInfo info{ParameterizationKind::Cube, 4, kConventionVersion, {{"prefilter", {{"lobe", "irradiance"}}}}};
  writeMap(furnaceE, info, dir / "old.exr");
  const BakedOutput old = BakedOutput::open(dir / "old.exr");
  EXPECT_NEAR(old.lookup(Vec3(0.3, 0.2, -1))[0], 1.0, 1e-6);
  EXPECT_EQ(old.describe()["quantity"], "E/pi");
  EXPECT_TRUE(old.describe().contains("quantity_note"));
  info.spec["prefilter"]["irradiance_quantity"] = "E/pi";
  writeMap(Image(cube.width(), cube.height(), Rgba(1, 1, 1, 1)), info, dir / "new.exr");
  const BakedOutput stated = BakedOutput::open(dir / "new.exr");
  EXPECT_NEAR(stated.lookup(Vec3(0.3, 0.2, -1))[0], 1.0, 1e-6);
  EXPECT_FALSE(stated.describe().contains("quantity_note"));
  // An SH file stating another quantity is refused, naming the key.
  nlohmann::json sh = irradianceShToJson(ShExpansion{2, std::vector<Rgb>(9, Rgb::Zero())}, nlohmann::json::object());
  sh["quantity"] = "E";
  try {
    irradianceShFromJson(sh, "sh.json");
    ADD_FAILURE() << "quantity E accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("sh.json: quantity"), std::string::npos) << error.what();
  }
}

TEST(TiledMips, CubeFacesAreSixTiledFilesAndBadRequestsAreRefused) {
  test::TempDir dir;
  const Environment furnace = loadEnvironment(test::sourcePath("data_samples/environments/furnace_latlong.exr"));
  PrefilterOptions options;
  options.parameterization = ParameterizationKind::Cube;
  options.resolution = 8;
  options.mips = true;
  const PrefilteredMap map = prefilter(furnace, PrefilterLobe::irradiance(), options);
  const auto written = writePrefilteredMap(map, dir / "c.exr", {}, CubeLayout::Faces, {}, MipLayout::Tiled);
  ASSERT_EQ(written.files.size(), 6u);
  EXPECT_EQ(imageMipLevelCount(dir / "c_negy.exr"), 4);  // 8, 4, 2, 1: a face halves exactly
  for (int level = 0; level < 4; ++level) {
    OpenOutputOptions open;
    open.mipLevel = level;
    const BakedOutput out = BakedOutput::open(dir / "c.exr", open);
    EXPECT_NEAR(out.lookup(Vec3(0.2, -1, 0.3))[0], 1.0, 1e-4) << level;  // irradiance maps hold E/pi
  }
  EXPECT_NE(tiledMipProblem(dir / "c.png", 8), "");
  EXPECT_NE(tiledMipProblem(dir / "c.exr", 12), "");
  EXPECT_EQ(tiledMipProblem(dir / "c.exr", 16), "");
  PrefilterOptions odd = options;
  odd.resolution = 6;
  EXPECT_THROW(writePrefilteredMap(prefilter(furnace, PrefilterLobe::irradiance(), odd), dir / "odd.exr", {},
                                   CubeLayout::Cross, {}, MipLayout::Tiled),
               Error);
  EXPECT_FALSE(fs::exists(dir / "odd.exr"));
}

// --mips --tiled of a 1 x 1 map: one level, so one tiled file of one level (it said "needs the mip
// levels (PrefilterOptions::mips)", naming an option the user had set). Without mips: refused in words.
TEST(TiledMips, AOneTexelMapIsAOneLevelFileAndNoMipsIsRefusedInWords) {
  test::TempDir dir;
  const Environment furnace = loadEnvironment(test::sourcePath("data_samples/environments/furnace_latlong.exr"));
  PrefilterOptions options;
  options.parameterization = ParameterizationKind::Sphere;
  options.resolution = 1;
  options.mips = true;
  writePrefilteredMap(prefilter(furnace, PrefilterLobe::irradiance(), options), dir / "dot.exr", {}, CubeLayout::Cross,
                      {}, MipLayout::Tiled);
  EXPECT_EQ(imageMipLevelCount(dir / "dot.exr"), 1);
  options.resolution = 8;
  options.mips = false;
  try {
    writePrefilteredMap(prefilter(furnace, PrefilterLobe::irradiance(), options), dir / "flat.exr", {},
                        CubeLayout::Cross, {}, MipLayout::Tiled);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "a tiled MIP-mapped output holds every mip level; prefilter with mips on (\"mips\": true, --mips)");
  }
}

// A Fresnel table written before the rename says "parameterization": "fresnel_profile"; it still
// opens as a Fresnel table. Texels hold 0.1, 0.2, 0.3, 0.4 at cos theta = 0.125, 0.375, ...: at
// n.v = 0.5, halfway between texels 1 and 2, the linear lookup gives 0.25.
TEST(FresnelTable, AFileWithTheFormerParameterizationNameStillOpens) {
  test::TempDir dir;
  Image image = fresnelTableImage({Rgb::Constant(0.1), Rgb::Constant(0.2), Rgb::Constant(0.3), Rgb::Constant(0.4)});
  EXPECT_EQ(image.metadata["parameterization"], "fresnel_table");
  image.metadata["parameterization"] = "fresnel_profile";
  writeImage(image, dir / "old.exr");
  const BakedOutput out = BakedOutput::open(dir / "old.exr");
  EXPECT_EQ(out.kind(), OutputKind::FresnelTable);
  EXPECT_NEAR(out.lookup(Vec3::UnitZ(), 0.5)[1], 0.25, 1e-6);
  EXPECT_THROW(MapInfo::fromJson(image.metadata), Error);  // not a 2-D map, under either name
}

// The basis the JSON states, written out as polynomials, against evaluateShBasis.
TEST(ShIrradiance, TheDocumentedBasisIsTheOneEvaluated) {
  for (const Vec3& d : randomDirections(20, 5)) {
    const double x = d.x(), y = d.y(), z = d.z();
    const double expected[9] = {0.282095,
                                -0.488603 * y,
                                0.488603 * z,
                                -0.488603 * x,
                                1.092548 * x * y,
                                -1.092548 * y * z,
                                0.315392 * (3 * z * z - 1),
                                -1.092548 * x * z,
                                0.546274 * (x * x - y * y)};
    double basis[9];
    evaluateShBasis(2, d, basis);
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(basis[i], expected[i], 2e-6) << i;
  }
}

TEST(ShIrradiance, AConstantEnvironmentGivesItsRadianceEverywhere) {
  const Rgb radiance(0.5, 2.0, 3.0);
  const Environment constant = latLongEnvironment(64, [&](const Vec3&) { return radiance; });
  const ShExpansion sh = irradianceSh(constant);
  double scratch[9];
  for (const Vec3& n : randomDirections(50, 9)) {
    const Rgb value = sh.evaluate(n, scratch);  // E / pi: L for a constant environment (E = pi L)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(value[c], radiance[c], 5e-4 * radiance[c]) << n.transpose();
  }
}

// A sky of radiance 1 over the upper hemisphere (y > 0): E(n) = pi (1 + n.y) / 2 exactly, which has
// bands 0 and 1 only, so three bands represent it exactly (Ramamoorthi & Hanrahan 2001: band 2 of a
// step is 0 and odd bands above 1 vanish under the cosine lobe).
TEST(ShIrradiance, AHemisphericalSkyMatchesTheClosedForm) {
  const Environment sky = latLongEnvironment(128, [](const Vec3& d) { return d.y() > 0 ? Rgb::Ones() : Rgb::Zero(); });
  const ShExpansion sh = irradianceSh(sky);
  double scratch[9];
  for (const Vec3& n : randomDirections(50, 11)) {
    EXPECT_NEAR(sh.evaluate(n, scratch)[0], 0.5 * (1.0 + n.y()), 5e-4) << n.transpose();
  }
  // Round trip through the JSON a renderer reads.
  const nlohmann::json document = irradianceShToJson(sh, {{"file", "test"}});
  EXPECT_EQ(document["coefficients"].size(), 9u);
  const ShExpansion back = irradianceShFromJson(document, "doc");
  for (int i = 0; i < 9; ++i) {
    EXPECT_TRUE((back.coefficients[static_cast<std::size_t>(i)] == sh.coefficients[static_cast<std::size_t>(i)]).all())
        << i;
  }
  nlohmann::json bad = document;
  bad["coefficients"].erase(3);
  EXPECT_THROW(irradianceShFromJson(bad, "doc"), Error);
}

// A sky of radiance y^2 has bands 0 and 2 only (y^2 = 1/3 + 2/3 P2(y)), so three bands hold its
// irradiance exactly: E(n)/pi = 1/3 + 2/3 (A_2/pi) P2(n.y) with A_2 = pi/4 (Ramamoorthi & Hanrahan
// 2001), = (1 + n.y^2) / 4. By hand: n = y gives 2 pi (1/4) / pi = 1/2; n = x gives (pi/4) / pi = 1/4.
TEST(ShIrradiance, AQuadraticSkyMatchesTheClosedFormThroughBandTwo) {
  const Environment sky = latLongEnvironment(128, [](const Vec3& d) { return Rgb::Constant(d.y() * d.y()); });
  const ShExpansion sh = irradianceSh(sky);
  double scratch[9];
  for (const Vec3& n : randomDirections(50, 13)) {
    EXPECT_NEAR(sh.evaluate(n, scratch)[0], 0.25 * (1.0 + n.y() * n.y()), 5e-4) << n.transpose();
  }
}

// cmgen's lines are the coefficients times the basis constants: Ramamoorthi & Hanrahan 2001's
// 0.282095, 0.488603, 1.092548, 0.315392 and 0.546274, with the signs of the basis above.
TEST(ShIrradiance, CmgenLinesArePreScaledByThePublishedConstants) {
  const double expected[9] = {0.282095,  -0.488603, 0.488603,  -0.488603, 1.092548,
                              -1.092548, 0.315392,  -1.092548, 0.546274};
  const std::string text = irradianceShCmgenText(ShExpansion{2, std::vector<Rgb>(9, Rgb::Ones())});
  std::istringstream lines(text);
  std::string line;
  int i = 0;
  while (std::getline(lines, line)) {
    ASSERT_LT(i, 9) << line;
    double r = 0.0, g = 0.0, b = 0.0;
    ASSERT_EQ(std::sscanf(line.c_str(), "(%lf, %lf, %lf)", &r, &g, &b), 3) << line;
    EXPECT_NEAR(r, expected[i], 1e-6) << line;
    EXPECT_EQ(g, r);
    EXPECT_EQ(b, r);
    ++i;
  }
  EXPECT_EQ(i, 9);
}

}  // namespace
}  // namespace brdfbake
