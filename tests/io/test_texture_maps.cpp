// Maps in KTX2, KTX1 and DDS files: writeMap / writeTiledMap / readMap choose the container by the
// extension, a cube map becomes a cube texture, and lookups equal those of the OpenEXR.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/io/texture.hpp>
#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/maps/map_mips.hpp>

#include <cmath>
#include <random>

#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;

// A smooth, direction-dependent map: each texel holds a function of its centre's direction.
Image mapOf(const Parameterization& map) {
  Image image(map.width(), map.height(), Rgba(0, 0, 0, 0));
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) {
      const auto d = map.getDirectionFor(Vec2(x + 0.5, y + 0.5));
      if (!d) continue;
      image.set(x, y, Rgba(1.5 + d->x(), 2.0 + d->y() * d->z(), 0.25 + d->z() * d->z(), map.texelCoverage(x, y)));
    }
  return image;
}

MapInfo infoOf(ParameterizationKind kind, int n) {
  return {kind, n, kConventionVersion, {{"material", {{"model", "phong"}, {"exponent", 20}}}}};
}

std::vector<Vec3> directions(int count) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  std::vector<Vec3> out;
  while (static_cast<int>(out.size()) < count) {
    const Vec3 d(g(rng), g(rng), g(rng));
    if (d.norm() > 1e-3) out.push_back(d.normalized());
  }
  return out;
}

TEST(TextureMaps, CubeMapInKtx2AndDdsLooksUpAsTheExr) {
  test::TempDir dir;
  const CubeMap cube(16);
  const Image image = mapOf(cube);
  writeMap(image, infoOf(ParameterizationKind::Cube, 16), dir / "c.exr");
  WriteOptions full;
  full.texelFormat = TexelFormat::Rgba32Float;
  writeMap(image, infoOf(ParameterizationKind::Cube, 16), dir / "c32.ktx2", CubeLayout::Cross, full);
  writeMap(image, infoOf(ParameterizationKind::Cube, 16), dir / "c32.dds", CubeLayout::Cross, full);
  writeMap(image, infoOf(ParameterizationKind::Cube, 16), dir / "c32.ktx", CubeLayout::Cross, full);
  writeMap(image, infoOf(ParameterizationKind::Cube, 16), dir / "c16.ktx2");
  writeMap(image, infoOf(ParameterizationKind::Cube, 16), dir / "c16.dds");
  // Each is one cube texture of six 16 x 16 faces, not a cross.
  for (const char* name : {"c32.ktx2", "c32.dds", "c32.ktx", "c16.ktx2"}) {
    const TextureHeader header = readTextureHeaderOf(dir / name);
    EXPECT_EQ(header.faces, 6) << name;
    EXPECT_EQ(header.width, 16) << name;
    EXPECT_EQ(header.height, 16) << name;
    EXPECT_EQ(header.metadata.value("parameterization", ""), "cube") << name;
  }
  EXPECT_TRUE(fs::exists(dir / "c16.dds.json"));  // DDS holds no metadata: the sidecar does
  EXPECT_FALSE(fs::exists(dir / "c16.ktx2.json"));
  const MapFile exr = readMap(dir / "c.exr");
  for (const char* name : {"c32.ktx2", "c32.dds", "c32.ktx", "c16.ktx2", "c16.dds"}) {
    SCOPED_TRACE(name);
    const MapFile file = readMap(dir / name);
    EXPECT_EQ(file.info.parameterization, ParameterizationKind::Cube);
    EXPECT_EQ(file.info.resolution, 16);
    EXPECT_EQ(file.info.spec, exr.info.spec);
    const bool half = std::string(name).find("16") != std::string::npos;
    for (const Vec3& d : directions(500)) {
      const Rgba a = sampleBilinear(exr.image, *exr.parameterization, d);
      const Rgba b = sampleBilinear(file.image, *file.parameterization, d);
      for (int c = 0; c < 4; ++c) {
        if (half) {
          ASSERT_NEAR(b[c], a[c], std::abs(a[c]) * 0x1p-10) << c;  // two half ulps of rounding, interpolated
        } else {
          ASSERT_EQ(b[c], a[c]) << c;
        }
      }
    }
  }
}

TEST(TextureMaps, EveryParameterizationRoundTripsAsATwoDimensionalTexture) {
  test::TempDir dir;
  WriteOptions full;
  full.texelFormat = TexelFormat::Rgba32Float;
  for (const ParameterizationKind kind :
       {ParameterizationKind::Sphere, ParameterizationKind::Paraboloid, ParameterizationKind::LatLong}) {
    const auto map = makeParameterization(kind, 8);
    const Image image = mapOf(*map);
    for (const char* ext : {".ktx2", ".ktx", ".dds"}) {
      const fs::path path = dir / (std::string(toString(kind)) + ext);
      writeMap(image, infoOf(kind, 8), path, CubeLayout::Cross, full);
      const TextureHeader header = readTextureHeaderOf(path);
      EXPECT_EQ(header.faces, 1);
      EXPECT_EQ(header.width, map->width());
      const MapFile file = readMap(path);
      EXPECT_EQ(file.info.parameterization, kind);
      for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) ASSERT_TRUE((file.image.at(x, y) == image.at(x, y)).all()) << path;
    }
  }
}

// Metadata of a wrong JSON type in a map file (a hand edit, another tool) reads as absent and is refused
// naming the file and the key: it once gave "internal error: [json.exception.type_error.302]", exit 1.
TEST(TextureMaps, MetadataOfAWrongTypeIsRefusedNamingTheFileAndKey) {
  test::TempDir dir;
  const auto sphere = makeParameterization(ParameterizationKind::Sphere, 8);
  writeMap(mapOf(*sphere), infoOf(ParameterizationKind::Sphere, 8), dir / "good.exr");
  const Image good = readImage(dir / "good.exr");
  const std::vector<std::pair<nlohmann::json, std::string>> cases = {
      {{{"parameterization", 5}}, "no valid 'parameterization'"},
      {{{"resolution", "8"}}, "no valid 'resolution'"},
      {{{"resolution", 1e300}}, "no valid 'resolution'"},
      {{{"spec", "x"}}, "no valid 'spec'"},
      {{{"convention_version", "1"}}, "no valid 'convention_version'"}};
  for (const char* extension : {".exr", ".ktx2"}) {
    for (std::size_t i = 0; i < cases.size(); ++i) {
      Image bad = good;
      bad.metadata.update(cases[i].first);
      const fs::path file = dir / ("bad" + std::to_string(i) + extension);
      writeImage(bad, file);
      try {
        readMap(file);
        ADD_FAILURE() << file << " read";
      } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::InvalidInput) << e.what();
        EXPECT_EQ(std::string(e.what()).rfind(file.string() + ": map metadata has " + cases[i].second, 0), 0u)
            << e.what();
      }
    }
  }
  // A face's "layout" of a wrong type is no face set: the file reads as the map it is.
  Image face = good;
  face.metadata["layout"] = 7;
  writeImage(face, dir / "layout.exr");
  EXPECT_EQ(readMap(dir / "layout.exr").info.resolution, 8);
}

TEST(TextureMaps, CubeFacesLayoutWritesSixTwoDimensionalTextures) {
  test::TempDir dir;
  const CubeMap cube(4);
  writeMap(mapOf(cube), infoOf(ParameterizationKind::Cube, 4), dir / "f.ktx2", CubeLayout::Faces);
  for (const auto& face : cubeFacePaths(dir / "f.ktx2")) EXPECT_EQ(readTextureHeaderOf(face).faces, 1) << face;
  const MapFile file = readMap(dir / "f.ktx2");
  EXPECT_EQ(file.image.width(), 16);
}

TEST(TextureMaps, AWholeChainInOneTextureReadsBackLevelByLevel) {
  test::TempDir dir;
  WriteOptions full;
  full.texelFormat = TexelFormat::Rgba32Float;
  for (const ParameterizationKind kind : {ParameterizationKind::Cube, ParameterizationKind::LatLong}) {
    const auto map = makeParameterization(kind, 8);
    const std::vector<Image> levels = environmentMipChain(mapOf(*map), *map);
    ASSERT_EQ(levels.size(), 4u);
    std::vector<nlohmann::json> values;
    for (int k = 0; k < 4; ++k) values.push_back({{"roughness", k / 3.0}});
    for (const char* ext : {".ktx2", ".ktx", ".dds"}) {
      const fs::path path = dir / (std::string(toString(kind)) + "_chain" + ext);
      SCOPED_TRACE(path.string());
      const MapWriteReport report = writeTiledMap(levels, infoOf(kind, 8), path, CubeLayout::Cross, full, values);
      ASSERT_EQ(report.files.size(), 1u);
      const TextureHeader header = readTextureHeaderOf(path);
      // A cube texture ends with the map (8, 4, 2, 1); a 16 x 8 lat-long map's last level is 2 x 1,
      // and one more 1 x 1 level completes the texture's chain.
      EXPECT_EQ(header.levels, kind == ParameterizationKind::Cube ? 4 : 5);
      EXPECT_EQ(header.faces, kind == ParameterizationKind::Cube ? 6 : 1);
      EXPECT_EQ(header.metadata.value("mip_levels", 0), 4);
      for (int k = 0; k < 4; ++k) {
        const MapFile level = readMap(path, k);
        EXPECT_EQ(level.info.resolution, 8 >> k);
        EXPECT_DOUBLE_EQ(levelValues(level.image.metadata, k).value("roughness", -1.0), k / 3.0);
        for (int y = 0; y < levels[k].height(); ++y)
          for (int x = 0; x < levels[k].width(); ++x)
            ASSERT_TRUE((level.image.at(x, y) == levels[k].at(x, y)).all()) << k;
      }
      EXPECT_THROW(readMap(path, 4), Error);  // beyond the cube's levels, or the lat-long map's mean level
    }
  }
}

TEST(TextureMaps, ContainerProblemsAreFoundBeforeAnyWork) {
  const fs::path dir = "out";
  OutputShape chain;
  chain.parameterization = ParameterizationKind::Cube;
  chain.resolution = 16;
  chain.wholeChain = true;
  EXPECT_EQ(containerProblem(dir / "c.ktx2", chain), "");
  EXPECT_EQ(containerProblem(dir / "c.dds", chain), "");
  EXPECT_EQ(containerProblem(dir / "c.exr", chain), "");
  EXPECT_NE(containerProblem(dir / "c.png", chain).find("a whole mip chain in one file needs"), std::string::npos);
  EXPECT_NE(containerProblem(dir / "c.hdr", chain), "");
  chain.resolution = 12;
  EXPECT_NE(containerProblem(dir / "c.ktx2", chain).find("power-of-two"), std::string::npos);
  EXPECT_EQ(tiledMipProblem(dir / "c.ktx2", 16), "");
  EXPECT_NE(tiledMipProblem(dir / "c.tif", 16), "");
  OutputShape one;
  one.texelFormat = TexelFormat::Rgb16Float;
  EXPECT_NE(containerProblem(dir / "c.dds", one).find("no 3-channel half-float"), std::string::npos);
  EXPECT_EQ(containerProblem(dir / "c.ktx2", one), "");
  EXPECT_NE(containerProblem(dir / "c.exr", one).find("applies to .ktx2, .ktx and .dds outputs only"),
            std::string::npos);
  EXPECT_NE(containerProblem(dir / "c.jpg", OutputShape{}).find("unsupported image extension"), std::string::npos);
  OutputShape huge;
  huge.parameterization = ParameterizationKind::LatLong;
  huge.resolution = 40000;
  EXPECT_NE(containerProblem(dir / "c.ktx2", huge).find("larger than"), std::string::npos);
}

TEST(TextureMaps, WritesKeepTheImagePolicies) {
  test::TempDir dir;
  const auto map = makeParameterization(ParameterizationKind::Sphere, 8);
  Image image = mapOf(*map);
  // Never overwrite an input.
  writeMap(image, infoOf(ParameterizationKind::Sphere, 8), dir / "in.ktx2");
  EXPECT_THROW(writeMap(image, infoOf(ParameterizationKind::Sphere, 8), dir / "in.ktx2", CubeLayout::Cross,
                        WriteOptions{{dir / "in.ktx2"}, std::nullopt}),
               Error);
  // A stale sidecar beside a KTX2 is removed; a DDS gets one.
  writeFileAtomically(dir / "s.ktx2.json", "{\"stale\": true}");
  writeMap(image, infoOf(ParameterizationKind::Sphere, 8), dir / "s.ktx2");
  EXPECT_FALSE(fs::exists(dir / "s.ktx2.json"));
  // Unsigned and RGB formats say what they changed.
  image.set(0, 0, Rgba(-1, 70000, 1, 0.5));
  WriteOptions packed;
  packed.texelFormat = TexelFormat::Rgb9e5;
  const MapWriteReport report =
      writeMap(image, infoOf(ParameterizationKind::Sphere, 8), dir / "p.ktx2", CubeLayout::Cross, packed);
  std::string notes;
  for (const auto& n : report.notes) notes += n + "\n";
  EXPECT_NE(notes.find("stored as 0"), std::string::npos) << notes;
  EXPECT_NE(notes.find("65408"), std::string::npos) << notes;
  EXPECT_NE(notes.find("alpha (coverage) dropped"), std::string::npos) << notes;
  const MapFile back = readMap(dir / "p.ktx2");
  EXPECT_EQ(back.image.at(0, 0)[0], 0.0f);
  EXPECT_EQ(back.image.at(0, 0)[1], 65408.0f);
  EXPECT_EQ(back.image.at(0, 0)[3], 1.0f);
  // NaN is never written, and no file appears.
  image.set(1, 1, Rgba(NAN, 0, 0, 1));
  EXPECT_THROW(writeMap(image, infoOf(ParameterizationKind::Sphere, 8), dir / "nan.dds"), Error);
  EXPECT_FALSE(fs::exists(dir / "nan.dds"));
}

TEST(TextureMaps, ACubeTextureFromAnotherToolReadsAsTheCross) {
  test::TempDir dir;
  // Six faces without brdfbake metadata, face f holding f everywhere.
  Texture texture;
  texture.levels.emplace_back();
  for (int f = 0; f < 6; ++f) texture.levels[0].emplace_back(4, 4, Rgba(f, 0, 0, 1));
  writeTexture(texture, dir / "other.ktx2");
  const Image cross = readImage(dir / "other.ktx2");
  ASSERT_EQ(cross.width(), 16);
  ASSERT_EQ(cross.height(), 12);
  EXPECT_TRUE(cross.metadata.empty());
  const CubeMap cube(4);
  for (int f = 0; f < 6; ++f) {
    const TexelRect r = cube.region(f);
    EXPECT_EQ(cross.at(r.x0 + 1, r.y0 + 2)[0], f) << f;
  }
  EXPECT_EQ(cross.at(0, 0)[3], 0.0f);  // unused cells: coverage 0
  const MapFile map = adoptImage(cross, ParameterizationKind::Cube, "other.ktx2");
  EXPECT_EQ(sampleBilinear(map.image, *map.parameterization, Vec3(0, -1, 0))[0], 3.0);  // -Y is face 3
}

TEST(TextureMaps, AKtx2FileWithAnotherExtensionIsStillReadAsOne) {
  test::TempDir dir;
  const auto map = makeParameterization(ParameterizationKind::Sphere, 4);
  writeMap(mapOf(*map), infoOf(ParameterizationKind::Sphere, 4), dir / "m.ktx2");
  fs::copy_file(dir / "m.ktx2", dir / "m.bin");
  EXPECT_EQ(readImage(dir / "m.bin").width(), 4);
  writeFileAtomically(dir / "fake.ktx2", "this is not a texture");
  try {
    (void)readImage(dir / "fake.ktx2");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "fake.ktx2").string()), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace brdfbake
