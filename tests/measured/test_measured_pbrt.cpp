// pbrt-v2 .brdf tables: the real Krylon blue copy equals its ASTM twin; malformed small files.
#include <brdfbake/measured/measured_io.hpp>

#include "measured_test_files.hpp"
#include "test_support.hpp"

namespace brdfbake {
namespace {

using test::rejects;
using test::writeFile;

// Comments, 3 wavelengths over two lines, a comment, two samples (lines 7 and 8).
constexpr const char* kSmallPbrt =
    "# a test table\n"
    "3\n"
    "# wls\n"
    "400 550\n"
    "700\n"
    "# theta_i phi_i theta_s phi_s values\n"
    "0.174533 0 0.141539 3.141593 0.1 0.2 0.3\n"
    "0.349066\t0 0.283794 -1.570796 0.4 0.5 0.6   # trailing comment\n";

TEST(ReadPbrt, RealFileEqualsTheAstmRowForRow) {
  BRDFBAKE_REQUIRE_SHARED(brdfPath, "data/cornell/krylon_blue.brdf");
  BRDFBAKE_REQUIRE_SHARED(astmPath, "data/cornell/krylon_blue.astm");
  const MeasuredTable pbrt = readPbrt(brdfPath);
  const MeasuredTable astm = readAstm(astmPath);
  EXPECT_EQ(pbrt.format, TableFormat::Pbrt);
  EXPECT_EQ(pbrt.kind, ChannelKind::Spectral);
  ASSERT_EQ(pbrt.size(), 1439u);
  ASSERT_EQ(pbrt.channelCount(), 31u);
  EXPECT_EQ(pbrt.wavelengthsNm, astm.wavelengthsNm);
  EXPECT_EQ(pbrt.channelNames, astm.channelNames);
  // Same numbers in another layout: identical doubles, row for row.
  EXPECT_EQ(pbrt.values, astm.values);
  for (std::size_t i = 0; i < pbrt.size(); ++i) {
    EXPECT_EQ(pbrt.angles[i].thetaIn, astm.angles[i].thetaIn) << "row " << i;
    EXPECT_EQ(pbrt.angles[i].phiIn, astm.angles[i].phiIn) << "row " << i;
    EXPECT_EQ(pbrt.angles[i].thetaOut, astm.angles[i].thetaOut) << "row " << i;
    EXPECT_EQ(pbrt.angles[i].phiOut, astm.angles[i].phiOut) << "row " << i;
  }
  EXPECT_EQ(pbrt.values(0, 0), 0.017415);
  EXPECT_EQ(pbrt.values(1438, 0), 64.220479);
  // The comments are kept as header entries.
  ASSERT_FALSE(pbrt.header.empty());
  EXPECT_EQ(pbrt.header.front().first, "#");
  EXPECT_EQ(pbrt.header.front().second, "Cornell University, Program of Computer Graphics");
}

TEST(ReadPbrt, SmallFile) {
  test::TempDir dir;
  writeFile(dir / "t.brdf", kSmallPbrt);
  const MeasuredTable table = readPbrt(dir / "t.brdf");
  EXPECT_EQ(table.wavelengthsNm, (std::vector<double>{400, 550, 700}));
  EXPECT_EQ(table.channelNames, (std::vector<std::string>{"400nm", "550nm", "700nm"}));
  ASSERT_EQ(table.size(), 2u);
  EXPECT_EQ(table.values(1, 2), 0.6);
  EXPECT_EQ(table.angles[1].phiOut, -1.570796);
}

class MalformedPbrt : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& content) {
    const auto path = dir_ / "bad.brdf";
    writeFile(path, content);
    return path;
  }
  std::string at(int line) const { return (dir_ / "bad.brdf").string() + ":" + std::to_string(line) + ":"; }
  test::TempDir dir_;
};

TEST_F(MalformedPbrt, WrongColumnCount) {
  const auto path = write(std::string(kSmallPbrt) + "0.5 0 0.1 0 0.1 0.2\n");
  EXPECT_TRUE(rejects([&] { readPbrt(path); }, {at(9), "expected 7 whitespace-separated fields", "found 6"}));
}

TEST_F(MalformedPbrt, TruncatedRowAndTruncatedWavelengths) {
  std::string content = kSmallPbrt;
  content.resize(content.find("0.5 0.6"));
  auto path = write(content);
  EXPECT_TRUE(rejects([&] { readPbrt(path); }, {at(8), "found 5", "truncated"}));
  path = write("# c\n31\n400 410 420\n");
  EXPECT_TRUE(rejects([&] { readPbrt(path); }, {at(3), "ends after 3 of 31 wavelengths"}));
}

TEST_F(MalformedPbrt, NonNumericAndNanFields) {
  std::string content = kSmallPbrt;
  content.replace(content.find("0.2 0.3"), 3, "x.y");
  auto path = write(content);
  EXPECT_TRUE(rejects([&] { readPbrt(path); }, {at(7), "field 6 'x.y' is not a number"}));
  content = kSmallPbrt;
  content.replace(content.find("0.4 0.5"), 3, "NaN");
  path = write(content);
  EXPECT_TRUE(rejects([&] { readPbrt(path); }, {at(8), "field 5 'NaN' is not finite"}));
}

TEST_F(MalformedPbrt, BadWavelengthCountOrOrder) {
  auto path = write("# c\nthirty\n");
  EXPECT_TRUE(rejects([&] { readPbrt(path); }, {at(2), "expected the number of wavelengths"}));
  path = write("2\n500 400\n0.1 0 0.2 0 1 2\n");
  EXPECT_TRUE(rejects([&] { readPbrt(path); }, {at(2), "wavelengths must be positive and increasing"}));
  path = write("2\n400 500 0.1 0 0.2 0 1 2\n");
  EXPECT_TRUE(rejects([&] { readPbrt(path); }, {at(2), "values after the 2 wavelengths"}));
  path = write("# only comments\n");
  EXPECT_TRUE(rejects([&] { readPbrt(path); }, {at(1), "no data"}));
  path = write("2\n400 500\n");
  EXPECT_TRUE(rejects([&] { readPbrt(path); }, {at(2), "no samples"}));
}

}  // namespace
}  // namespace brdfbake
