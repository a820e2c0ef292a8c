#pragma once
/// @file
/// Zimmons & Bastos 1999's measured reflectance map (Zimmons & Bastos 1999 section 8): for each incident angle the BRDF
/// in the mirror direction, as a table over theta, baked as a radially symmetric sphere map. Two ways to get the mirror
/// value (docs/fitting.md, "The mirror-direction table"):
///
/// - `strongestNearMirrorTable`, Zimmons & Bastos 1999's: for each incident angle and channel, the strongest
///   sample within `window` of the exact mirror direction (Zimmons & Bastos 1999 "pieced together the strongest
///   reflected energy for each wavelength", assuming it lies in the mirror direction). Cornell
///   tables have no sample on the mirror direction (the nearest is 0.2 to 3.7 degrees off), so
///   for a sharp highlight this can be far from the mirror value, and a wide window picks
///   off-specular peaks.
/// - `fittedMirrorTable`: fitted lobes evaluated exactly on the mirror direction
///   (LobeModel::mirrorValue).
///
/// Between the table's angles the value is interpolated linearly in theta, and held at the first and
/// last angle's value beyond them (Cornell: 10 and 80 degrees).

#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/brdf/material.hpp>
#include <brdfbake/measured/measured_table.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace brdfbake {

/// A per-channel table of the mirror-direction BRDF (1/sr) over the incident angle theta.
struct MirrorDirectionTable {
  std::vector<double> thetas;  ///< radians, strictly increasing
  Eigen::MatrixXd values;      ///< thetas.size() x channels, 1/sr
  /// Angle (radians) between the sample used and the exact mirror direction, per theta and
  /// channel (0 for fitted tables).
  Eigen::MatrixXd offsets;
  std::vector<std::string> channelNames;
  std::vector<double> wavelengthsNm;  ///< spectral tables; else empty

  std::size_t channelCount() const { return static_cast<std::size_t>(values.cols()); }
  /// The table at `theta` (radians), interpolated as in @file.
  Eigen::VectorXd at(double theta) const;
  /// Throws Error(InvalidArgument) for empty or inconsistent tables or non-finite values.
  void validate() const;
};

/// Zimmons & Bastos 1999's table (see @file). `windowRadians` in (0, pi]: pi takes the strongest sample of
/// the whole incident angle, as Zimmons & Bastos 1999 did literally. Incident angles with no sample in the
/// window use the nearest sample to the mirror direction. Throws Error(InvalidInput) for an empty
/// table, Error(InvalidArgument) for a bad window.
MirrorDirectionTable strongestNearMirrorTable(const MeasuredTable& table, double windowRadians = 10.0 * kPi / 180.0);

/// The fitted model on the exact mirror direction at the given incident angles (radians).
MirrorDirectionTable fittedMirrorTable(const LobeModel& model, const std::vector<double>& thetas);

/// A reflectance-map material from an RGB table (channels R, G, B): no lights; unlit(g) is the
/// table at theta = the angle between the normal and the view, i.e. the BRDF for light arriving
/// from the view direction mirrored about the normal (like cook_torrance's reflectance mode).
class MirrorDirectionMaterial final : public Material {
 public:
  /// Throws Error(InvalidArgument) unless the table validates and has 3 channels.
  explicit MirrorDirectionMaterial(MirrorDirectionTable table, std::string modelName = "measured");
  std::string_view model() const override { return modelName_; }
  Rgb unlit(const ShadingGeometry& g) const override;
  bool viewIndependent() const override { return false; }
  const MirrorDirectionTable& table() const { return table_; }

 private:
  MirrorDirectionTable table_;
  std::string modelName_;
};

}  // namespace brdfbake
