#pragma once
/// @file
/// 1-D radial profiles: the whole of a map whose value depends only on the angle to one axis.
///
/// A profile of N texels stores f over u = |d - axis| / 2 = sin(alpha / 2), alpha the angle between
/// the direction d and the axis, u in [0, 1]; texel i is centred at u = (i + 0.5) / N and holds the
/// solid-angle-weighted mean of f over its ring (u in [i/N, (i+1)/N]). Lookups interpolate linearly
/// in u and clamp at both ends, as a GPU's linear filter on a 1-D texture with clamp-to-edge does.
///
/// For a sphere map (axis = view = +z) u is exactly the sphere-map radius: a renderer computes the
/// GL_SPHERE_MAP coordinates (s, t) and looks the profile up at u = |(2s - 1, 2t - 1)|. The rings
/// are equal in solid angle (each N-th of u^2), so the profile's texels are as fair as the sphere
/// map's. See docs/spec.md ("parameterization": "profile").

#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/bake/map_function.hpp>
#include <brdfbake/maps/image.hpp>

#include <nlohmann/json.hpp>

#include <vector>

namespace brdfbake {

class RadialProfile {
 public:
  /// `axis` non-zero and finite (normalised here), `texels` non-empty and finite. Throws
  /// Error(InvalidArgument).
  RadialProfile(const Vec3& axis, std::vector<Rgb> texels);

  const Vec3& axis() const { return axis_; }
  int resolution() const { return static_cast<int>(texels_.size()); }
  const std::vector<Rgb>& texels() const { return texels_; }

  /// u = |d - axis| / 2 for unit d, in [0, 1].
  double coordinateFor(const Vec3& direction) const;
  /// The unit direction at coordinate u in [0, 1] and azimuth phi (radians) about the axis.
  Vec3 directionFor(double u, double phi) const;
  /// Linear interpolation in u between texel centres, clamped at the ends.
  Rgb lookup(const Vec3& direction) const;

  /// The profile as an N x 1 RGBA image (alpha 1), with metadata (toJson) to write with writeImage.
  Image toImage() const;
  /// {"parameterization": "profile", "resolution": N, "axis": [x, y, z], "coordinate": ...}.
  nlohmann::json toJson() const;

 private:
  Vec3 axis_;
  Vec3 tangent_, bitangent_;
  std::vector<Rgb> texels_;
};

/// Bakes `function` into a profile about `axis` with `resolution` texels (>= 1) and
/// `samplesPerTexel` (>= 1) stratified samples per ring, equal in solid angle, each at its own
/// azimuth (a golden-angle sequence), so a function that is not quite symmetric is averaged.
/// Runs on the context's threads; throws Error(InvalidArgument) for bad arguments.
RadialProfile bakeRadialProfile(const MapFunction& function, const Vec3& axis, int resolution, int samplesPerTexel,
                                const Context& context = {});

/// Lookup errors of a profile against the exact function, as measureMapError measures maps:
/// rms over directions uniform on the sphere, visibleRms over a visible sphere's lookups when the
/// axis is the view (+z; u uniform over the sphere-map disc, i.e. u^2 uniform), relative to the peak.
/// About the view, the rim band measureMapError skips for a sphere map of 2N texels across (the
/// same radial texel size) is skipped too: there the profile is looked up through sphere-map
/// coordinates, whose rim is singular.
ErrorStats measureProfileError(const RadialProfile& profile, const MapFunction& exact,
                               const ErrorOptions& options = {});
/// The same against probes already drawn for the function.
ErrorStats measureProfileError(const RadialProfile& profile, const ErrorProbes& probes, bool visibleSphere = true);
/// What measureProfileError reports for bakeRadialProfile(function, axis, resolution,
/// samplesPerTexel), computing only the texels the probes' lookups read (measureSparseLookups).
ErrorStats estimateProfileError(const MapFunction& function, const Vec3& axis, int resolution, int samplesPerTexel,
                                const ErrorProbes& probes, bool visibleSphere = true, const Context& context = {});

}  // namespace brdfbake
