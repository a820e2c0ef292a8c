#pragma once
/// @file
/// What a map stores, as a function of the map-frame direction.

#include <brdfbake/brdf/material.hpp>
#include <brdfbake/maps/image.hpp>

#include <memory>
#include <optional>
#include <vector>

namespace brdfbake {

/// A function on the sphere of directions, in the map's frame, returning linear RGB.
/// Implementations must be thread-safe and return finite values for every unit direction.
class MapFunction {
 public:
  virtual ~MapFunction() = default;
  virtual Rgb evaluate(const Vec3& direction) const = 0;
  /// If evaluate() is exactly a sum of radial lobes, those lobes: the baker then tabulates each
  /// profile once instead of evaluating the model per sample.
  virtual std::optional<std::vector<RadialLobe>> radialLobes() const { return std::nullopt; }
  /// If evaluate() is exactly a sum of microfacet lobes (one per light), those lobes, with the
  /// light colours folded into their weights: the baker then tabulates D once per light.
  virtual std::optional<std::vector<MicrofacetLobe>> microfacetLobes() const { return std::nullopt; }
  /// If evaluate(d) depends on d only through its angle to one axis, that axis (then a 1-D
  /// radial profile holds the whole map: bake/radial_profile.hpp). The default: the common axis
  /// of radialLobes(), if they share one.
  virtual std::optional<Vec3> symmetryAxis() const;
};

/// A directional light in the map's frame. `direction` points towards the light.
struct DirectionalLight {
  Vec3 direction;
  Rgb color = Rgb::Ones();
};

/// A material lit by directional lights and seen from a fixed view, as a function of the
/// reflected direction r (the map direction): n = normalize(r + v) (geometryForReflection).
/// For sphere maps the view is +z (eye space).
class MaterialMapFunction final : public MapFunction {
 public:
  /// Throws Error(InvalidArgument) for zero or non-finite directions.
  MaterialMapFunction(std::shared_ptr<const Material> material, std::vector<DirectionalLight> lights, const Vec3& view);
  Rgb evaluate(const Vec3& direction) const override;
  std::optional<std::vector<RadialLobe>> radialLobes() const override;
  std::optional<std::vector<MicrofacetLobe>> microfacetLobes() const override;
  /// The view, for unlit materials whose value depends on n.v only; else as MapFunction's.
  std::optional<Vec3> symmetryAxis() const override;

 private:
  std::shared_ptr<const Material> material_;
  std::vector<DirectionalLight> lights_;
  Vec3 view_;
};

/// A map image read back as a function: bilinear lookup (sampleBilinear) of its RGB. Used to
/// resample maps from one parameterization into another. Holds references: keep both alive.
class ImageMapFunction final : public MapFunction {
 public:
  ImageMapFunction(const Image& image, const Parameterization& map) : image_(image), map_(map) {}
  Rgb evaluate(const Vec3& direction) const override;

 private:
  const Image& image_;
  const Parameterization& map_;
};

}  // namespace brdfbake
