#pragma once
/// @file
/// Environments: incoming radiance L(l) stored as an image in one of the four parameterizations,
/// read from EXR/HDR files or generated (furnace, sky with sun, coloured cube) for tests.

#include <brdfbake/bake/map_function.hpp>
#include <brdfbake/core/context.hpp>
#include <brdfbake/maps/image.hpp>
#include <brdfbake/maps/parameterization.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace brdfbake {

namespace detail {
struct EnvironmentCache;  // env/environment_cache.hpp
}

/// What computations prepare from an environment's radiance (the bright texels and the mip pyramid
/// of the rest that shading under it reads), made on first use and kept with the environment, so
/// that many materials are shaded under one environment without repeating that work. Safe to use
/// from several threads. A copy of an Environment starts with nothing prepared (its image may
/// change); a move keeps what was prepared. Change an environment's image only before using it.
class EnvironmentPreparation {
 public:
  EnvironmentPreparation();
  ~EnvironmentPreparation();
  EnvironmentPreparation(const EnvironmentPreparation&);
  EnvironmentPreparation& operator=(const EnvironmentPreparation&);
  EnvironmentPreparation(EnvironmentPreparation&&) noexcept;
  EnvironmentPreparation& operator=(EnvironmentPreparation&&) noexcept;
  /// The cache (private to env/).
  detail::EnvironmentCache& cache() const { return *cache_; }

 private:
  std::unique_ptr<detail::EnvironmentCache> cache_;
};

/// Radiance over the sphere of directions, in the environment's own frame (y up; for lat-long
/// images the image centre looks down -z, docs/conventions.md). Alpha is ignored.
struct Environment {
  Image image;
  std::shared_ptr<const Parameterization> map;
  std::string source;     ///< file name or generator, recorded in prefiltered maps
  std::string detection;  ///< how the parameterization was decided (for reports)
  /// What shading under it has prepared (see EnvironmentPreparation).
  EnvironmentPreparation prepared;

  ParameterizationKind kind() const { return map->kind(); }
  /// Bilinear lookup of the RGB radiance at a unit direction.
  Rgb radiance(const Vec3& direction) const;
};

struct EnvironmentLoadOptions {
  /// The parameterization of a plain image (`--from`). Default: from the file's brdfbake metadata
  /// if present, else the aspect ratio (2:1 lat-long, 4:3 cube cross). Paraboloid (2:1) and
  /// sphere (1:1) images need metadata or this option.
  std::optional<ParameterizationKind> kind;
};

/// Reads an environment (any format readImage reads; EXR and HDR are the usual). A cube given as
/// six files STEM_posx.EXT ... STEM_negz.EXT (cubeFacePaths) is read when PATH itself does not
/// exist and all six do. Throws Error(Io) for unreadable files, Error(InvalidInput) for images
/// whose size fits no parameterization (naming the sizes accepted), images under 2 texels per
/// side of the parameterization's resolution, and NaN or infinite texels (naming the texel), and
/// Error(InvalidArgument) when `kind` contradicts the file's metadata.
Environment loadEnvironment(const std::filesystem::path& path, const EnvironmentLoadOptions& options = {});

/// Wraps an image as an environment of the given parameterization, with the checks of
/// loadEnvironment. `source` names it in messages and metadata.
Environment makeEnvironment(Image image, ParameterizationKind kind, const std::string& source);

/// Bakes an analytic environment into an image (footprint supersampling, `samplesPerTexel`).
Environment bakeEnvironment(const MapFunction& radiance, ParameterizationKind kind, int resolution,
                            const std::string& source, int samplesPerTexel = 16, const Context& context = {});

/// The furnace: the same radiance in every direction.
class ConstantEnvironment final : public MapFunction {
 public:
  explicit ConstantEnvironment(const Rgb& radiance = Rgb::Ones()) : radiance_(radiance) {}
  Rgb evaluate(const Vec3&) const override { return radiance_; }

 private:
  Rgb radiance_;
};

/// A clear sky: blue zenith fading to a bright horizon (radiance about 0.3 to 1), an aureole
/// around the sun, a dim uniform ground below the horizon (0.25), and the sun, a uniform disc.
struct SkyParameters {
  Vec3 sunDirection = Vec3(0.5, 0.6, -0.62).normalized();  ///< towards the sun (elevation ~37 degrees)
  double sunAngularRadius = 1.5 * kPi / 180.0;             ///< radians
  Rgb sunRadiance = Rgb(2000.0, 1900.0, 1700.0);           ///< ~4.3 of irradiance at normal incidence
};
class SkyEnvironment final : public MapFunction {
 public:
  explicit SkyEnvironment(const SkyParameters& parameters = {});
  Rgb evaluate(const Vec3& direction) const override;
  /// The sky without the sun disc (smooth), and the sun disc alone.
  Rgb skyOnly(const Vec3& direction) const;
  const SkyParameters& parameters() const { return parameters_; }

 private:
  SkyParameters parameters_;
};

/// The inside of a cube with one colour per face (Heidrich 2000 Fig. 1): +x red, -x cyan, +y green,
/// -y magenta, +z blue, -z yellow, radiance 1 in each primary.
class ColoredCubeEnvironment final : public MapFunction {
 public:
  Rgb evaluate(const Vec3& direction) const override;
};

}  // namespace brdfbake
