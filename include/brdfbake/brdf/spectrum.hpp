#pragma once
/// @file
/// Spectral data to linear sRGB: the one implementation every part uses (measured BRDF tables,
/// spectral Fresnel tables).
///
/// Method (docs/measured_tables.md, "Spectral to RGB"): a spectrum s(lambda) given at some
/// wavelengths is read as a reflectance-like factor (a BRDF in 1/sr, a Fresnel reflectance, ...).
/// It is interpolated linearly between its samples and held constant beyond its first and last
/// sample, evaluated on the 5 nm grid of the CIE 1931 2-degree colour-matching functions
/// (380..780 nm), lit by CIE standard illuminant D65 and integrated as a Riemann sum:
///
///     X = sum_k D65(l_k) xbar(l_k) s(l_k) / sum_k D65(l_k) ybar(l_k)     (Y, Z likewise)
///
/// so a constant spectrum v gives XYZ = v * (D65 white, Y = 1). XYZ then goes to linear sRGB with
/// the IEC 61966-2-1 matrix (D65 white, no chromatic adaptation needed), so a constant spectrum v
/// maps to (v, v, v) within 3e-4 relative. Results are linear (no transfer curve) and may be
/// negative for colours outside the sRGB gamut (e.g. monochromatic light).

#include <brdfbake/core/color.hpp>
#include <brdfbake/core/math.hpp>

#include <array>
#include <cstddef>
#include <span>
#include <vector>

namespace brdfbake {

/// One row of a tabulated colour-matching function (dimensionless, ybar peaks at 1).
struct CmfSample {
  double wavelengthNm;
  double xBar, yBar, zBar;
};

/// The CIE 1931 2-degree standard observer, 380..780 nm every 5 nm (81 rows): the CIE 1 nm table
/// (CIE 015:2004) at every fifth wavelength. ybar(555 nm) = 1.
std::span<const CmfSample> cie1931Cmf2Deg();

/// CIE standard illuminant D65, relative spectral power (100 at 560 nm), at the wavelengths of
/// cie1931Cmf2Deg() (81 values, 380..780 nm every 5 nm; CIE 015:2004 Table T.1).
std::span<const double> cieD65Spd();

/// CIE XYZ (Y = 1 for the white) to linear sRGB: IEC 61966-2-1 primaries R (0.64, 0.33),
/// G (0.30, 0.60), B (0.15, 0.06) and white D65 (0.3127, 0.3290), derived from these
/// chromaticities; agrees with the standard's 4-decimal matrix
/// [3.2406 -1.5372 -0.4986; -0.9689 1.8758 0.0415; 0.0557 -0.2040 1.0570] to 4e-4.
const Mat3& xyzToLinearSrgbMatrix();
Rgb xyzToLinearSrgb(const Vec3& xyz);

/// The spectral->XYZ->linear sRGB map for one wavelength grid, precomputed: the conversion is
/// linear in the values, so it is a 3 x N matrix (cheap to apply to thousands of samples).
class SpectrumToRgb {
 public:
  /// `wavelengthsNm`: at least one, finite, strictly increasing (nm). Throws
  /// Error(InvalidArgument) otherwise.
  explicit SpectrumToRgb(std::span<const double> wavelengthsNm);

  std::size_t size() const { return wavelengthsNm_.size(); }
  const std::vector<double>& wavelengthsNm() const { return wavelengthsNm_; }

  /// XYZ of the spectrum under D65, normalised so that a constant 1 has Y = 1 (see @file).
  /// `values` must have size() finite entries, else Error(InvalidArgument).
  Vec3 xyz(std::span<const double> values) const;
  /// Linear sRGB; a constant spectrum v gives about (v, v, v).
  Rgb linearSrgb(std::span<const double> values) const;

  /// XYZ = xyzWeights() * values.
  const Eigen::Matrix<double, 3, Eigen::Dynamic>& xyzWeights() const { return xyzWeights_; }
  /// linear sRGB = srgbWeights() * values.
  const Eigen::Matrix<double, 3, Eigen::Dynamic>& srgbWeights() const { return srgbWeights_; }

 private:
  void checkValues(std::span<const double> values) const;
  std::vector<double> wavelengthsNm_;
  Eigen::Matrix<double, 3, Eigen::Dynamic> xyzWeights_, srgbWeights_;
};

/// One-shot SpectrumToRgb(wavelengthsNm).xyz(values).
Vec3 spectrumToXyz(std::span<const double> wavelengthsNm, std::span<const double> values);
/// One-shot SpectrumToRgb(wavelengthsNm).linearSrgb(values).
Rgb spectrumToLinearSrgb(std::span<const double> wavelengthsNm, std::span<const double> values);

/// Zimmons & Bastos 1999's other way to make RGB from a spectrum (Zimmons & Bastos 1999 section 8): the value at one
/// wavelength per channel, R at 750 nm, G at 550 nm, B at 400 nm.
inline constexpr std::array<double, 3> kSingleWavelengthRgbNm{750.0, 550.0, 400.0};

/// Which sample stands for each of R, G, B: the nearest available wavelength (ties go to the
/// shorter one).
struct WavelengthPick {
  std::array<double, 3> requestedNm{};
  std::array<double, 3> usedNm{};
  std::array<std::size_t, 3> index{};
  /// True when some channel had to use a wavelength other than the one requested.
  bool substituted() const { return requestedNm != usedNm; }
};

/// Throws Error(InvalidArgument) for an empty grid or non-finite wavelengths.
WavelengthPick nearestWavelengths(std::span<const double> wavelengthsNm,
                                  const std::array<double, 3>& requestedNm = kSingleWavelengthRgbNm);
/// (values[pick.index[0]], values[pick.index[1]], values[pick.index[2]]).
Rgb singleWavelengthRgb(std::span<const double> values, const WavelengthPick& pick);

}  // namespace brdfbake
