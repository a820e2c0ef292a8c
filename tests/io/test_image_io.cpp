// Image files: formats, metadata round trips, atomic writes, refusing to overwrite inputs.
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/map_file.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;

Image gradient(int w, int h) {
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) image.set(x, y, Rgba(x / double(w), y / double(h), 2.5, (x + y) % 2));
  return image;
}

MapInfo sphereInfo(int n) {
  return {ParameterizationKind::Sphere, n, kConventionVersion, {{"material", {{"model", "phong"}}}}};
}

TEST(ImageIo, ExrRoundTripsFloatRgbaAndMetadata) {
  test::TempDir dir;
  const Image image = gradient(8, 8);
  writeMap(image, sphereInfo(8), dir / "map.exr");
  const MapFile file = readMap(dir / "map.exr");
  EXPECT_EQ(file.info.parameterization, ParameterizationKind::Sphere);
  EXPECT_EQ(file.info.resolution, 8);
  EXPECT_EQ(file.info.spec["material"]["model"], "phong");
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) ASSERT_EQ(file.image.at(x, y)[2], 2.5f);
  EXPECT_EQ(file.image.at(3, 4)[0], image.at(3, 4)[0]);
  EXPECT_EQ(file.image.at(3, 4)[3], 1.0);
  EXPECT_FALSE(fs::exists(dir.path() / "map.exr.json"));  // OpenEXR holds the metadata itself
}

// The sRGB transfer curve (IEC 61966-2-1), typed out.
double srgbEncode(double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055; }

TEST(ImageIo, EveryFormatKeepsItsMetadata) {
  test::TempDir dir;
  const Image image = gradient(8, 8);
  for (const std::string name : {"m.hdr", "m.tif", "m.png"}) {
    const auto report = writeMap(image, sphereInfo(8), dir / name);
    const MapFile file = readMap(dir / name);
    EXPECT_EQ(file.info.resolution, 8) << name;
    EXPECT_EQ(file.info.spec["material"]["model"], "phong") << name;
    ASSERT_EQ(file.image.width(), 8);
    ASSERT_EQ(file.image.height(), 8);
    // Every texel back within the format's precision.
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        const Rgba written = image.at(x, y), read = file.image.at(x, y);
        SCOPED_TRACE(name + " texel " + std::to_string(x) + "," + std::to_string(y));
        if (name == "m.tif") {
          // 32-bit float TIFF: exact, alpha included.
          for (int c = 0; c < 4; ++c) EXPECT_EQ(read[c], written[c]) << c;
        } else if (name == "m.hdr") {
          // RGBE: an 8-bit mantissa per channel and an exponent shared with the largest (here 2.5,
          // exponent 2): each channel within one mantissa step, 2^2 / 256 <= max / 128. No alpha.
          const double step = written.head<3>().maxCoeff() / 128.0;
          for (int c = 0; c < 3; ++c) EXPECT_NEAR(read[c], written[c], step) << c;
          EXPECT_EQ(read[3], 1.0f);
        } else {
          // 8-bit sRGB: clamped to [0, 1], then within half a code of the sRGB curve.
          for (int c = 0; c < 3; ++c) {
            const double clamped = std::clamp(double(written[c]), 0.0, 1.0);
            EXPECT_NEAR(srgbEncode(read[c]), srgbEncode(clamped), 0.5 / 255.0 + 1e-6) << c;
          }
          EXPECT_EQ(read[3], written[3]);  // 0 or 1: exact in 8 bits
        }
      }
    if (name == "m.png") {
      ASSERT_FALSE(report.notes.empty());
      EXPECT_NE(report.notes[0].find("sRGB"), std::string::npos);
      // 8-bit sRGB: 2.5 clamps to 1; linear 0.5 survives the transfer curve to within a step.
      EXPECT_NEAR(file.image.at(4, 0)[0], 0.5, 0.01);
      EXPECT_NEAR(file.image.at(4, 0)[2], 1.0, 1e-6);
    }
  }
}

TEST(ImageIo, RefusesToOverwriteAnInput) {
  test::TempDir dir;
  const fs::path input = dir / "in.exr";
  writeImage(gradient(4, 4), input);
  const auto before = fs::last_write_time(input);
  WriteOptions options;
  options.inputs = {input};
  EXPECT_THROW(writeImage(gradient(4, 4), dir.path() / "." / "in.exr", options), Error);
  EXPECT_EQ(fs::last_write_time(input), before);
}

TEST(ImageIo, RefusesNonFiniteValuesAndLeavesNoFile) {
  test::TempDir dir;
  Image image = gradient(4, 4);
  image.set(2, 1, Rgba(NAN, 0, 0, 1));
  try {
    writeImage(image, dir / "bad.exr");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("(2, 1)"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(ImageIo, FailedWriteLeavesTheOldFileAndNoTemporary) {
  test::TempDir dir;
  const fs::path target = dir / "keep.exr";
  writeImage(gradient(4, 4), target);
  Image bad = gradient(4, 4);
  bad.set(0, 0, Rgba(INFINITY, 0, 0, 1));
  EXPECT_THROW(writeImage(bad, target), Error);
  EXPECT_EQ(readImage(target).at(1, 0)[0], 0.25f);
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir.path())) files += entry.is_regular_file();
  EXPECT_EQ(files, 1);
}

TEST(ImageIo, ClearErrorsForBadPaths) {
  test::TempDir dir;
  EXPECT_THROW(imageFormatFor("x.jpg"), Error);
  try {
    readImage(dir / "missing.exr");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::Io);
    EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos);
  }
  std::ofstream(dir / "garbage.exr") << "not an image";
  EXPECT_THROW(readImage(dir / "garbage.exr"), Error);
  writeImage(gradient(4, 4), dir / "plain.exr");
  EXPECT_THROW(readMap(dir / "plain.exr"), Error);  // no brdfbake metadata
}

// The OpenGL cube-map table (OpenGL 4.6 core, Table 8.19): the direction of face f's texture
// coordinate (s, t) in [0, 1]^2, with sc = 2 s - 1, tc = 2 t - 1 and |ma| = 1.
Vec3 openGlFaceDirection(int face, double s, double t) {
  const double sc = 2 * s - 1, tc = 2 * t - 1;
  switch (face) {
    case 0:
      return {1, -tc, -sc};  // +X: sc = -rz, tc = -ry
    case 1:
      return {-1, -tc, sc};  // -X: sc = +rz, tc = -ry
    case 2:
      return {sc, 1, tc};  // +Y: sc = +rx, tc = +rz
    case 3:
      return {sc, -1, -tc};  // -Y: sc = +rx, tc = -rz
    case 4:
      return {sc, -tc, 1};  // +Z: sc = +rx, tc = -ry
    default:
      return {-sc, -tc, -1};  // -Z: sc = -rx, tc = -ry
  }
}

TEST(ImageIo, CubeFacesAreWrittenAsSixFilesHoldingTheirFacesTexels) {
  // An environment whose colour says its direction, 0.5 + 0.5 d / |d|, laid out as the cross of
  // maps/cube_map.hpp (+Y above +Z; -X, +Z, +X, -Z in the middle row; -Y below) with each face's
  // texel (i, j) at (s, t) = ((i + 0.5) / N, (j + 0.5) / N) of the OpenGL table, typed out above.
  // Each face file (OpenGL order) must hold that face's texels, and the cube read back from the
  // six files must look up, at each face's centre, the mean of the four texels around it.
  test::TempDir dir;
  const int n = 4;
  const int cell[6][2] = {{2, 1}, {0, 1}, {1, 0}, {1, 2}, {1, 1}, {3, 1}};
  auto colour = [](const Vec3& d) {
    const Vec3 u = d.normalized();
    return Rgba(0.5 + 0.5 * u.x(), 0.5 + 0.5 * u.y(), 0.5 + 0.5 * u.z(), 1.0);
  };
  Image cross(4 * n, 3 * n, Rgba::Zero());
  for (int f = 0; f < 6; ++f)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        cross.set(cell[f][0] * n + i, cell[f][1] * n + j, colour(openGlFaceDirection(f, (i + 0.5) / n, (j + 0.5) / n)));
  const auto report =
      writeMap(cross, {ParameterizationKind::Cube, n, kConventionVersion, {}}, dir / "cube.exr", CubeLayout::Faces);
  ASSERT_EQ(report.files.size(), 6u);
  const auto paths = cubeFacePaths(dir / "cube.exr");
  const char* names[6] = {"posx", "negx", "posy", "negy", "posz", "negz"};
  for (int f = 0; f < 6; ++f) {
    EXPECT_EQ(paths[f], dir / ("cube_" + std::string(names[f]) + ".exr"));
    const Image face = readImage(paths[f]);
    ASSERT_EQ(face.width(), n);
    ASSERT_EQ(face.height(), n);
    EXPECT_TRUE(face.metadata.contains("face"));
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Rgba expected = colour(openGlFaceDirection(f, (i + 0.5) / n, (j + 0.5) / n));
        EXPECT_LT((face.at(i, j) - expected).head<3>().abs().maxCoeff(), 1e-6)
            << names[f] << " (" << i << ", " << j << ")";
      }
  }
  const MapFile back = readMap(dir / "cube.exr");
  for (int f = 0; f < 6; ++f) {
    // Between the four centre texels: their mean, which bilinear lookup returns there.
    Rgba mean = Rgba::Zero();
    for (double s : {0.375, 0.625})
      for (double t : {0.375, 0.625}) mean += colour(openGlFaceDirection(f, s, t)) / 4.0;
    const Rgba looked = sampleBilinear(back.image, *back.parameterization, openGlFaceDirection(f, 0.5, 0.5));
    EXPECT_LT((looked - mean).head<3>().abs().maxCoeff(), 1e-6) << names[f];
  }
}

}  // namespace
}  // namespace brdfbake
