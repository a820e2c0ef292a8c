#pragma once
/// @file
/// The material interface the baker evaluates. All vectors are unit vectors pointing away from
/// the surface, in whatever frame the map uses.

#include <brdfbake/brdf/reflection_lobe.hpp>
#include <brdfbake/core/color.hpp>
#include <brdfbake/core/math.hpp>

#include <functional>
#include <optional>
#include <string_view>
#include <vector>

namespace brdfbake {

/// The geometry at one shading point.
struct ShadingGeometry {
  Vec3 normal;     ///< surface normal n
  Vec3 view;       ///< towards the viewer, v
  Vec3 reflected;  ///< v mirrored about n: 2 (n.v) n - v
};

/// Builds the geometry for a map texel that stands for reflected direction `reflected` seen from
/// `view`: n = normalize(r + v). Where r = -v (the sphere map's rim) n is any unit vector
/// perpendicular to v (grazing); the choice is deterministic.
ShadingGeometry geometryForReflection(const Vec3& reflected, const Vec3& view);

/// A term radially symmetric about an axis: value(d) = weight * profile(dot(d, axis)), with d the
/// map direction (the reflected vector). Profiles take the cosine of the angle to the axis, in
/// [-1, 1], and must be finite there.
struct RadialLobe {
  Vec3 axis;
  Rgb weight;
  std::function<double(double)> profile;
};

/// A Cook-Torrance microfacet term for one light and view, as a function of the reflected
/// direction r through the normal n = normalize(r + v) (geometryForReflection), with the half
/// vector h = normalize(l + v) fixed, hence v.h and F(v.h) constant (Cook & Torrance 1981):
///   value(r) = specular * D(n.h) * cookTorranceGOverNlNv(n.h, n.v, n.l, v.h) * n.l
///            + diffuse * n.l          where n.l > 0 and n.h > 0, else 0.
/// `distribution` takes n.h in [-1, 1] and must be finite there; only n.h > 0 is used (a
/// material may continue D smoothly past 0 so a table of it stays small).
struct MicrofacetLobe {
  Vec3 light;                ///< l, towards the light
  Vec3 view;                 ///< v, towards the viewer
  Vec3 halfVector;           ///< h = normalize(l + v)
  double viewDotHalf = 1.0;  ///< v.h > 0
  Rgb specular;              ///< light colour * s F(v.h) / denominator
  Rgb diffuse;               ///< light colour * (1 - s) rho_d / pi
  std::function<double(double)> distribution;
};

/// A reflectance model as the baker sees it.
class Material {
 public:
  virtual ~Material() = default;
  /// The spec's model name, e.g. "phong".
  virtual std::string_view model() const = 0;
  /// False if the model ignores lights (reflectance and hand-designed maps: then a spec omits them
  /// and shade() is 0). Materials that use lights override shade().
  virtual bool usesLights() const { return false; }
  /// Radiance towards the viewer from one directional light of unit colour arriving from unit
  /// direction `light` (irradiance at normal incidence = 1, OpenGL-style lighting). 0 for a material
  /// that ignores lights.
  virtual Rgb shade(const ShadingGeometry&, const Vec3& /*light*/) const { return Rgb::Zero(); }
  /// The part of the map that does not depend on lights (reflectance and hand-designed maps).
  virtual Rgb unlit(const ShadingGeometry&) const { return Rgb::Zero(); }
  /// True if the value depends on the geometry only through the reflected direction, so a map
  /// indexed by reflected direction is valid for every view.
  virtual bool viewIndependent() const = 0;
  /// True if unlit(g) depends on g only through n.v (so a map of it is radially symmetric about the
  /// view, and its 1-D profile is enough: bake/radial_profile.hpp).
  virtual bool unlitSymmetricAboutView() const { return false; }
  /// If shade(g, light) is exactly a sum of radial lobes about fixed axes as a function of the
  /// reflected direction (for this light and view), those lobes; otherwise nullopt.
  virtual std::optional<std::vector<RadialLobe>> radialLobes(const Vec3& light, const Vec3& view) const {
    return std::nullopt;
  }
  /// If unlit(g) is exactly a sum of radial lobes about fixed axes as a function of the reflected
  /// direction (for this view), those lobes; otherwise nullopt.
  virtual std::optional<std::vector<RadialLobe>> unlitRadialLobes(const Vec3& view) const { return std::nullopt; }
  /// If unlit(g) is zero and shade(g, light) is exactly one MicrofacetLobe for this light and
  /// view, that lobe (with unit light colour); otherwise nullopt.
  virtual std::optional<MicrofacetLobe> microfacetLobe(const Vec3& light, const Vec3& view) const {
    return std::nullopt;
  }
  /// The light colour that stands for unit irradiance at normal incidence (docs/conventions.md,
  /// "Radiometric units"): 1 where a light's colour is its irradiance (Cook-Torrance, fitted and
  /// measured models), 1/pi for Phong and Blinn-Phong, whose light colour is the radiance a white
  /// Lambertian surface facing the light reflects. Under an environment a texel of radiance L and
  /// solid angle dω acts as a light of colour L dω times this.
  virtual double lightColorPerIrradiance() const { return 1.0; }
  /// If lightColorPerIrradiance() shade(g, l) is the model's BRDF times the cosine, f_r(l, v)
  /// max(0, n.l), for every light direction l (Phong's specular lobe is not clipped at the horizon,
  /// as in its lighting), the BRDF's parts as functions of l for this geometry
  /// (reflection_lobe.hpp), for integrators over incident directions; nullopt when the model has
  /// no BRDF (hand-designed maps, reflectance and prefiltered modes).
  virtual std::optional<std::vector<ReflectionLobe>> reflectionLobes(const ShadingGeometry&) const {
    return std::nullopt;
  }
};

/// Rec. 709 luminance of a linear RGB colour (weights of reflection lobes).
inline double luminance(const Rgb& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

}  // namespace brdfbake
