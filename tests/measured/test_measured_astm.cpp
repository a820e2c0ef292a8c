// Cornell ASTM E1392 tables: the real files beside the repository, and malformed small files.
#include <brdfbake/measured/measured_io.hpp>

#include "measured_test_files.hpp"
#include "test_support.hpp"

#include <cmath>

namespace brdfbake {
namespace {

using test::rejects;
using test::writeFile;

// Four header lines, then two rows (lines 5 and 6).
constexpr const char* kSmallRgb =
    "SAMPLE_NAME Test\n"
    "NUM_POINTS 2\n"
    "VARS theta_i,phi_i,theta_s,phi_s,R,G,B\n"
    "\n"
    "0.174533,0.000000,0.141539,3.141593,0.5,0.25,-0.01\n"
    "0.349066,0.000000,0.283794,-1.570796,0.4,0.2,0.1\n";

TEST(ReadAstm, RealSpectralFile) {
  BRDFBAKE_REQUIRE_SHARED(path, "data/cornell/garnet_red.astm");
  const MeasuredTable table = readAstm(path);
  EXPECT_EQ(table.size(), 1439u);
  EXPECT_EQ(table.channelCount(), 31u);
  EXPECT_EQ(table.kind, ChannelKind::Spectral);
  EXPECT_EQ(table.format, TableFormat::Astm);
  EXPECT_EQ(table.sourceFile, path.string());
  ASSERT_EQ(table.wavelengthsNm.size(), 31u);
  for (std::size_t c = 0; c < 31; ++c) EXPECT_EQ(table.wavelengthsNm[c], 400.0 + 10.0 * c);
  EXPECT_EQ(table.channelNames.front(), "400nm");
  EXPECT_EQ(table.channelNames.back(), "700nm");

  // theta_i is 10, 20, ..., 80 degrees, phi_i always 0; samples per incidence as in the file.
  const std::vector<double> thetas = table.incidentThetas();
  ASSERT_EQ(thetas.size(), 8u);
  for (std::size_t k = 0; k < 8; ++k) EXPECT_NEAR(degrees(thetas[k]), 10.0 * (k + 1), 1e-4);
  const std::size_t perIncidence[8] = {178, 179, 179, 180, 181, 180, 180, 182};
  for (std::size_t k = 0; k < 8; ++k) EXPECT_EQ(table.samplesAtIncidentTheta(thetas[k]).size(), perIncidence[k]);
  for (const SampleAngles& a : table.angles) EXPECT_EQ(a.phiIn, 0.0);
  EXPECT_EQ(table.incidentAngles().size(), 8u);

  // Outgoing directions lie on the 10 equal-area rings sqrt(2) sin(theta_s / 2) = k / 10.
  for (const SampleAngles& a : table.angles) {
    const double ring = 10.0 * std::sqrt(2.0) * std::sin(a.thetaOut / 2.0);
    EXPECT_NEAR(ring, std::round(ring), 1e-4);
    EXPECT_LE(std::round(ring), 9.0);
  }

  // First and last rows, as printed in the file.
  EXPECT_EQ(table.angles.front().thetaIn, 0.872665);
  EXPECT_EQ(table.angles.front().thetaOut, 0.573513);
  EXPECT_EQ(table.values(0, 0), 0.023025);
  EXPECT_EQ(table.angles.back().thetaIn, 1.396263);
  EXPECT_EQ(table.angles.back().phiOut, 3.141593);
  EXPECT_EQ(table.values(1438, 0), 29.528748);

  // Spectral files have no negative values; the header is kept.
  EXPECT_EQ((table.values.array() < 0.0).count(), 0);
  bool sawName = false;
  for (const auto& [key, value] : table.header)
    if (key == "SAMPLE_NAME") sawName = value == "Garnet Red";
  EXPECT_TRUE(sawName);
  EXPECT_NO_THROW(table.validate());
}

TEST(ReadAstm, RealRgbFileWithCrlfKeepsNegativeValues) {
  BRDFBAKE_REQUIRE_SHARED(path, "data/cornell/garnet_red_RGB.astm");
  const MeasuredTable table = readAstm(path);
  EXPECT_EQ(table.size(), 1439u);
  EXPECT_EQ(table.kind, ChannelKind::Trichromatic);
  EXPECT_EQ(table.channelNames, (std::vector<std::string>{"R", "G", "B"}));
  EXPECT_TRUE(table.wavelengthsNm.empty());
  // 222 of the 4317 values are negative; they are kept as stored, and a note says so.
  EXPECT_EQ((table.values.array() < 0.0).count(), 222);
  EXPECT_EQ(table.values(9, 1), -0.000055);  // line 32: 1.396263,0.000000,1.202528,-0.294524,0.007177,-0.000055,...
  bool noted = false;
  for (const std::string& note : table.notes)
    noted = noted || note.find("222 of 4317 values are negative") != std::string::npos;
  EXPECT_TRUE(noted);
  EXPECT_EQ(table.values(1438, 0), 11.583783);
}

TEST(ReadAstm, KrylonBlueRgbHasItsNegatives) {
  BRDFBAKE_REQUIRE_SHARED(path, "data/cornell/krylon_blue_RGB.astm");
  const MeasuredTable table = readAstm(path);
  EXPECT_EQ(table.size(), 1439u);
  EXPECT_EQ((table.values.array() < 0.0).count(), 943);
  EXPECT_EQ(table.values(0, 0), -0.000794);
}

TEST(ReadAstm, SmallFileLfAndCrlfReadTheSame) {
  test::TempDir dir;
  writeFile(dir / "lf.astm", kSmallRgb);
  std::string crlf;
  for (char c : std::string(kSmallRgb)) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  writeFile(dir / "crlf.astm", crlf);
  const MeasuredTable lf = readAstm(dir / "lf.astm");
  const MeasuredTable cr = readAstm(dir / "crlf.astm");
  ASSERT_EQ(lf.size(), 2u);
  EXPECT_EQ(lf.values, cr.values);
  EXPECT_EQ(lf.values(0, 2), -0.01);
  EXPECT_EQ(lf.angles[1].phiOut, -1.570796);
  EXPECT_EQ(cr.angles[1].phiOut, -1.570796);
  EXPECT_EQ(lf.kind, ChannelKind::Trichromatic);
}

TEST(ReadAstm, WithoutNumPointsNotesTheUncheckedCount) {
  test::TempDir dir;
  writeFile(dir / "t.astm", "VARS theta_i,phi_i,theta_s,phi_s,BRDF\n0.1,0,0.2,0,0.3\n");
  const MeasuredTable table = readAstm(dir / "t.astm");
  EXPECT_EQ(table.kind, ChannelKind::Monochrome);
  ASSERT_FALSE(table.notes.empty());
  EXPECT_NE(table.notes.front().find("no NUM_POINTS"), std::string::npos);
}

// ---- malformed files: each error names the file and the line --------------------------------

class MalformedAstm : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& content) {
    const auto path = dir_ / "bad.astm";
    writeFile(path, content);
    return path;
  }
  std::string at(int line) const { return (dir_ / "bad.astm").string() + ":" + std::to_string(line) + ":"; }
  test::TempDir dir_;
};

TEST_F(MalformedAstm, HeaderFieldsAreQuotedPrintableAndShort) {
  // A 1 MB NUM_POINTS was echoed whole (a 1,000,077-byte error), escape sequences raw.
  const std::string huge = "\x1b]0;pwned\x07" + std::string(1'000'000, '9') + "x";
  for (const std::string& line : {"NUM_POINTS " + huge, huge + " 1", "VARS " + huge}) {
    const auto path = write(line + "\nVARS theta_i,phi_i,theta_s,phi_s,BRDF\n");
    try {
      readAstm(path);
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(at(1), 0), 0u) << message.substr(0, 200);
      EXPECT_LT(message.size(), 400u) << message.substr(0, 400);
      EXPECT_EQ(message.find('\x1b'), std::string::npos);
      EXPECT_NE(message.find("\\x1b]0;pwned\\x07"), std::string::npos) << message;
    }
  }
}

TEST_F(MalformedAstm, TruncatedInTheMiddleOfARow) {
  std::string content = kSmallRgb;
  content.resize(content.size() - 12);  // line 6 loses its last fields and its newline
  const auto path = write(content);
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(6), "expected 7 comma-separated fields", "found 5", "truncated"}));
}

TEST_F(MalformedAstm, TruncatedAtALineEndFallsShortOfNumPoints) {
  std::string content = kSmallRgb;
  content.resize(content.find("0.349066"));  // only the first row remains
  const auto path = write(content);
  EXPECT_TRUE(
      rejects([&] { readAstm(path); }, {at(5), "ends after 1 rows", "NUM_POINTS (line 2) says 2", "truncated"}));
}

TEST_F(MalformedAstm, WrongColumnCount) {
  const auto path = write(std::string(kSmallRgb) + "0.5,0,0.1,0,0.1,0.2,0.3,0.4\n");
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(7), "expected 7 comma-separated fields", "found 8"}));
}

TEST_F(MalformedAstm, MoreRowsThanNumPoints) {
  const auto path = write(std::string(kSmallRgb) + "0.5,0,0.1,0,0.1,0.2,0.3\n");
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(7), "more rows than NUM_POINTS 2 (line 2)"}));
}

TEST_F(MalformedAstm, NumPointsNotANumber) {
  std::string content = kSmallRgb;
  content.replace(content.find("NUM_POINTS 2"), 12, "NUM_POINTS two");
  const auto path = write(content);
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(2), "NUM_POINTS 'two' is not a whole number"}));
}

TEST_F(MalformedAstm, NonNumericField) {
  std::string content = kSmallRgb;
  content.replace(content.find("0.25"), 4, "abc");
  const auto path = write(content);
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(5), "field 6 'abc' is not a number"}));
}

TEST_F(MalformedAstm, NanAndInfinityFields) {
  std::string content = kSmallRgb;
  content.replace(content.find("0.25"), 4, "nan");
  auto path = write(content);
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(5), "field 6 'nan' is not finite"}));
  content = kSmallRgb;
  content.replace(content.find("0.283794"), 8, "inf");
  path = write(content);
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(6), "theta_s 'inf' is not finite"}));
}

TEST_F(MalformedAstm, MissingVarsLine) {
  std::string content = kSmallRgb;
  content.erase(content.find("VARS"), content.find("\n\n") - content.find("VARS") + 1);
  auto path = write(content);  // the first data row is now line 4
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(4), "data row before the VARS line"}));
  path = write("SAMPLE_NAME Test\nNUM_POINTS 2\n");
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(2), "no VARS line"}));
}

TEST_F(MalformedAstm, VarsWithoutTheFourAngles) {
  const auto path = write("VARS theta_i,theta_s,R,G,B\n0.1,0.2,0.3,0.4,0.5\n");
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(1), "VARS must start with theta_i,phi_i,theta_s,phi_s"}));
}

TEST_F(MalformedAstm, UnknownChannelNames) {
  const auto path = write("VARS theta_i,phi_i,theta_s,phi_s,X,Y\n0.1,0,0.2,0,0.3,0.4\n");
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(1), "channels must be wavelengths"}));
}

TEST_F(MalformedAstm, DecreasingWavelengths) {
  const auto path = write("VARS theta_i,phi_i,theta_s,phi_s,500nm,400nm\n0.1,0,0.2,0,0.3,0.4\n");
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(1), "wavelengths must increase"}));
}

TEST_F(MalformedAstm, AnglesInDegrees) {
  const auto path = write("VARS theta_i,phi_i,theta_s,phi_s,R,G,B\n10,0,8.11,180,0.1,0.2,0.3\n");
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(2), "theta_i = 10 is outside [0, pi/2]", "radians"}));
}

TEST_F(MalformedAstm, BadHeaderLineAndNoRows) {
  auto path = write("SAMPLE_NAME Test\n(not a key)\nVARS theta_i,phi_i,theta_s,phi_s,R,G,B\n");
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(2), "expected a header line 'KEY value'"}));
  path = write("VARS theta_i,phi_i,theta_s,phi_s,R,G,B\n\n");
  EXPECT_TRUE(rejects([&] { readAstm(path); }, {at(2), "no data rows"}));
}

TEST(ReadAstm, MissingFileIsAnIoError) {
  test::TempDir dir;
  EXPECT_TRUE(
      test::throwsError([&] { readAstm(dir / "absent.astm"); }, Error::Kind::Io, {"absent.astm", "no such file"}));
  EXPECT_TRUE(test::throwsError([&] { readAstm(dir.path()); }, Error::Kind::Io,
                                {dir.path().string(), "is a folder, not a file"}));
}

}  // namespace
}  // namespace brdfbake
