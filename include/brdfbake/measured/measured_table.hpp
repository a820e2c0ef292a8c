#pragma once
/// @file
/// Measured BRDF tables: scattered samples (Cornell ASTM E1392, pbrt-v2 .brdf, MATLAB .mat) as
/// MeasuredTable, and the dense MERL grid as MerlTable. Formats and conventions:
/// docs/measured_tables.md.
///
/// Frame and angles (Cornell convention, used by every format here): a local frame with z the
/// surface normal. theta is the polar angle from z, phi the azimuth from x towards y, both in
/// radians. The incident direction wi (towards the light) is (theta_i, phi_i), the outgoing
/// direction wo (towards the viewer, Cornell's "scattered", _s) is (theta_s, phi_s); both point
/// away from the surface. Cornell tables have phi_i = 0, so phi_s = pi is the mirror (specular)
/// side and phi_s = 0 the retro side. Values are BRDF in 1/sr.

#include <brdfbake/core/color.hpp>
#include <brdfbake/core/math.hpp>

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace brdfbake {

/// File formats of measured tables. `Auto` asks the reader to look at the content.
enum class TableFormat { Auto, Astm, Pbrt, Merl, Mat };

/// "auto", "astm", "pbrt", "merl", "mat".
std::string_view toString(TableFormat format);
/// Inverse of toString (any case); throws Error(InvalidArgument) listing the names for others.
TableFormat parseTableFormat(std::string_view name);

/// What the channels of a table are.
enum class ChannelKind {
  Spectral,      ///< one channel per wavelength (MeasuredTable::wavelengthsNm)
  Trichromatic,  ///< R, G, B as stored in the file (the primaries are the file's own)
  Monochrome,    ///< a single channel
};

/// How MeasuredTable::toRgb makes RGB from a spectral table.
enum class RgbMethod {
  Cie1931,            ///< CIE 1931 2-degree observer under D65 to linear sRGB (brdf/spectrum.hpp)
  SingleWavelengths,  ///< the value at the nearest wavelength to 750 / 550 / 400 nm (Zimmons & Bastos 1999 section 8)
};
std::string_view toString(RgbMethod method);
/// "cie1931" | "single_wavelengths"; throws Error(InvalidArgument) listing them.
RgbMethod parseRgbMethod(std::string_view name);

/// The angles of one sample, radians (see @file for the frame).
struct SampleAngles {
  double thetaIn = 0.0;   ///< theta_i, in [0, pi/2]
  double phiIn = 0.0;     ///< phi_i
  double thetaOut = 0.0;  ///< theta_s, in [0, pi/2]
  double phiOut = 0.0;    ///< phi_s
};

/// Unit vector of polar angle `theta` (from +z) and azimuth `phi` (from +x towards +y):
/// (sin theta cos phi, sin theta sin phi, cos theta).
Vec3 directionFromAngles(double theta, double phi);

/// Samples x channels, one row per sample.
using TableValues = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// A table of scattered BRDF samples. Only measured directions are present: samples the device
/// could not take (Cornell: around the retro direction, and one half of the hemisphere, which
/// is mirror-symmetric) are simply absent, never stored as zeros or NaN.
struct MeasuredTable {
  std::vector<SampleAngles> angles;  ///< one per sample
  TableValues values;                ///< angles.size() x channelCount(), BRDF 1/sr, finite;
                                     ///< may be negative (Cornell RGB files), kept as measured
  ChannelKind kind = ChannelKind::Spectral;
  std::vector<std::string> channelNames;   ///< as in the file ("400nm", "R", ...)
  std::vector<double> wavelengthsNm;       ///< Spectral: one per channel, strictly increasing; else empty
  std::string sourceFile;                  ///< where it was read from ("" when built in memory)
  TableFormat format = TableFormat::Astm;  ///< the format it was read from
  /// Header lines of the file in order (ASTM `KEY value`; pbrt comments as {"#", text}).
  std::vector<std::pair<std::string, std::string>> header;
  /// Facts a user should know about how the data was read or converted (one sentence each).
  std::vector<std::string> notes;

  std::size_t size() const { return angles.size(); }
  std::size_t channelCount() const { return static_cast<std::size_t>(values.cols()); }

  /// wi of sample i: directionFromAngles(thetaIn, phiIn).
  Vec3 incidentDirection(std::size_t i) const;
  /// wo of sample i: directionFromAngles(thetaOut, phiOut).
  Vec3 outgoingDirection(std::size_t i) const;

  /// The distinct theta_i of the table, ascending (radians; values closer than `tolerance` are one).
  std::vector<double> incidentThetas(double tolerance = 1e-5) const;
  /// The distinct (theta_i, phi_i) pairs, ordered by theta then phi.
  std::vector<std::pair<double, double>> incidentAngles(double tolerance = 1e-5) const;
  /// Indices of the samples whose theta_i is within `tolerance` of `thetaIn`.
  std::vector<std::size_t> samplesAtIncidentTheta(double thetaIn, double tolerance = 1e-5) const;

  /// Channel c's name as in the file, or its index written out when the table has no names for it.
  std::string channelName(std::size_t c) const;
  /// The index of a channel by name (e.g. "550nm", "G"); std::nullopt if there is no such channel.
  std::optional<std::size_t> channelIndex(std::string_view name) const;

  /// An RGB copy (kind Trichromatic, channels "R", "G", "B", no wavelengths, same samples and header).
  /// Spectral: by `method`, with a note saying which and, for SingleWavelengths, which
  /// wavelengths stood in for missing ones (Cornell data ends at 700 nm, so R uses 700 nm).
  /// Trichromatic: an unchanged copy. Monochrome: the channel copied to R, G and B.
  MeasuredTable toRgb(RgbMethod method = RgbMethod::Cie1931) const;

  /// A copy with the other half of the hemisphere added by the mirror symmetry phi_s -> -phi_s
  /// (valid for an isotropic surface with every phi_i = 0); samples in the plane of incidence
  /// (phi_s = 0 or +-pi, or theta_s = 0) are not duplicated. Throws Error(InvalidArgument) if
  /// some phi_i is not 0.
  MeasuredTable withMirroredHalf(double tolerance = 1e-5) const;

  /// What messages call the table: sourceFile, or "(table)" for a table built in memory.
  std::string label() const;
  /// Throws Error(InvalidInput) naming sourceFile if the table is inconsistent: sizes, channel
  /// names / wavelengths, non-finite values, theta outside [0, pi/2].
  void validate() const;
};

/// The MERL BRDF database's dense isotropic table (Matusik et al. 2003): 90 theta_half (sqrt
/// spaced) x 90 theta_diff x 180 phi_diff bins per channel in Rusinkiewicz half/difference
/// coordinates, looked up exactly as MERL's reference code does (nearest bin, no interpolation).
class MerlTable {
 public:
  static constexpr int kThetaHalfBins = 90;
  static constexpr int kThetaDiffBins = 90;
  static constexpr int kPhiDiffBins = 180;
  static constexpr std::size_t kBinsPerChannel =
      std::size_t(kThetaHalfBins) * kThetaDiffBins * kPhiDiffBins;  // 1 458 000
  /// MERL's per-channel factors from stored numbers to BRDF (1/sr).
  static constexpr std::array<double, 3> kChannelScale{1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

  /// `stored`: 3 * kBinsPerChannel numbers as in the file (channel-major R, G, B; within a
  /// channel index = phiDiff + kPhiDiffBins * (thetaDiff + kThetaDiffBins * thetaHalf)), before
  /// scaling; negative = not measured. Throws Error(InvalidArgument) for a wrong size or
  /// non-finite numbers.
  explicit MerlTable(std::vector<double> stored, std::string sourceFile = {});

  /// Rusinkiewicz coordinates of a pair of directions (both pointing away from the surface, local
  /// frame with z the normal; need not be normalised), computed as MERL's reference code does.
  struct HalfDiff {
    double thetaHalf, phiHalf, thetaDiff, phiDiff;
  };
  static HalfDiff halfDiffCoordinates(const Vec3& wi, const Vec3& wo);

  /// MERL's index functions: theta_half -> sqrt(theta_half / (pi/2)) * 90 (the non-linear
  /// mapping), theta_diff -> theta_diff / (pi/2) * 90, phi_diff -> phi_diff (+pi if negative,
  /// reciprocity) / pi * 180; truncated and clamped to the bin range.
  static int thetaHalfIndex(double thetaHalf);
  static int thetaDiffIndex(double thetaDiff);
  static int phiDiffIndex(double phiDiff);

  /// The BRDF (1/sr) for light from `wi` seen from `wo`; std::nullopt when either is at or below
  /// the horizon (z <= 0) or the bin was not measured (a negative stored number in any channel).
  std::optional<Rgb> evaluate(const Vec3& wi, const Vec3& wo) const;

  /// The BRDF (1/sr) stored in one bin, or std::nullopt if it was not measured.
  std::optional<Rgb> bin(int thetaHalf, int thetaDiff, int phiDiff) const;

  /// Number of bins with a negative (unmeasured) number in some channel.
  std::size_t unmeasuredBinCount() const;
  const std::string& sourceFile() const { return sourceFile_; }
  /// The numbers as stored in the file (unscaled), channel-major.
  const std::vector<double>& stored() const { return stored_; }

 private:
  std::vector<double> stored_;
  std::string sourceFile_;
};

}  // namespace brdfbake
