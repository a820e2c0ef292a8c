// Zero, negative, NaN and Inf values in input images and measured tables.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/version.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/measured/measured_io.hpp>

#include <algorithm>
#include <fstream>

#include "test_support.hpp"

namespace brdfbake {
namespace {
namespace fs = std::filesystem;

// OpenEXR stores NaN and Inf; reading such an environment is refused with the file and texel named.
TEST(InputImages, NaNAndInfTexelsAreRefusedNamingTheTexel) {
  test::TempDir dir;
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity()}) {
    const fs::path path = dir / "bad.exr";
    // Written with OpenImageIO directly: writeImage itself refuses non-finite values.
    std::vector<float> pixels(8 * 4 * 4, 1.0f);
    pixels[(2 * 8 + 5) * 4 + 1] = bad;
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out && out->open(path.string(), OIIO::ImageSpec(8, 4, 4, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) && out->close());
    try {
      adoptImage(readImage(path), ParameterizationKind::LatLong, path.string());
      FAIL() << "expected an error";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::InvalidInput);
      EXPECT_NE(
          std::string(e.what()).find(path.string() + ": texel (5, 2) is " + (std::isnan(bad) ? "NaN" : "infinite")),
          std::string::npos)
          << e.what();
    }
  }
}

TEST(InputImages, ZeroAndNegativeValuesAreKept) {
  Image image(8, 4, Rgba(0, 0, 0, 1));
  image.set(1, 1, Rgba(-0.25, 0, 2, 1));
  const MapFile file = adoptImage(image, ParameterizationKind::LatLong, "env");
  EXPECT_EQ(file.image.at(1, 1)[0], -0.25f);
}

TEST(InputImages, WrongShapeIsAClearError) {
  try {
    adoptImage(Image(10, 4), ParameterizationKind::LatLong, "pano.exr");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("pano.exr: image is 10 x 4 but a latlong map of resolution 4 is 8 x 4"),
              std::string::npos)
        << e.what();
  }
}

std::string astm(const std::string& values) {
  return "NUM_POINTS 2\nVARS theta_i,phi_i,theta_s,phi_s,R,G,B\n"
         "0.174533,0.000000,0.0,0.0,0.1,0.1,0.1\n"
         "0.174533,0.000000,0.139626,3.141593," +
         values + "\n";
}

TEST(InputTables, NaNAndInfFieldsAreRefusedNamingTheLine) {
  test::TempDir dir;
  for (const std::string bad : {"nan,0.1,0.1", "0.1,inf,0.1", "0.1,0.1,-inf"}) {
    std::ofstream(dir / "t.astm") << astm(bad);
    try {
      readMeasuredTable(dir / "t.astm");
      FAIL() << bad;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("t.astm:4"), std::string::npos) << e.what();
    }
  }
}

TEST(InputTables, ZeroAndNegativeValuesAreKeptAndNoted) {
  test::TempDir dir;
  std::ofstream(dir / "t.astm") << astm("0,-0.002,0.3");
  const MeasuredTable table = readMeasuredTable(dir / "t.astm");
  EXPECT_EQ(table.values(1, 0), 0.0);
  EXPECT_EQ(table.values(1, 1), -0.002);
  // The note about negative values, with the count: one of the 2 x 3 values. (An RGB table always
  // also gets a note about its primaries, so "some note" would prove nothing.)
  auto negativeNotes = [](const MeasuredTable& t) {
    return std::count_if(t.notes.begin(), t.notes.end(),
                         [](const std::string& n) { return n.find("negative") != std::string::npos; });
  };
  EXPECT_EQ(negativeNotes(table), 1) << ::testing::PrintToString(table.notes);
  EXPECT_NE(std::find(table.notes.begin(), table.notes.end(),
                      "1 of 6 values are negative; they are kept as stored in the file"),
            table.notes.end())
      << ::testing::PrintToString(table.notes);
  // Zeros alone are kept without a note about negative values.
  std::ofstream(dir / "z.astm") << astm("0,0.002,0.3");
  const MeasuredTable zeros = readMeasuredTable(dir / "z.astm");
  EXPECT_EQ(zeros.values(1, 0), 0.0);
  EXPECT_EQ(negativeNotes(zeros), 0) << ::testing::PrintToString(zeros.notes);
}

}  // namespace
}  // namespace brdfbake
