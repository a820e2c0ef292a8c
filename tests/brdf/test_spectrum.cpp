// Spectral -> linear sRGB: the CIE tables, the sRGB matrix, and the normalisation.
#include <brdfbake/brdf/spectrum.hpp>
#include <brdfbake/core/error.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace brdfbake {
namespace {

// The Cornell tables' grid: 400..700 nm every 10 nm (31 wavelengths).
std::vector<double> cornellGrid() {
  std::vector<double> grid;
  for (int nm = 400; nm <= 700; nm += 10) grid.push_back(nm);
  return grid;
}

// 1 at `peakNm`, 0 elsewhere on the Cornell grid.
std::vector<double> monochromatic(double peakNm) {
  std::vector<double> values;
  for (double nm : cornellGrid()) values.push_back(nm == peakNm ? 1.0 : 0.0);
  return values;
}

TEST(Cie1931Cmf, TableIs380To780Every5nm) {
  const auto cmf = cie1931Cmf2Deg();
  ASSERT_EQ(cmf.size(), 81u);
  for (std::size_t k = 0; k < cmf.size(); ++k) EXPECT_EQ(cmf[k].wavelengthNm, 380.0 + 5.0 * k);
}

TEST(Cie1931Cmf, KnownValuesAndPeaks) {
  const auto cmf = cie1931Cmf2Deg();
  const auto at = [&](double nm) {
    return *std::find_if(cmf.begin(), cmf.end(), [&](const CmfSample& s) { return s.wavelengthNm == nm; });
  };
  // ybar is the photopic luminous efficiency: 1 at 555 nm, its maximum.
  EXPECT_EQ(at(555).yBar, 1.0);
  for (const CmfSample& s : cmf) EXPECT_LE(s.yBar, 1.0);
  // A few CIE 015 values.
  EXPECT_DOUBLE_EQ(at(600).xBar, 1.0622);
  EXPECT_DOUBLE_EQ(at(440).xBar, 0.34828);
  EXPECT_DOUBLE_EQ(at(445).zBar, 1.7826);
  EXPECT_DOUBLE_EQ(at(500).yBar, 0.323);
  EXPECT_DOUBLE_EQ(at(380).xBar, 0.001368);
  EXPECT_EQ(at(700).zBar, 0.0);
  // xbar peaks at 595-600 nm, zbar at 445 nm (on the 5 nm grid).
  const auto xMax = std::max_element(cmf.begin(), cmf.end(), [](auto& a, auto& b) { return a.xBar < b.xBar; });
  const auto zMax = std::max_element(cmf.begin(), cmf.end(), [](auto& a, auto& b) { return a.zBar < b.zBar; });
  EXPECT_EQ(xMax->wavelengthNm, 600.0);
  EXPECT_EQ(zMax->wavelengthNm, 445.0);
}

TEST(Cie1931Cmf, EqualEnergyWhiteHasEqualTristimulusSums) {
  // The CIE functions are scaled so that illuminant E has X = Y = Z; at 5 nm each sum is 21.371.
  double x = 0, y = 0, z = 0;
  for (const CmfSample& s : cie1931Cmf2Deg()) {
    x += s.xBar;
    y += s.yBar;
    z += s.zBar;
  }
  EXPECT_NEAR(y, 21.3714, 1e-3);
  EXPECT_NEAR(x / y, 1.0, 1e-4);
  EXPECT_NEAR(z / y, 1.0, 1e-4);
}

TEST(CieD65, WhitePointChromaticity) {
  const auto d65 = cieD65Spd();
  const auto cmf = cie1931Cmf2Deg();
  ASSERT_EQ(d65.size(), cmf.size());
  EXPECT_EQ(d65[(560 - 380) / 5], 100.0);
  Vec3 xyz = Vec3::Zero();
  for (std::size_t k = 0; k < cmf.size(); ++k) xyz += d65[k] * Vec3(cmf[k].xBar, cmf[k].yBar, cmf[k].zBar);
  EXPECT_NEAR(xyz.x() / xyz.sum(), 0.3127, 2e-4);
  EXPECT_NEAR(xyz.y() / xyz.sum(), 0.3290, 2e-4);
}

TEST(XyzToSrgb, MatchesIec61966Matrix) {
  const Mat3& m = xyzToLinearSrgbMatrix();
  Mat3 iec;
  iec << 3.2406, -1.5372, -0.4986,  //
      -0.9689, 1.8758, 0.0415,      //
      0.0557, -0.2040, 1.0570;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(m(r, c), iec(r, c), 4e-4) << "row " << r << " column " << c;
  // The D65 white (Y = 1) maps to (1, 1, 1).
  const Rgb white = xyzToLinearSrgb(Vec3(0.95047, 1.0, 1.08883));
  EXPECT_NEAR(white[0], 1.0, 1e-3);
  EXPECT_NEAR(white[1], 1.0, 1e-3);
  EXPECT_NEAR(white[2], 1.0, 1e-3);
}

TEST(SpectrumToLinearSrgb, ConstantSpectrumIsGreyOfTheSameValue) {
  const std::vector<double> grid = cornellGrid();
  for (double v : {1.0, 0.37, 29.5}) {
    const std::vector<double> flat(grid.size(), v);
    const Rgb rgb = spectrumToLinearSrgb(grid, flat);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgb[c], v, 3e-4 * v) << "channel " << c << " for v = " << v;
    EXPECT_NEAR(spectrumToXyz(grid, flat).y(), v, 1e-12 * v);
  }
  // Any grid, even one sample (a constant spectrum).
  const std::vector<double> one{555.0}, value{2.0};
  EXPECT_NEAR(spectrumToLinearSrgb(one, value)[1], 2.0, 1e-3);
}

TEST(SpectrumToLinearSrgb, MonochromaticSpectraHaveTheExpectedHue) {
  const std::vector<double> grid = cornellGrid();
  const Rgb red = spectrumToLinearSrgb(grid, monochromatic(700));
  EXPECT_GT(red[0], 0.0);
  EXPECT_GT(red[0], 5.0 * std::abs(red[1]));
  EXPECT_GT(red[0], 5.0 * std::abs(red[2]));
  const Rgb green = spectrumToLinearSrgb(grid, monochromatic(530));
  EXPECT_GT(green[1], green[0]);
  EXPECT_GT(green[1], green[2]);
  const Rgb blue = spectrumToLinearSrgb(grid, monochromatic(450));
  EXPECT_GT(blue[2], blue[0]);
  EXPECT_GT(blue[2], blue[1]);
}

TEST(SpectrumToRgb, IsLinearWithRowsSummingToOne) {
  const std::vector<double> grid = cornellGrid();
  const SpectrumToRgb converter(grid);
  ASSERT_EQ(converter.srgbWeights().cols(), 31);
  // Constant 1 -> (1, 1, 1) means each row of weights sums to about 1, and Y exactly to 1.
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(converter.srgbWeights().row(c).sum(), 1.0, 3e-4);
  EXPECT_NEAR(converter.xyzWeights().row(1).sum(), 1.0, 1e-12);
  const std::vector<double> a = monochromatic(600), b = monochromatic(450);
  std::vector<double> sum(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) sum[i] = 2.0 * a[i] + b[i];
  const Rgb expected = 2.0 * converter.linearSrgb(a) + converter.linearSrgb(b);
  EXPECT_TRUE(converter.linearSrgb(sum).isApprox(expected, 1e-12));
}

TEST(SpectrumToRgb, RejectsBadInput) {
  const std::vector<double> decreasing{500, 400}, empty;
  EXPECT_THROW(SpectrumToRgb{decreasing}, Error);
  EXPECT_THROW(SpectrumToRgb{empty}, Error);
  const std::vector<double> grid{400, 500, 600};
  const std::vector<double> withNan{1.0, std::nan(""), 1.0}, shortValues{1.0, 1.0};
  try {
    spectrumToLinearSrgb(grid, withNan);
    ADD_FAILURE() << "NaN accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::InvalidArgument);
    EXPECT_NE(std::string(e.what()).find("500 nm is not finite"), std::string::npos) << e.what();
  }
  EXPECT_THROW(spectrumToLinearSrgb(grid, shortValues), Error);
}

TEST(SingleWavelengths, NearestAvailableStandsInForTheSeedsWavelengths) {
  const std::vector<double> grid = cornellGrid();
  const WavelengthPick pick = nearestWavelengths(grid);
  EXPECT_EQ(pick.requestedNm, kSingleWavelengthRgbNm);
  EXPECT_EQ(pick.usedNm, (std::array<double, 3>{700.0, 550.0, 400.0}));
  EXPECT_EQ(pick.index, (std::array<std::size_t, 3>{30, 15, 0}));
  EXPECT_TRUE(pick.substituted());
  std::vector<double> values(grid.size());
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = grid[i] / 1000.0;
  const Rgb rgb = singleWavelengthRgb(values, pick);
  EXPECT_DOUBLE_EQ(rgb[0], 0.7);
  EXPECT_DOUBLE_EQ(rgb[1], 0.55);
  EXPECT_DOUBLE_EQ(rgb[2], 0.4);
  // Ties go to the shorter wavelength; an exact grid is not a substitution.
  const std::vector<double> coarse{400, 500, 600, 750};
  EXPECT_EQ(nearestWavelengths(coarse, {750, 550, 400}).usedNm, (std::array<double, 3>{750, 500, 400}));
  EXPECT_FALSE(nearestWavelengths(coarse, {750, 500, 400}).substituted());
}

}  // namespace
}  // namespace brdfbake
