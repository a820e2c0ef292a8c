#include <brdfbake/brdf/spectrum.hpp>

#include <brdfbake/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace brdfbake {

namespace {

// CIE 1931 2-degree observer at 5 nm: the CIE 1 nm table (CIE 015:2004) at every fifth
// wavelength, with the 1 nm table's last-digit rounding (e.g. 0.06785001) restored to the
// 5 nm values (0.06785). zbar is exactly 0 from 650 nm on.
constexpr std::array<CmfSample, 81> kCie1931{{
    {380, 0.001368, 3.9e-05, 0.00645},
    {385, 0.002236, 6.4e-05, 0.01055},
    {390, 0.004243, 0.00012, 0.02005},
    {395, 0.00765, 0.000217, 0.03621},
    {400, 0.01431, 0.000396, 0.06785},
    {405, 0.02319, 0.00064, 0.1102},
    {410, 0.04351, 0.00121, 0.2074},
    {415, 0.07763, 0.00218, 0.3713},
    {420, 0.13438, 0.004, 0.6456},
    {425, 0.21477, 0.0073, 1.03905},
    {430, 0.2839, 0.0116, 1.3856},
    {435, 0.3285, 0.01684, 1.62296},
    {440, 0.34828, 0.023, 1.74706},
    {445, 0.34806, 0.0298, 1.7826},
    {450, 0.3362, 0.038, 1.77211},
    {455, 0.3187, 0.048, 1.7441},
    {460, 0.2908, 0.06, 1.6692},
    {465, 0.2511, 0.0739, 1.5281},
    {470, 0.19536, 0.09098, 1.28764},
    {475, 0.1421, 0.1126, 1.0419},
    {480, 0.09564, 0.13902, 0.8129501},
    {485, 0.05795, 0.1693, 0.6162},
    {490, 0.03201, 0.20802, 0.46518},
    {495, 0.0147, 0.2586, 0.3533},
    {500, 0.0049, 0.323, 0.272},
    {505, 0.0024, 0.4073, 0.2123},
    {510, 0.0093, 0.503, 0.1582},
    {515, 0.0291, 0.6082, 0.1117},
    {520, 0.06327, 0.71, 0.07825},
    {525, 0.1096, 0.7932, 0.05725},
    {530, 0.1655, 0.862, 0.04216},
    {535, 0.2257499, 0.9148501, 0.02984},
    {540, 0.2904, 0.954, 0.0203},
    {545, 0.3597, 0.9803, 0.0134},
    {550, 0.4334499, 0.9949501, 0.00875},
    {555, 0.5120501, 1.0, 0.00575},
    {560, 0.5945, 0.995, 0.0039},
    {565, 0.6784, 0.9786, 0.00275},
    {570, 0.7621, 0.952, 0.0021},
    {575, 0.8425, 0.9154, 0.0018},
    {580, 0.9163, 0.87, 0.00165},
    {585, 0.9786, 0.8163, 0.0014},
    {590, 1.0263, 0.757, 0.0011},
    {595, 1.0567, 0.6949, 0.001},
    {600, 1.0622, 0.631, 0.0008},
    {605, 1.0456, 0.5668, 0.0006},
    {610, 1.0026, 0.503, 0.00034},
    {615, 0.9384, 0.4412, 0.00024},
    {620, 0.8544499, 0.381, 0.00019},
    {625, 0.7514, 0.321, 0.0001},
    {630, 0.6424, 0.265, 5e-05},
    {635, 0.5419, 0.217, 3e-05},
    {640, 0.4479, 0.175, 2e-05},
    {645, 0.3608, 0.1382, 1e-05},
    {650, 0.2835, 0.107, 0.0},
    {655, 0.2187, 0.0816, 0.0},
    {660, 0.1649, 0.061, 0.0},
    {665, 0.1212, 0.04458, 0.0},
    {670, 0.0874, 0.032, 0.0},
    {675, 0.0636, 0.0232, 0.0},
    {680, 0.04677, 0.017, 0.0},
    {685, 0.0329, 0.01192, 0.0},
    {690, 0.0227, 0.00821, 0.0},
    {695, 0.01584, 0.005723, 0.0},
    {700, 0.01135916, 0.004102, 0.0},
    {705, 0.008110916, 0.002929, 0.0},
    {710, 0.005790346, 0.002091, 0.0},
    {715, 0.004109457, 0.001484, 0.0},
    {720, 0.002899327, 0.001047, 0.0},
    {725, 0.00204919, 0.00074, 0.0},
    {730, 0.001439971, 0.00052, 0.0},
    {735, 0.0009999493, 0.0003611, 0.0},
    {740, 0.0006900786, 0.0002492, 0.0},
    {745, 0.0004760213, 0.0001719, 0.0},
    {750, 0.0003323011, 0.00012, 0.0},
    {755, 0.0002348261, 8.48e-05, 0.0},
    {760, 0.0001661505, 6e-05, 0.0},
    {765, 0.000117413, 4.24e-05, 0.0},
    {770, 8.307527e-05, 3e-05, 0.0},
    {775, 5.870652e-05, 2.12e-05, 0.0},
    {780, 4.150994e-05, 1.499e-05, 0.0},
}};

// CIE standard illuminant D65 (relative, 100 at 560 nm), 380..780 nm every 5 nm.
constexpr std::array<double, 81> kD65{
    49.9755, 52.3118, 54.6482, 68.7015, 82.7549, 87.1204, 91.486,  92.4589, 93.4318, 90.057,  86.6823, 95.7736,
    104.865, 110.936, 117.008, 117.41,  117.812, 116.336, 114.861, 115.392, 115.923, 112.367, 108.811, 109.082,
    109.354, 108.578, 107.802, 106.296, 104.79,  106.239, 107.689, 106.047, 104.405, 104.225, 104.046, 102.023,
    100.0,   98.1671, 96.3342, 96.0611, 95.788,  92.2368, 88.6856, 89.3459, 90.0062, 89.8026, 89.5991, 88.6489,
    87.6987, 85.4936, 83.2886, 83.4939, 83.6992, 81.863,  80.0268, 80.1207, 80.2146, 81.2462, 82.2778, 80.281,
    78.2842, 74.0027, 69.7213, 70.6652, 71.6091, 72.979,  74.349,  67.9765, 61.604,  65.7448, 69.8856, 72.4863,
    75.087,  69.3398, 63.5927, 55.0054, 46.4182, 56.6118, 66.8054, 65.0941, 63.3828,
};

Mat3 deriveXyzToSrgb() {
  // Columns: XYZ of the primaries scaled so that R = G = B = 1 is the D65 white with Y = 1.
  const auto xyzOf = [](double x, double y) { return Vec3(x / y, 1.0, (1.0 - x - y) / y); };
  Mat3 primaries;
  primaries << xyzOf(0.64, 0.33), xyzOf(0.30, 0.60), xyzOf(0.15, 0.06);
  const Vec3 white = xyzOf(0.3127, 0.3290);
  const Vec3 scale = primaries.partialPivLu().solve(white);
  const Mat3 rgbToXyz = primaries * scale.asDiagonal();
  return rgbToXyz.inverse();
}

std::string describeNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace

std::span<const CmfSample> cie1931Cmf2Deg() { return kCie1931; }

std::span<const double> cieD65Spd() { return kD65; }

const Mat3& xyzToLinearSrgbMatrix() {
  static const Mat3 matrix = deriveXyzToSrgb();
  return matrix;
}

Rgb xyzToLinearSrgb(const Vec3& xyz) { return (xyzToLinearSrgbMatrix() * xyz).array(); }

SpectrumToRgb::SpectrumToRgb(std::span<const double> wavelengthsNm)
    : wavelengthsNm_(wavelengthsNm.begin(), wavelengthsNm.end()) {
  const std::size_t n = wavelengthsNm_.size();
  require(n >= 1, "spectrum: at least one wavelength is needed");
  for (std::size_t j = 0; j < n; ++j) {
    require(std::isfinite(wavelengthsNm_[j]), "spectrum: wavelength " + std::to_string(j) + " is not finite");
    if (j > 0)
      require(wavelengthsNm_[j] > wavelengthsNm_[j - 1], "spectrum: wavelengths must be strictly increasing (" +
                                                             describeNumber(wavelengthsNm_[j - 1]) + " nm, then " +
                                                             describeNumber(wavelengthsNm_[j]) + " nm)");
  }

  // Each 5 nm grid point reads the piecewise-linear spectrum (held constant beyond the ends);
  // that reading is a weighted pair of samples, so the whole integral is linear in the samples.
  xyzWeights_.setZero(3, static_cast<Eigen::Index>(n));
  double whiteY = 0.0;
  for (std::size_t k = 0; k < kCie1931.size(); ++k) {
    const CmfSample& c = kCie1931[k];
    const Vec3 weight = kD65[k] * Vec3(c.xBar, c.yBar, c.zBar);
    whiteY += weight.y();
    const double lambda = c.wavelengthNm;
    if (lambda <= wavelengthsNm_.front()) {
      xyzWeights_.col(0) += weight;
    } else if (lambda >= wavelengthsNm_.back()) {
      xyzWeights_.col(static_cast<Eigen::Index>(n - 1)) += weight;
    } else {
      const auto upper = std::upper_bound(wavelengthsNm_.begin(), wavelengthsNm_.end(), lambda);
      const auto j = static_cast<Eigen::Index>(upper - wavelengthsNm_.begin()) - 1;
      const double t = (lambda - wavelengthsNm_[j]) / (wavelengthsNm_[j + 1] - wavelengthsNm_[j]);
      xyzWeights_.col(j) += (1.0 - t) * weight;
      xyzWeights_.col(j + 1) += t * weight;
    }
  }
  xyzWeights_ /= whiteY;
  srgbWeights_ = xyzToLinearSrgbMatrix() * xyzWeights_;
}

void SpectrumToRgb::checkValues(std::span<const double> values) const {
  require(values.size() == wavelengthsNm_.size(), "spectrum: " + std::to_string(values.size()) + " values for " +
                                                      std::to_string(wavelengthsNm_.size()) + " wavelengths");
  for (std::size_t j = 0; j < values.size(); ++j)
    require(std::isfinite(values[j]), "spectrum: value at " + describeNumber(wavelengthsNm_[j]) + " nm is not finite");
}

Vec3 SpectrumToRgb::xyz(std::span<const double> values) const {
  checkValues(values);
  return xyzWeights_ * Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

Rgb SpectrumToRgb::linearSrgb(std::span<const double> values) const {
  checkValues(values);
  return (srgbWeights_ * Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size())))
      .array();
}

Vec3 spectrumToXyz(std::span<const double> wavelengthsNm, std::span<const double> values) {
  return SpectrumToRgb(wavelengthsNm).xyz(values);
}

Rgb spectrumToLinearSrgb(std::span<const double> wavelengthsNm, std::span<const double> values) {
  return SpectrumToRgb(wavelengthsNm).linearSrgb(values);
}

WavelengthPick nearestWavelengths(std::span<const double> wavelengthsNm, const std::array<double, 3>& requestedNm) {
  require(!wavelengthsNm.empty(), "spectrum: no wavelengths to pick from");
  for (double w : wavelengthsNm) require(std::isfinite(w), "spectrum: a wavelength is not finite");
  WavelengthPick pick;
  pick.requestedNm = requestedNm;
  for (std::size_t c = 0; c < 3; ++c) {
    std::size_t best = 0;
    for (std::size_t j = 1; j < wavelengthsNm.size(); ++j) {
      const double d = std::abs(wavelengthsNm[j] - requestedNm[c]);
      const double bestD = std::abs(wavelengthsNm[best] - requestedNm[c]);
      if (d < bestD || (d == bestD && wavelengthsNm[j] < wavelengthsNm[best])) best = j;
    }
    pick.index[c] = best;
    pick.usedNm[c] = wavelengthsNm[best];
  }
  return pick;
}

Rgb singleWavelengthRgb(std::span<const double> values, const WavelengthPick& pick) {
  Rgb rgb;
  for (std::size_t c = 0; c < 3; ++c) {
    require(pick.index[c] < values.size(), "spectrum: wavelength pick outside the values");
    rgb[static_cast<Eigen::Index>(c)] = values[pick.index[c]];
  }
  return rgb;
}

}  // namespace brdfbake
