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

// Chromaticity (x, y) of monochromatic light on the CIE 1931 2-degree spectral locus, as published
// (CIE 015:2004 Table T.3, rounded to 4 decimals), and D65 and ybar there (Tables T.1 and T.4).
struct LocusPoint {
  double nm, x, y, d65, yBar;
};
constexpr LocusPoint kLocus[] = {{450, 0.1566, 0.0177, 117.008, 0.038},   {480, 0.0913, 0.1327, 115.923, 0.13902},
                                 {500, 0.0082, 0.5384, 109.354, 0.323},   {520, 0.0743, 0.8338, 104.79, 0.71},
                                 {550, 0.3016, 0.6923, 104.046, 0.99495}, {580, 0.5125, 0.4866, 95.788, 0.87},
                                 {600, 0.6270, 0.3725, 90.0062, 0.631},   {650, 0.7260, 0.2740, 80.0268, 0.107},
                                 {700, 0.7347, 0.2653, 71.6091, 0.004102}};

// Light at `nm` alone: 1 at nm, 0 at nm -+ 5 (and beyond), so of the 5 nm grid only nm is lit.
Vec3 monochromaticXyz(double nm) {
  const std::vector<double> grid{nm - 5.0, nm, nm + 5.0}, values{0.0, 1.0, 0.0};
  return spectrumToXyz(grid, values);
}

TEST(SpectrumToLinearSrgb, MonochromaticLightHasThePublishedChromaticity) {
  // sRGB back to XYZ by the standard's own 4-decimal matrix (IEC 61966-2-1), so the RGB is checked
  // against the published figures too; the two matrices are each other's inverse to 4e-4 per
  // entry, which moves a chromaticity by at most 2e-3 here.
  Mat3 srgbToXyz;
  srgbToXyz << 0.4124, 0.3576, 0.1805,  //
      0.2126, 0.7152, 0.0722,           //
      0.0193, 0.1192, 0.9505;
  for (const LocusPoint& p : kLocus) {
    const Vec3 xyz = monochromaticXyz(p.nm);
    EXPECT_NEAR(xyz.x() / xyz.sum(), p.x, 1e-4) << p.nm << " nm";  // the table's rounding: 5e-5
    EXPECT_NEAR(xyz.y() / xyz.sum(), p.y, 1e-4) << p.nm << " nm";
    const std::vector<double> grid{p.nm - 5.0, p.nm, p.nm + 5.0}, values{0.0, 1.0, 0.0};
    const Rgb rgb = spectrumToLinearSrgb(grid, values);
    const Vec3 back = srgbToXyz * rgb.matrix();
    EXPECT_NEAR(back.x() / back.sum(), p.x, 2e-3) << p.nm << " nm";
    EXPECT_NEAR(back.y() / back.sum(), p.y, 2e-3) << p.nm << " nm";
  }
  // Luminance in proportion to D65 x ybar at the wavelength: Y(550) / Y(600) and Y(480) / Y(650).
  EXPECT_NEAR(monochromaticXyz(550).y() / monochromaticXyz(600).y(), (104.046 * 0.99495) / (90.0062 * 0.631),
              1e-4 * 1.82);
  EXPECT_NEAR(monochromaticXyz(480).y() / monochromaticXyz(650).y(), (115.923 * 0.13902) / (80.0268 * 0.107),
              1e-4 * 1.88);
  // Green light (520 nm) lies outside the sRGB gamut: red goes negative; 700 nm is nearly the red
  // primary (0.64, 0.33) seen from the white: green and blue small and negative.
  const std::vector<double> g520{515, 520, 525}, g700{695, 700, 705}, one{0.0, 1.0, 0.0};
  EXPECT_LT(spectrumToLinearSrgb(g520, one)[0], 0.0);
  const Rgb red = spectrumToLinearSrgb(g700, one);
  EXPECT_GT(red[0], 0.0);
  EXPECT_LT(std::abs(red[1]), 0.15 * red[0]);
  EXPECT_LT(std::abs(red[2]), 0.05 * red[0]);
}

TEST(SpectrumToXyz, AnIrregularGridIsReadLinearlyBetweenItsSamplesAndHeldBeyond) {
  // s = 1 below 450 nm, linear from 1 at 450 to 3 at 520, to 2 at 690, 2 above: the sums of
  // brdf/spectrum.hpp's formula over the CIE 5 nm tables (checked against the published tables by
  // Cie1931Cmf.KnownValuesAndPeaks and CieD65.WhitePointChromaticity).
  const std::vector<double> grid{450, 520, 690}, values{1.0, 3.0, 2.0};
  auto s = [](double nm) {
    if (nm <= 450) return 1.0;
    if (nm >= 690) return 2.0;
    return nm <= 520 ? 1.0 + 2.0 * (nm - 450) / 70.0 : 3.0 - (nm - 520) / 170.0;
  };
  const auto cmf = cie1931Cmf2Deg();
  const auto d65 = cieD65Spd();
  Vec3 expected = Vec3::Zero();
  double white = 0.0;
  for (std::size_t k = 0; k < cmf.size(); ++k) {
    expected += d65[k] * s(cmf[k].wavelengthNm) * Vec3(cmf[k].xBar, cmf[k].yBar, cmf[k].zBar);
    white += d65[k] * cmf[k].yBar;
  }
  expected /= white;
  EXPECT_TRUE(spectrumToXyz(grid, values).isApprox(expected, 1e-12)) << spectrumToXyz(grid, values).transpose();
  // Scaling the spectrum scales XYZ; a grid of one sample is a constant spectrum (Y = its value).
  const std::vector<double> doubled{2.0, 6.0, 4.0};
  EXPECT_TRUE(spectrumToXyz(grid, doubled).isApprox(2.0 * expected, 1e-12));
  const std::vector<double> single{600.0}, value{0.7};
  EXPECT_NEAR(spectrumToXyz(single, value).y(), 0.7, 1e-12);
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
