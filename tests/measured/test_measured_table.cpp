// MeasuredTable helpers (directions, RGB, mirroring), format detection and the ASTM writer.
#include <brdfbake/brdf/spectrum.hpp>
#include <brdfbake/measured/measured_io.hpp>

#include "measured_test_files.hpp"
#include "test_support.hpp"

#include <cmath>

namespace brdfbake {
namespace {

using test::rejects;
using test::writeFile;

// Two incidences (10 and 20 deg), spectral 400..700 nm every 100 nm, constant spectra.
MeasuredTable smallSpectral() {
  MeasuredTable table;
  table.kind = ChannelKind::Spectral;
  table.wavelengthsNm = {400, 500, 600, 700};
  table.channelNames = {"400nm", "500nm", "600nm", "700nm"};
  table.angles = {
      {radians(10), 0, radians(15), kPi}, {radians(10), 0, 0.0, 0.0}, {radians(20), 0, radians(40), -kPi / 2}};
  table.values.resize(3, 4);
  table.values << 0.5, 0.5, 0.5, 0.5,  //
      1, 2, 3, 4,                      //
      0.1, 0.2, 0.3, 0.4;
  table.header = {{"SAMPLE_NAME", "Small"}};
  return table;
}

TEST(MeasuredTable, DirectionsFollowTheCornellConvention) {
  const MeasuredTable table = smallSpectral();
  const Vec3 wi = table.incidentDirection(0), wo = table.outgoingDirection(0);
  EXPECT_TRUE(wi.isApprox(Vec3(std::sin(radians(10)), 0, std::cos(radians(10))), 1e-15));
  // phi_i = 0 and phi_s = pi: the mirror side; equal thetas would be the mirror direction itself.
  EXPECT_LT(wo.x(), 0.0);
  EXPECT_TRUE(directionFromAngles(radians(10), kPi).isApprox(reflect<double>(wi, Vec3::UnitZ()), 1e-15));
  EXPECT_TRUE(table.outgoingDirection(1).isApprox(Vec3::UnitZ(), 1e-15));
  EXPECT_NEAR(directionFromAngles(0.7, -2.0).norm(), 1.0, 1e-15);
}

TEST(MeasuredTable, IncidentAnglesAndChannels) {
  const MeasuredTable table = smallSpectral();
  EXPECT_EQ(table.incidentThetas(), (std::vector<double>{radians(10), radians(20)}));
  EXPECT_EQ(table.incidentAngles().size(), 2u);
  EXPECT_EQ(table.samplesAtIncidentTheta(radians(10)), (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(table.channelIndex("600NM"), 2u);
  EXPECT_FALSE(table.channelIndex("R").has_value());
}

TEST(MeasuredTable, ToRgbBySingleWavelengthsSaysWhichWereUsed) {
  const MeasuredTable rgb = smallSpectral().toRgb(RgbMethod::SingleWavelengths);
  EXPECT_EQ(rgb.values(1, 0), 4.0);  // 700 nm for 750
  EXPECT_EQ(rgb.values(1, 1), 2.0);  // 500 nm for 550 (ties go to the shorter wavelength)
  EXPECT_EQ(rgb.values(1, 2), 1.0);  // 400 nm
  ASSERT_FALSE(rgb.notes.empty());
  EXPECT_NE(rgb.notes.back().find("R = 700 nm (nearest available to 750 nm)"), std::string::npos) << rgb.notes.back();
}

TEST(MeasuredTable, ToRgbOfRgbAndMonochrome) {
  MeasuredTable mono;
  mono.kind = ChannelKind::Monochrome;
  mono.channelNames = {"BRDF"};
  mono.angles = {{0.1, 0, 0.2, 0}};
  mono.values.resize(1, 1);
  mono.values << 0.25;
  const MeasuredTable rgb = mono.toRgb();
  EXPECT_EQ(rgb.values.cols(), 3);
  EXPECT_TRUE((rgb.values.array() == 0.25).all());
  const MeasuredTable again = rgb.toRgb();
  EXPECT_EQ(again.values, rgb.values);
  EXPECT_EQ(again.notes, rgb.notes);
}

// The CIE 1931 2-degree colour-matching functions (xbar, ybar, zbar) at 400, 410, ..., 700 nm and
// CIE illuminant D65 (relative, 100 at 560 nm) at the same wavelengths, typed from the published
// tables (CIE 015:2004 Tables T.1 and T.4).
struct PublishedRow {
  double nm, xBar, yBar, zBar, d65;
};
constexpr PublishedRow kPublished[31] = {
    {400, 0.01431, 0.000396, 0.06785, 82.7549}, {410, 0.04351, 0.00121, 0.2074, 91.486},
    {420, 0.13438, 0.004, 0.6456, 93.4318},     {430, 0.2839, 0.0116, 1.3856, 86.6823},
    {440, 0.34828, 0.023, 1.74706, 104.865},    {450, 0.3362, 0.038, 1.77211, 117.008},
    {460, 0.2908, 0.06, 1.6692, 117.812},       {470, 0.19536, 0.09098, 1.28764, 114.861},
    {480, 0.09564, 0.13902, 0.81295, 115.923},  {490, 0.03201, 0.20802, 0.46518, 108.811},
    {500, 0.0049, 0.323, 0.272, 109.354},       {510, 0.0093, 0.503, 0.1582, 107.802},
    {520, 0.06327, 0.71, 0.07825, 104.79},      {530, 0.1655, 0.862, 0.04216, 107.689},
    {540, 0.2904, 0.954, 0.0203, 104.405},      {550, 0.43345, 0.99495, 0.00875, 104.046},
    {560, 0.5945, 0.995, 0.0039, 100.0},        {570, 0.7621, 0.952, 0.0021, 96.3342},
    {580, 0.9163, 0.87, 0.00165, 95.788},       {590, 1.0263, 0.757, 0.0011, 88.6856},
    {600, 1.0622, 0.631, 0.0008, 90.0062},      {610, 1.0026, 0.503, 0.00034, 89.5991},
    {620, 0.85445, 0.381, 0.00019, 87.6987},    {630, 0.6424, 0.265, 0.00005, 83.2886},
    {640, 0.4479, 0.175, 0.00002, 83.6992},     {650, 0.2835, 0.107, 0.0, 80.0268},
    {660, 0.1649, 0.061, 0.0, 80.2146},         {670, 0.0874, 0.032, 0.0, 82.2778},
    {680, 0.04677, 0.017, 0.0, 78.2842},        {690, 0.0227, 0.00821, 0.0, 69.7213},
    {700, 0.011359, 0.004102, 0.0, 71.6091}};

// The conversion of brdf/spectrum.hpp typed out for any grid: the spectrum read linearly between
// its samples and held beyond them at every 5 nm of the CIE tables, weighted by D65 x CMF,
// normalised by the white's Y; XYZ to linear sRGB by the IEC 61966-2-1 4-decimal matrix (which the
// library's derived matrix matches to 4e-4 per entry: hence tolerances of 5e-4 x |X| + |Y| + |Z|).
// `scale` receives |X| + |Y| + |Z|.
Rgb documentedRgb(const std::vector<double>& grid, const std::vector<double>& values, double& scale) {
  const auto cmf = cie1931Cmf2Deg();
  const auto d65 = cieD65Spd();
  const double m[3][3] = {{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};
  double xyz[3] = {0, 0, 0}, whiteY = 0.0;
  for (std::size_t k = 0; k < cmf.size(); ++k) {
    const double nm = cmf[k].wavelengthNm;
    double v = values.front();
    if (nm >= grid.back()) {
      v = values.back();
    } else if (nm > grid.front()) {
      std::size_t j = 0;
      while (grid[j + 1] < nm) ++j;
      const double f = (nm - grid[j]) / (grid[j + 1] - grid[j]);
      v = (1.0 - f) * values[j] + f * values[j + 1];
    }
    xyz[0] += d65[k] * cmf[k].xBar * v, xyz[1] += d65[k] * cmf[k].yBar * v, xyz[2] += d65[k] * cmf[k].zBar * v;
    whiteY += d65[k] * cmf[k].yBar;
  }
  for (double& c : xyz) c /= whiteY;
  scale = std::abs(xyz[0]) + std::abs(xyz[1]) + std::abs(xyz[2]);
  Rgb out;
  for (int c = 0; c < 3; ++c) out[c] = m[c][0] * xyz[0] + m[c][1] * xyz[1] + m[c][2] * xyz[2];
  return out;
}

TEST(Cie1931Tables, MatchThePublishedTablesEvery10nmWithoutTheSharedData) {
  // The tables the conversion integrates against (5 nm, 380..780 nm) agree with the published
  // values at every 10 nm from 400 to 700 nm, and ybar(555 nm) = 1.
  const auto cmf = cie1931Cmf2Deg();
  const auto d65 = cieD65Spd();
  ASSERT_EQ(cmf.size(), 81u);
  ASSERT_EQ(d65.size(), 81u);
  for (int j = 0; j < 31; ++j) {
    const std::size_t k = 4 + 2 * static_cast<std::size_t>(j);  // 380 + 5 k nm
    const PublishedRow& p = kPublished[j];
    EXPECT_EQ(cmf[k].wavelengthNm, p.nm);
    EXPECT_NEAR(cmf[k].xBar, p.xBar, 1e-6) << p.nm;
    EXPECT_NEAR(cmf[k].yBar, p.yBar, 1e-6) << p.nm;
    EXPECT_NEAR(cmf[k].zBar, p.zBar, 1e-6) << p.nm;
    EXPECT_NEAR(d65[k], p.d65, 1e-4) << p.nm;
  }
  EXPECT_EQ(cmf[35].wavelengthNm, 555.0);
  EXPECT_EQ(cmf[35].yBar, 1.0);
}

TEST(MeasuredTable, ToRgbByCie1931FollowsTheDocumentedMethod) {
  const MeasuredTable table = smallSpectral();
  const MeasuredTable rgb = table.toRgb(RgbMethod::Cie1931);
  EXPECT_EQ(rgb.kind, ChannelKind::Trichromatic);
  EXPECT_EQ(rgb.channelNames, (std::vector<std::string>{"R", "G", "B"}));
  EXPECT_TRUE(rgb.wavelengthsNm.empty());
  ASSERT_EQ(rgb.values.rows(), 3);
  // A constant spectrum 0.5 is the D65 white at half intensity: sRGB (0.5, 0.5, 0.5) by the
  // standard's definition of its white (within the 4-decimal matrix's 3e-4).
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgb.values(0, c), 0.5, 2e-4);
  // Every row against the method typed out (documentedRgb).
  for (Eigen::Index row = 0; row < 3; ++row) {
    std::vector<double> values(4);
    for (Eigen::Index c = 0; c < 4; ++c) values[c] = table.values(row, c);
    double scale = 0.0;
    const Rgb expected = documentedRgb(table.wavelengthsNm, values, scale);
    for (Eigen::Index c = 0; c < 3; ++c)
      EXPECT_NEAR(rgb.values(row, c), expected[c], 5e-4 * scale) << "row " << row << " channel " << c;
  }
  // The rising spectrum (1, 2, 3, 4 at 400..700 nm) is reddish.
  EXPECT_GT(rgb.values(1, 0), rgb.values(1, 2));
  ASSERT_FALSE(rgb.notes.empty());
  EXPECT_NE(rgb.notes.back().find("CIE 1931"), std::string::npos);
}

TEST(MeasuredTable, RealGarnetRedToRgb) {
  BRDFBAKE_REQUIRE_SHARED(path, "data/cornell/garnet_red.astm");
  const MeasuredTable spectral = readAstm(path);
  ASSERT_EQ(spectral.wavelengthsNm.size(), 31u);
  const MeasuredTable rgb = spectral.toRgb(RgbMethod::Cie1931);
  ASSERT_EQ(rgb.size(), 1439u);

  // The tables are checked against the published ones by Cie1931Tables (above); the file's grid:
  const auto cmf = cie1931Cmf2Deg();
  const auto d65 = cieD65Spd();
  for (int j = 0; j < 31; ++j) EXPECT_EQ(spectral.wavelengthsNm[static_cast<std::size_t>(j)], kPublished[j].nm);

  // The documented method typed out (brdf/spectrum.hpp): the spectrum read linearly between its
  // samples and held beyond them at every 5 nm, weighted by D65 x CMF, normalised by the white's
  // Y; XYZ to linear sRGB by the IEC 61966-2-1 matrix (4 decimals, which the library's derived
  // matrix matches to 4e-4 per entry).
  const double m[3][3] = {{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};
  auto expectedRgb = [&](Eigen::Index row, double& scale) {
    double xyz[3] = {0, 0, 0}, whiteY = 0.0;
    for (std::size_t k = 0; k < cmf.size(); ++k) {
      const double nm = cmf[k].wavelengthNm;
      double v;
      if (nm <= 400.0) {
        v = spectral.values(row, 0);
      } else if (nm >= 700.0) {
        v = spectral.values(row, 30);
      } else {
        const int j = static_cast<int>((nm - 400.0) / 10.0);
        const double f = (nm - 400.0 - 10.0 * j) / 10.0;
        v = (1.0 - f) * spectral.values(row, j) + f * spectral.values(row, j + 1);
      }
      xyz[0] += d65[k] * cmf[k].xBar * v, xyz[1] += d65[k] * cmf[k].yBar * v, xyz[2] += d65[k] * cmf[k].zBar * v;
      whiteY += d65[k] * cmf[k].yBar;
    }
    for (double& c : xyz) c /= whiteY;
    scale = std::abs(xyz[0]) + std::abs(xyz[1]) + std::abs(xyz[2]);
    Rgb out;
    for (int c = 0; c < 3; ++c) out[c] = m[c][0] * xyz[0] + m[c][1] * xyz[1] + m[c][2] * xyz[2];
    return out;
  };
  for (Eigen::Index row = 0; row < 1439; ++row) {
    double scale = 0.0;
    const Rgb expected = expectedRgb(row, scale);
    for (Eigen::Index c = 0; c < 3; ++c)
      ASSERT_NEAR(rgb.values(row, c), expected[c], 5e-4 * scale + 1e-12) << "row " << row << " channel " << c;
  }
  // The diffuse part of garnet red is red; the highlight (last row, near mirror at 80 deg) is
  // much brighter and about neutral.
  EXPECT_GT(rgb.values(0, 0), 2.0 * rgb.values(0, 1));
  EXPECT_GT(rgb.values(0, 0), 2.0 * rgb.values(0, 2));
  double scale = 0.0;
  const Rgb highlight = expectedRgb(1438, scale);
  EXPECT_GT(highlight.minCoeff(), 0.85 * highlight.maxCoeff());
  EXPECT_GT(highlight.minCoeff(), 20.0 * rgb.values(0, 0));
  const MeasuredTable single = spectral.toRgb(RgbMethod::SingleWavelengths);
  EXPECT_EQ(single.values(0, 0), spectral.values(0, 30));
  EXPECT_EQ(single.values(0, 1), spectral.values(0, 15));
  EXPECT_EQ(single.values(0, 2), spectral.values(0, 0));
}

TEST(MeasuredTable, WithMirroredHalf) {
  const MeasuredTable full = smallSpectral().withMirroredHalf();
  // Sample 0 (phi_s = pi) and 1 (theta_s = 0) are in the plane of incidence; only 2 is mirrored.
  ASSERT_EQ(full.size(), 4u);
  EXPECT_DOUBLE_EQ(full.angles[3].phiOut, kPi / 2);
  EXPECT_EQ(full.values.row(3), full.values.row(2));

  MeasuredTable tilted = smallSpectral();
  tilted.angles[0].phiIn = 0.5;
  EXPECT_TRUE(test::throwsError([&] { tilted.withMirroredHalf(); }, Error::Kind::InvalidArgument, {"phi_i = 0"}));
}

TEST(MeasuredTable, RealMirroredHalf) {
  BRDFBAKE_REQUIRE_SHARED(path, "data/cornell/krylon_blue.astm");
  const MeasuredTable table = readAstm(path);
  // 72 samples have phi_s = pi and 53 phi_s = 0 (the 7 at theta_s = 0 among them): 1439 - 125 = 1314 mirrored.
  EXPECT_EQ(table.withMirroredHalf().size(), 1439u + 1314u);
}

TEST(MeasuredTable, ValidateCatchesInconsistentTables) {
  MeasuredTable table = smallSpectral();
  table.values(2, 1) = std::nan("");
  EXPECT_TRUE(rejects([&] { table.validate(); }, {"non-finite"}));
  table = smallSpectral();
  table.wavelengthsNm.pop_back();
  EXPECT_TRUE(rejects([&] { table.validate(); }, {"3 wavelengths for 4 channels"}));
  table = smallSpectral();
  table.angles[0].thetaOut = 2.0;
  EXPECT_TRUE(rejects([&] { table.validate(); }, {"sample 0: theta_s = 2 is outside"}));
}

TEST(MeasuredIo, FormatNames) {
  for (TableFormat f : {TableFormat::Auto, TableFormat::Astm, TableFormat::Pbrt, TableFormat::Merl, TableFormat::Mat})
    EXPECT_EQ(parseTableFormat(toString(f)), f);
  EXPECT_EQ(parseTableFormat("ASTM"), TableFormat::Astm);
  EXPECT_THROW(parseTableFormat("csv"), Error);
}

TEST(MeasuredIo, DetectsTextFormatsByContent) {
  test::TempDir dir;
  writeFile(dir / "a.txt", "\n\nSAMPLE_NAME x\nVARS theta_i,phi_i,theta_s,phi_s,R,G,B\n0.1,0,0.2,0,1,1,1\n");
  writeFile(dir / "b.txt", "# comment\r\n\r\n2\r\n400 500\r\n0.1 0 0.2 0 1 1\r\n");
  writeFile(dir / "c.txt", "2\n400 500\n0.1 0 0.2 0 1 1\n");
  writeFile(dir / "d.txt", "hello world\n");
  writeFile(dir / "e.txt", "");
  EXPECT_EQ(detectTableFormat(dir / "a.txt"), TableFormat::Astm);
  EXPECT_EQ(detectTableFormat(dir / "b.txt"), TableFormat::Pbrt);
  EXPECT_EQ(detectTableFormat(dir / "c.txt"), TableFormat::Pbrt);
  EXPECT_EQ(readMeasuredTable(dir / "a.txt").format, TableFormat::Astm);
  EXPECT_EQ(readMeasuredTable(dir / "b.txt").size(), 1u);
  EXPECT_TRUE(
      rejects([&] { detectTableFormat(dir / "d.txt"); }, {(dir / "d.txt").string(), "cannot tell the table format"}));
  EXPECT_TRUE(rejects([&] { detectTableFormat(dir / "e.txt"); }, {"cannot tell the table format"}));
  EXPECT_TRUE(test::throwsError([&] { readMeasuredTable(dir / "a.txt", TableFormat::Merl); },
                                Error::Kind::InvalidArgument, {"readMerl"}));
}

TEST(MeasuredIo, DetectsTheRealFiles) {
  BRDFBAKE_REQUIRE_SHARED(astm, "data/cornell/garnet_red_RGB.astm");
  BRDFBAKE_REQUIRE_SHARED(brdf, "data/cornell/krylon_blue.brdf");
  EXPECT_EQ(detectTableFormat(astm), TableFormat::Astm);
  EXPECT_EQ(detectTableFormat(brdf), TableFormat::Pbrt);
}

TEST(WriteAstm, RoundTripsExactly) {
  test::TempDir dir;
  MeasuredTable table = smallSpectral();
  table.values(2, 3) = 1.0 / 3.0;  // needs all 17 digits
  writeAstm(dir / "w.astm", table);
  const MeasuredTable back = readAstm(dir / "w.astm");
  EXPECT_EQ(back.values, table.values);
  EXPECT_EQ(back.wavelengthsNm, table.wavelengthsNm);
  for (std::size_t i = 0; i < table.size(); ++i) {
    EXPECT_EQ(back.angles[i].thetaIn, table.angles[i].thetaIn);
    EXPECT_EQ(back.angles[i].phiOut, table.angles[i].phiOut);
  }
  EXPECT_EQ(back.header.front(), (std::pair<std::string, std::string>{"SAMPLE_NAME", "Small"}));
  EXPECT_EQ(detectTableFormat(dir / "w.astm"), TableFormat::Astm);

  const MeasuredTable rgb = table.toRgb();
  writeAstm(dir / "rgb.astm", rgb);
  EXPECT_EQ(readAstm(dir / "rgb.astm").values, rgb.values);
}

TEST(WriteAstm, RoundTripsTheRealFile) {
  BRDFBAKE_REQUIRE_SHARED(path, "data/cornell/garnet_red_RGB.astm");
  test::TempDir dir;
  const MeasuredTable table = readAstm(path);
  writeAstm(dir / "copy.astm", table);
  const MeasuredTable back = readAstm(dir / "copy.astm");
  EXPECT_EQ(back.values, table.values);
  EXPECT_EQ(back.size(), 1439u);
  EXPECT_EQ(back.header.size(), table.header.size());
}

TEST(WriteAstm, RefusesInvalidTables) {
  test::TempDir dir;
  MeasuredTable table = smallSpectral();
  table.channelNames.pop_back();
  EXPECT_TRUE(rejects([&] { writeAstm(dir / "x.astm", table); }, {"3 channel names for 4 channels"}));
  EXPECT_FALSE(std::filesystem::exists(dir / "x.astm"));
}

}  // namespace
}  // namespace brdfbake
