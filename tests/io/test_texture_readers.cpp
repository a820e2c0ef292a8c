// Face order and orientation of cube textures, pinned by readers the writer does not share:
// ktx-parse (npm) for KTX2 and parse-dds (npm) for DDS headers, run by node on tests/js/*.mjs, and
// a small DDS reader written here from Microsoft's DDS specification. Each looks up directions the
// Vulkan way (major axis, then sc/tc by the specification's table, implemented in
// tests/js/cube_lookup.mjs and below, not by brdfbake's CubeMap) in a cube made from
// data_samples/environments/colored_cube_latlong.exr, whose faces have known colours
// (docs/prefilter.md: +x red, -x cyan, +y green, -y magenta, +z blue, -z yellow), and in a cube
// whose texels hold their own direction (orientation within each face).
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/io/texture.hpp>
#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/maps/map_mips.hpp>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>

#include "node_readers.hpp"
#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;

// The colored cube environment as a cube map: each texel samples the lat-long file at its centre's
// direction (brdfbake's CubeMap, the writer's side).
Image coloredCube(int n) {
  const MapFile latlong =
      adoptImage(readImage(fs::path(BRDFBAKE_SOURCE_DIR) / "data_samples/environments/colored_cube_latlong.exr"),
                 ParameterizationKind::LatLong, "colored_cube_latlong.exr");
  const CubeMap cube(n);
  Image image(cube.width(), cube.height(), Rgba(0, 0, 0, 0));
  for (int y = 0; y < cube.height(); ++y)
    for (int x = 0; x < cube.width(); ++x)
      if (const auto d = cube.getDirectionFor(Vec2(x + 0.5, y + 0.5))) {
        Rgba v = sampleBilinear(latlong.image, *latlong.parameterization, *d);
        v[3] = 1.0;
        image.set(x, y, v);
      }
  return image;
}

// Directions well inside each face (so mip levels keep the face's own colour), with the colour
// each face has, and each looked up both at and off the face centre.
struct Known {
  Vec3 direction;
  Rgb colour;
};
std::vector<Known> knownDirections() {
  const Rgb red(1, 0, 0), cyan(0, 1, 1), green(0, 1, 0), magenta(1, 0, 1), blue(0, 0, 1), yellow(1, 1, 0);
  return {{{1, 0, 0}, red},   {{1, 0.3, -0.2}, red},   {{-1, 0, 0}, cyan},    {{-1, -0.25, 0.3}, cyan},
          {{0, 1, 0}, green}, {{0.2, 1, 0.3}, green},  {{0, -1, 0}, magenta}, {{-0.3, -1, -0.2}, magenta},
          {{0, 0, 1}, blue},  {{0.25, -0.3, 1}, blue}, {{0, 0, -1}, yellow},  {{-0.2, 0.3, -1}, yellow}};
}

std::vector<Vec3> knownVectors() {
  std::vector<Vec3> out;
  for (const Known& k : knownDirections()) out.push_back(k.direction);
  return out;
}

// The colours at every known direction of every level with faces of 8 texels or more (coarser
// faces are all edge texels, which the mip chain blends with the neighbouring faces).
void expectKnownColours(const nlohmann::json& lookups, int size, double tolerance) {
  const auto known = knownDirections();
  for (std::size_t k = 0; k < lookups.size() && (size >> k) >= 8; ++k)
    for (std::size_t i = 0; i < known.size(); ++i)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(lookups[k][i][c].get<double>(), known[i].colour[c], tolerance)
            << "level " << k << " direction " << known[i].direction.transpose() << " channel " << c;
}

TEST(TextureReaders, Ktx2CubeAsKtxParseReadsItAndAVulkanSamplerLooksItUp) {
  if (!test::haveNodePackage("ktx-parse")) GTEST_SKIP() << test::missingNodePackage("ktx-parse");
  test::TempDir dir;
  const CubeMap cube(32);
  const std::vector<Image> chain = environmentMipChain(coloredCube(32), cube);
  const MapInfo info{ParameterizationKind::Cube, 32, kConventionVersion, {{"environment", "colored cube"}}};
  writeTiledMap(chain, info, dir / "cube.ktx2");
  const nlohmann::json ktx =
      test::runNodeReader("inspect_ktx2.mjs", dir / "cube.ktx2", test::directionsJson(knownVectors()));
  EXPECT_EQ(ktx["vkFormat"], 97);  // R16G16B16A16_SFLOAT
  EXPECT_EQ(ktx["typeSize"], 2);
  EXPECT_EQ(ktx["pixelWidth"], 32);
  EXPECT_EQ(ktx["pixelHeight"], 32);
  EXPECT_EQ(ktx["pixelDepth"], 0);
  EXPECT_EQ(ktx["layerCount"], 0);
  EXPECT_EQ(ktx["faceCount"], 6);
  EXPECT_EQ(ktx["levelCount"], 6);
  EXPECT_EQ(ktx["supercompressionScheme"], 0);
  // Data format descriptor: RGBSDA, BT.709, linear, 8 bytes, four signed-float 16-bit samples.
  const nlohmann::json& dfd = ktx["dfd"];
  EXPECT_EQ(dfd["vendorId"], 0);
  EXPECT_EQ(dfd["descriptorType"], 0);
  EXPECT_EQ(dfd["versionNumber"], 2);
  EXPECT_EQ(dfd["colorModel"], 1);
  EXPECT_EQ(dfd["colorPrimaries"], 1);
  EXPECT_EQ(dfd["transferFunction"], 1);
  EXPECT_EQ(dfd["bytesPlane"][0], 8);
  ASSERT_EQ(dfd["samples"].size(), 4u);
  const int channels[4] = {0, 1, 2, 15};
  for (int s = 0; s < 4; ++s) {
    EXPECT_EQ(dfd["samples"][s]["bitOffset"], 16 * s);
    EXPECT_EQ(dfd["samples"][s]["bitLength"], 15);
    EXPECT_EQ(dfd["samples"][s]["channelType"], 0xC0 | channels[s]);
    EXPECT_EQ(dfd["samples"][s]["sampleLower"], 0xBF800000u);
    EXPECT_EQ(dfd["samples"][s]["sampleUpper"], 0x3F800000u);
  }
  // Key/value data sorted by key, with the writer, the orientation and brdfbake's metadata.
  EXPECT_EQ(ktx["keys"], nlohmann::json({"KTXorientation", "KTXwriter", "brdfbake.metadata"}));
  EXPECT_EQ(ktx["keyValue"]["KTXorientation"], "rd");
  EXPECT_EQ(ktx["keyValue"]["KTXwriter"], std::string("brdfbake ") + BRDFBAKE_VERSION_STRING);
  const nlohmann::json metadata = nlohmann::json::parse(ktx["keyValue"]["brdfbake.metadata"].get<std::string>());
  EXPECT_EQ(metadata["parameterization"], "cube");
  EXPECT_EQ(metadata["mip_levels"], 6);
  EXPECT_EQ(ktx["index"]["dfdByteOffset"], 80 + 24 * 6);
  EXPECT_EQ(ktx["index"]["kvdByteOffset"],
            ktx["index"]["dfdByteOffset"].get<int>() + ktx["index"]["dfdByteLength"].get<int>());
  // Levels smallest first, 8-byte aligned, six faces each.
  for (int k = 0; k < 6; ++k) {
    const nlohmann::json& level = ktx["levels"][k];
    const int n = 32 >> k;
    EXPECT_EQ(level["byteLength"], 6 * n * n * 8) << k;
    EXPECT_EQ(level["uncompressedByteLength"], level["byteLength"]) << k;
    EXPECT_EQ(level["byteOffset"].get<std::uint64_t>() % 8, 0u) << k;
    if (k > 0) {
      EXPECT_LT(level["byteOffset"].get<std::uint64_t>(), ktx["levels"][k - 1]["byteOffset"].get<std::uint64_t>());
    }
  }
  expectKnownColours(ktx["lookups"], 32, 0.01);
}

TEST(TextureReaders, PackedFormatsReadTheSameByKtxParse) {
  if (!test::haveNodePackage("ktx-parse")) GTEST_SKIP() << test::missingNodePackage("ktx-parse");
  test::TempDir dir;
  const MapInfo info{ParameterizationKind::Cube, 16, kConventionVersion, {}};
  const Image image = coloredCube(16);
  for (const TexelFormat format : {TexelFormat::Rgb9e5, TexelFormat::B10g11r11, TexelFormat::Rgba32Float}) {
    WriteOptions options;
    options.texelFormat = format;
    const fs::path path = dir / (std::string(toString(format)) + ".ktx2");
    writeMap(image, info, path, CubeLayout::Cross, options);
    const nlohmann::json ktx = test::runNodeReader("inspect_ktx2.mjs", path, test::directionsJson(knownVectors()));
    SCOPED_TRACE(path.string());
    EXPECT_EQ(ktx["vkFormat"], format == TexelFormat::Rgb9e5 ? 123 : format == TexelFormat::B10g11r11 ? 122 : 109);
    expectKnownColours(ktx["lookups"], 16, 0.01);
  }
}

// A cube whose texels hold the direction of their centre (brdfbake's CubeMap, the writer's side).
Image directionCube(int n) {
  const CubeMap cube(n);
  Image image(cube.width(), cube.height(), Rgba(0, 0, 0, 0));
  for (int y = 0; y < cube.height(); ++y)
    for (int x = 0; x < cube.width(); ++x)
      if (const auto d = cube.getDirectionFor(Vec2(x + 0.5, y + 0.5))) image.set(x, y, Rgba(d->x(), d->y(), d->z(), 1));
  return image;
}

std::vector<Vec3> randomDirections(int count) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  std::vector<Vec3> out;
  while (static_cast<int>(out.size()) < count) {
    const Vec3 d(g(rng), g(rng), g(rng));
    if (d.norm() > 1e-3) out.push_back(d.normalized());
  }
  return out;
}

// The texel a nearest lookup returns lies within one texel of the direction: at most half a
// texel's diagonal, 0.5 sqrt(2) (2 / N) in face coordinates, which is at most that angle.
void expectTexelsHoldTheirDirections(const nlohmann::json& values, const std::vector<Vec3>& directions, int n) {
  const double limit = std::sqrt(2.0) / n;
  for (std::size_t i = 0; i < directions.size(); ++i) {
    const Vec3 stored(values[i][0].get<double>(), values[i][1].get<double>(), values[i][2].get<double>());
    EXPECT_LT(std::acos(std::clamp(stored.normalized().dot(directions[i]), -1.0, 1.0)), limit)
        << "direction " << directions[i].transpose() << " read texel holding " << stored.transpose();
  }
}

TEST(TextureReaders, OrientationWithinEveryFaceIsVulkansInKtx2AndDds) {
  if (!test::haveNodePackage("ktx-parse")) GTEST_SKIP() << test::missingNodePackage("ktx-parse");
  test::TempDir dir;
  const int n = 16;
  const MapInfo info{ParameterizationKind::Cube, n, kConventionVersion, {}};
  WriteOptions full;
  full.texelFormat = TexelFormat::Rgba32Float;
  const CubeMap cube(n);
  const std::vector<Image> chain = environmentMipChain(directionCube(n), cube);
  writeTiledMap(std::vector<Image>{chain}, info, dir / "d.ktx2", CubeLayout::Cross, full);
  writeTiledMap(std::vector<Image>{chain}, info, dir / "d.dds", CubeLayout::Cross, full);
  const std::vector<Vec3> directions = randomDirections(400);
  const nlohmann::json ktx = test::runNodeReader("inspect_ktx2.mjs", dir / "d.ktx2", test::directionsJson(directions));
  expectTexelsHoldTheirDirections(ktx["lookups"][0], directions, n);
  if (test::haveNodePackage("parse-dds")) {
    const nlohmann::json dds = test::runNodeReader("inspect_dds.mjs", dir / "d.dds", test::directionsJson(directions));
    EXPECT_EQ(dds["format"], "rgba32f");
    EXPECT_EQ(dds["cubemap"], true);
    EXPECT_EQ(dds["shape"], nlohmann::json({n, n}));
    ASSERT_EQ(dds["images"].size(), 6u * 5);
    // Faces outer, levels inner, right after the 148 bytes of DDS_HEADER and DDS_HEADER_DXT10.
    std::uint64_t offset = 148;
    for (int f = 0; f < 6; ++f)
      for (int k = 0; k < 5; ++k) {
        const nlohmann::json& image = dds["images"][f * 5 + k];
        EXPECT_EQ(image["offset"], offset) << f << " " << k;
        EXPECT_EQ(image["length"], (n >> k) * (n >> k) * 16) << f << " " << k;
        offset += image["length"].get<std::uint64_t>();
      }
    EXPECT_EQ(offset, fs::file_size(dir / "d.dds"));
    expectTexelsHoldTheirDirections(dds["lookups"][0], directions, n);
  }
}

// ---- a DDS reader from the specification, sharing nothing with maps/dds.cpp --------------------

struct SmallDds {
  std::uint32_t width = 0, height = 0, levels = 0, dxgi = 0, faces = 0;
  std::vector<char> bytes;
  std::size_t dataStart = 0;
  std::uint32_t word(std::size_t at) const {
    std::uint32_t v;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
  }
};

SmallDds readSmallDds(const fs::path& path) {
  SmallDds dds;
  std::ifstream in(path, std::ios::binary);
  dds.bytes.assign(std::istreambuf_iterator<char>(in), {});
  EXPECT_GE(dds.bytes.size(), 148u);
  EXPECT_EQ(std::string(dds.bytes.data(), 4), "DDS ");
  EXPECT_EQ(dds.word(4), 124u);                              // DDS_HEADER.dwSize
  dds.height = dds.word(12), dds.width = dds.word(16);       // dwHeight, dwWidth
  dds.levels = dds.word(28);                                 // dwMipMapCount
  EXPECT_EQ(std::string(dds.bytes.data() + 84, 4), "DX10");  // ddspf.dwFourCC
  dds.dxgi = dds.word(128);                                  // DDS_HEADER_DXT10.dxgiFormat
  const bool cube = (dds.word(136) & 0x4) != 0;              // miscFlag TEXTURECUBE
  EXPECT_EQ(cube, (dds.word(112) & 0xFE00) == 0xFE00);       // dwCaps2: CUBEMAP and all faces
  dds.faces = cube ? 6 * dds.word(140) : dds.word(140);      // arraySize counts cubes
  dds.dataStart = 148;
  return dds;
}

float halfValue(std::uint16_t h) {  // binary16 by its definition
  const int e = (h >> 10) & 31, m = h & 1023;
  const float v = e == 0 ? std::ldexp(float(m), -24) : std::ldexp(1.0f + m / 1024.0f, e - 15);
  return (h & 0x8000) ? -v : v;
}

// Vulkan's face selection again, in C++ (a copy of tests/js/cube_lookup.mjs, not brdfbake's CubeMap).
std::array<int, 3> vulkanTexel(const Vec3& r, int n) {
  const double ax = std::abs(r.x()), ay = std::abs(r.y()), az = std::abs(r.z());
  int face;
  double sc, tc, rc;
  if (ax >= ay && ax >= az) {
    rc = ax, face = r.x() >= 0 ? 0 : 1, sc = r.x() >= 0 ? -r.z() : r.z(), tc = -r.y();
  } else if (ay >= az) {
    rc = ay, face = r.y() >= 0 ? 2 : 3, sc = r.x(), tc = r.y() >= 0 ? r.z() : -r.z();
  } else {
    rc = az, face = r.z() >= 0 ? 4 : 5, sc = r.z() >= 0 ? r.x() : -r.x(), tc = -r.y();
  }
  auto texel = [&](double st) { return std::clamp(static_cast<int>(std::floor(st * n)), 0, n - 1); };
  return {face, texel(0.5 * (sc / rc + 1)), texel(0.5 * (tc / rc + 1))};
}

TEST(TextureReaders, DdsCubeReadByASmallReaderFromTheSpecification) {
  test::TempDir dir;
  const MapInfo info{ParameterizationKind::Cube, 32, kConventionVersion, {}};
  writeTiledMap(environmentMipChain(coloredCube(32), CubeMap(32)), info, dir / "c.dds");
  const SmallDds dds = readSmallDds(dir / "c.dds");
  EXPECT_EQ(dds.width, 32u);
  EXPECT_EQ(dds.height, 32u);
  EXPECT_EQ(dds.levels, 6u);
  EXPECT_EQ(dds.dxgi, 10u);  // DXGI_FORMAT_R16G16B16A16_FLOAT
  ASSERT_EQ(dds.faces, 6u);
  // Faces outer, levels inner: the whole file is accounted for.
  std::vector<std::vector<std::size_t>> start(6, std::vector<std::size_t>(6));
  std::size_t at = dds.dataStart;
  for (int f = 0; f < 6; ++f)
    for (int k = 0; k < 6; ++k) start[f][k] = at, at += std::size_t(32 >> k) * (32 >> k) * 8;
  ASSERT_EQ(at, dds.bytes.size());
  const auto known = knownDirections();
  for (int k = 0; (32 >> k) >= 8; ++k) {
    const int n = 32 >> k;
    for (const Known& c : known) {
      const auto [face, i, j] = vulkanTexel(c.direction.normalized(), n);
      const std::size_t texel = start[face][k] + (std::size_t(j) * n + i) * 8;
      for (int ch = 0; ch < 3; ++ch) {
        std::uint16_t h;
        std::memcpy(&h, dds.bytes.data() + texel + 2 * ch, 2);
        EXPECT_NEAR(halfValue(h), c.colour[ch], 0.01) << "level " << k << " " << c.direction.transpose();
      }
    }
  }
}

}  // namespace
}  // namespace brdfbake
