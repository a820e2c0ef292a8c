#pragma once
/// @file
/// Zimmons & Bastos 1999's measured reflectance map (Zimmons & Bastos 1999 section 8): for each incident angle the BRDF in
/// the mirror direction, as a profile over theta, baked as a radially symmetric sphere map. Two
/// ways to get the mirror value (docs/fitting.md, "The mirror-direction profile"):
///
/// - `strongestNearMirrorProfile`, Zimmons & Bastos 1999's: for each incident angle and channel, the strongest
///   sample within `window` of the exact mirror direction (Zimmons & Bastos 1999 "pieced together the strongest
///   reflected energy for each wavelength", assuming it lies in the mirror direction). Cornell
///   tables have no sample on the mirror direction (the nearest is 0.2 to 3.7 degrees off), so
///   for a sharp highlight this can be far from the mirror value, and a wide window picks
///   off-specular peaks.
/// - `fittedMirrorProfile`: fitted lobes evaluated exactly on the mirror direction
///   (LobeModel::mirrorValue).
///
/// Between profile angles the value is interpolated linearly in theta, and held at the first and
/// last angle's value beyond them (Cornell: 10 and 80 degrees).

#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/brdf/material.hpp>
#include <brdfbake/measured/measured_table.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace brdfbake {

/// A per-channel profile of the mirror-direction BRDF (1/sr) over the incident angle theta.
struct MirrorProfile {
  std::vector<double> thetas;               ///< radians, strictly increasing
  Eigen::MatrixXd values;                   ///< thetas.size() x channels, 1/sr
  /// Angle (radians) between the sample used and the exact mirror direction, per theta and
  /// channel (0 for fitted profiles).
  Eigen::MatrixXd offsets;
  std::vector<std::string> channelNames;
  std::vector<double> wavelengthsNm;        ///< spectral profiles; else empty

  std::size_t channelCount() const { return static_cast<std::size_t>(values.cols()); }
  /// The profile at `theta` (radians), interpolated as in @file.
  Eigen::VectorXd at(double theta) const;
  /// Throws Error(InvalidArgument) for empty or inconsistent profiles or non-finite values.
  void validate() const;
};

/// Zimmons & Bastos 1999's profile (see @file). `windowRadians` in (0, pi]: pi takes the strongest sample of
/// the whole incident angle, as Zimmons & Bastos 1999 did literally. Incident angles with no sample in the
/// window use the nearest sample to the mirror direction. Throws Error(InvalidInput) for an empty
/// table, Error(InvalidArgument) for a bad window.
MirrorProfile strongestNearMirrorProfile(const MeasuredTable& table, double windowRadians = 10.0 * kPi / 180.0);

/// The fitted model on the exact mirror direction at the given incident angles (radians).
MirrorProfile fittedMirrorProfile(const LobeModel& model, const std::vector<double>& thetas);

/// A reflectance-map material from an RGB profile (channels R, G, B): no lights; unlit(g) is the
/// profile at theta = the angle between the normal and the view, i.e. the BRDF for light arriving
/// from the view direction mirrored about the normal (like cook_torrance's reflectance mode).
class MirrorProfileMaterial final : public Material {
 public:
  /// Throws Error(InvalidArgument) unless the profile validates and has 3 channels.
  explicit MirrorProfileMaterial(MirrorProfile profile, std::string modelName = "measured");
  std::string_view model() const override { return modelName_; }
  Rgb shade(const ShadingGeometry&, const Vec3&) const override { return Rgb::Zero(); }
  Rgb unlit(const ShadingGeometry& g) const override;
  bool usesLights() const override { return false; }
  bool viewIndependent() const override { return false; }
  const MirrorProfile& profile() const { return profile_; }

 private:
  MirrorProfile profile_;
  std::string modelName_;
};

}  // namespace brdfbake
