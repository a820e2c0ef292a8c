#pragma once
/// @file
/// Phong and Blinn-Phong lobes and materials (Zimmons & Bastos 1999 section 5).

#include <brdfbake/brdf/blinn_conversion.hpp>
#include <brdfbake/brdf/material.hpp>

namespace brdfbake {

/// max(0, c)^n, with 0^0 = 1 for c > 0 only (a lobe of exponent 0 is the hemisphere c > 0).
template <class T>
T phongLobe(const T& cosAngle, const T& exponent) {
  using std::pow;
  return cosAngle > T(0) ? T(pow(cosAngle, exponent)) : T(0);
}

/// Normalisation (n + 2) / (2 pi) that makes the Phong lobe, weighted by cos of the angle to its
/// axis, integrate to 1 over the hemisphere about the axis.
template <class T>
T phongNormalization(const T& exponent) {
  return (exponent + T(2)) / T(2.0 * std::numbers::pi);
}

/// Phong: k_d max(0, n.l) + k_s max(0, r.l)^n, with r the reflected view vector (Zimmons & Bastos 1999
/// Eq. 5; in a sphere map the value at reflected direction r for light l is max(0, r.l)^n).
/// The specular lobe is a function of r alone, so it is radially symmetric about l and valid
/// for every view; the diffuse term needs the normal, hence the view, unless the light is at the
/// eye. Lights below the horizon (n.l <= 0) light no diffuse; the specular lobe is not clipped at
/// the horizon (it is the lobe a prefiltered Phong map uses).
class PhongMaterial final : public Material {
 public:
  /// Throws Error(InvalidArgument) for negative colours or exponent, or non-finite values.
  PhongMaterial(const Rgb& specular, double exponent, const Rgb& diffuse = Rgb::Zero());
  std::string_view model() const override { return "phong"; }
  bool usesLights() const override { return true; }
  Rgb shade(const ShadingGeometry& g, const Vec3& light) const override;
  bool viewIndependent() const override { return (diffuse_ == 0.0).all(); }
  std::optional<std::vector<RadialLobe>> radialLobes(const Vec3& light, const Vec3& view) const override;
  /// 1/pi: a light's colour is the radiance a white Lambertian facing it reflects.
  double lightColorPerIrradiance() const override { return 1.0 / kPi; }
  /// The specular lobe max(0, r.l)^n about r and the diffuse max(0, n.l).
  std::optional<std::vector<ReflectionLobe>> reflectionLobes(const ShadingGeometry& g) const override;

 private:
  Rgb specular_, diffuse_;
  double exponent_;
};

/// Blinn-Phong: k_d max(0, n.l) + k_s (n.h)^n', h = normalize(l + v), lit only where n.l > 0.
/// The exponent is either given, or derived from a Phong exponent by a conversion policy
/// (BlinnConversion); the `Exact` policy evaluates (n.h)^(n ratio(n.h)) per texel.
class BlinnPhongMaterial final : public Material {
 public:
  /// Blinn-Phong with a given exponent n'.
  BlinnPhongMaterial(const Rgb& specular, double exponent, const Rgb& diffuse = Rgb::Zero());
  /// Blinn-Phong meant to match Phong of exponent `phongExponent` under `policy`.
  BlinnPhongMaterial(const Rgb& specular, double phongExponent, BlinnConversion policy,
                     const Rgb& diffuse = Rgb::Zero());
  std::string_view model() const override { return "blinn_phong"; }
  bool usesLights() const override { return true; }
  Rgb shade(const ShadingGeometry& g, const Vec3& light) const override;
  bool viewIndependent() const override { return false; }
  std::optional<std::vector<RadialLobe>> radialLobes(const Vec3& light, const Vec3& view) const override;
  /// 1/pi, as Phong's.
  double lightColorPerIrradiance() const override { return 1.0 / kPi; }
  /// The N.H lobe (Blinn-Phong shape; the exact conversion as about 4 n) and the diffuse max(0, n.l).
  std::optional<std::vector<ReflectionLobe>> reflectionLobes(const ShadingGeometry& g) const override;

  /// The lobe as a function of n.h: x^n' for a constant exponent, or the exact conversion.
  double lobe(double nDotH) const;
  /// The constant exponent in use (for `Exact`: the Phong exponent it converts per texel).
  double exponent() const { return exponent_; }

 private:
  Rgb specular_, diffuse_;
  double exponent_;
  bool exact_ = false;
};

}  // namespace brdfbake
