#include <brdfbake/bake/baker.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/maps/cube_map.hpp>

#include <sstream>

namespace brdfbake {
namespace fs = std::filesystem;
namespace {

std::string sizeText(const Image& image) {
  return std::to_string(image.width()) + " x " + std::to_string(image.height());
}

// The resolution an image of this size has as a map of `kind`, or 0 if the size fits no such map.
int resolutionFor(const Image& image, ParameterizationKind kind) {
  const int w = image.width(), h = image.height();
  switch (kind) {
    case ParameterizationKind::Sphere:
      return w == h ? w : 0;
    case ParameterizationKind::Paraboloid:
    case ParameterizationKind::LatLong:
      return w == 2 * h ? h : 0;
    case ParameterizationKind::Cube:
      return 3 * w == 4 * h && w % 4 == 0 ? w / 4 : 0;
  }
  return 0;
}

std::string expectedShape(ParameterizationKind kind) {
  switch (kind) {
    case ParameterizationKind::Sphere:
      return "square (N x N)";
    case ParameterizationKind::Paraboloid:
      return "2:1 (2N x N, front hemisphere left)";
    case ParameterizationKind::LatLong:
      return "2:1 (2N x N)";
    case ParameterizationKind::Cube:
      return "4:3 (a 4N x 3N horizontal cross)";
  }
  return "";
}

}  // namespace

Rgb Environment::radiance(const Vec3& direction) const { return sampleBilinear(image, *map, direction).head<3>(); }

Environment makeEnvironment(Image image, ParameterizationKind kind, const std::string& source) {
  const int resolution = resolutionFor(image, kind);
  if (resolution == 0) {
    throw Error(Error::Kind::InvalidInput, source + ": a " + sizeText(image) + " image is not a " +
                                               std::string(toString(kind)) + " environment, which must be " +
                                               expectedShape(kind));
  }
  if (resolution < 2) {
    throw Error(Error::Kind::InvalidInput, source + ": a " + sizeText(image) + " image is too small for a " +
                                               std::string(toString(kind)) +
                                               " environment (at least 2 texels per side of each face or row count)");
  }
  requireFinite(image, source);
  MapFile adopted = adoptImage(std::move(image), kind, source);
  Environment environment;
  environment.image = std::move(adopted.image);
  environment.map = std::shared_ptr<const Parameterization>(std::move(adopted.parameterization));
  environment.source = source;
  return environment;
}

Environment loadEnvironment(const fs::path& path, const EnvironmentLoadOptions& options) {
  Image image;
  std::string detection;
  if (const auto faces = cubeFaceSet(path); !faces.empty()) {
    if (options.kind && *options.kind != ParameterizationKind::Cube) {
      throw Error(Error::Kind::InvalidArgument, path.string() + ": six face files make a cube, not a " +
                                                    std::string(toString(*options.kind)) + " map");
    }
    Environment environment = makeEnvironment(assembleCubeCross(faces), ParameterizationKind::Cube, path.string());
    environment.detection = "six cube faces";
    return environment;
  }
  if (!fs::exists(path)) {
    throw Error(Error::Kind::Io, path.string() + ": no such file (nor six cube faces " +
                                     cubeFacePaths(path)[0].filename().string() + " ...)");
  }
  image = readImage(path);
  if (image.width() < 2 || image.height() < 2) {
    throw Error(Error::Kind::InvalidInput,
                path.string() + ": a " + sizeText(image) +
                    " image is too small for an environment (lat-long needs at least 4 x 2)");
  }
  std::optional<ParameterizationKind> kind;
  if (image.metadata.is_object() && image.metadata.contains("parameterization")) {
    const MapInfo info = MapInfo::fromJson(image.metadata);
    if (options.kind && *options.kind != info.parameterization) {
      throw Error(Error::Kind::InvalidArgument, path.string() + ": its metadata says it is a " +
                                                    std::string(toString(info.parameterization)) + " map, not " +
                                                    std::string(toString(*options.kind)));
    }
    kind = info.parameterization;
    detection = "file metadata";
  } else if (options.kind) {
    kind = options.kind;
    detection = "given (--from)";
  } else if (image.width() == 2 * image.height()) {
    kind = ParameterizationKind::LatLong;
    detection = "aspect ratio 2:1 (lat-long)";
  } else if (3 * image.width() == 4 * image.height()) {
    kind = ParameterizationKind::Cube;
    detection = "aspect ratio 4:3 (cube cross)";
  } else {
    throw Error(Error::Kind::InvalidInput,
                path.string() + ": cannot tell the parameterization of a " + sizeText(image) +
                    " image without metadata: 2:1 is read as lat-long and 4:3 as a cube cross; for sphere or "
                    "paraboloid maps (or to override) pass the parameterization (--from)");
  }
  Environment environment = makeEnvironment(std::move(image), *kind, path.string());
  environment.detection = detection;
  return environment;
}

Environment bakeEnvironment(const MapFunction& radiance, ParameterizationKind kind, int resolution,
                            const std::string& source, int samplesPerTexel, const Context& context) {
  const auto map = makeParameterization(kind, resolution);
  BakeOptions options;
  options.samplesPerTexel = samplesPerTexel;
  Image image = bake(*map, radiance, options, context);
  // Unused cells of a cube cross hold 0 (bake leaves them so); alpha is coverage.
  Environment environment;
  environment.image = std::move(image);
  environment.map = std::shared_ptr<const Parameterization>(makeParameterization(kind, resolution));
  environment.source = source;
  environment.detection = "generated";
  return environment;
}

SkyEnvironment::SkyEnvironment(const SkyParameters& parameters) : parameters_(parameters) {
  require(parameters.sunDirection.allFinite() && parameters.sunDirection.norm() > 0.0,
          "sky: sun direction must be non-zero");
  require(parameters.sunAngularRadius > 0.0 && parameters.sunAngularRadius < 0.5,
          "sky: sun radius must be in (0, 0.5) rad");
  parameters_.sunDirection.normalize();
}

Rgb SkyEnvironment::skyOnly(const Vec3& d) const {
  if (d.y() < 0.0) return Rgb(0.25, 0.22, 0.18);  // ground
  const Rgb zenith(0.12, 0.25, 0.6), horizon(0.85, 0.9, 1.0);
  const double t = std::sqrt(std::clamp(d.y(), 0.0, 1.0));
  const double gamma = std::acos(std::clamp(d.dot(parameters_.sunDirection), -1.0, 1.0));
  const double aureole = 1.5 * std::exp(-(gamma * gamma) / (2.0 * 0.15 * 0.15));
  return horizon + (zenith - horizon) * t + aureole * Rgb(1.0, 0.95, 0.8);
}

Rgb SkyEnvironment::evaluate(const Vec3& d) const {
  Rgb value = skyOnly(d);
  if (d.dot(parameters_.sunDirection) >= std::cos(parameters_.sunAngularRadius)) value += parameters_.sunRadiance;
  return value;
}

Rgb ColoredCubeEnvironment::evaluate(const Vec3& d) const {
  const auto [face, st] = CubeMap::faceCoordinates(d.normalized());
  static const Rgb colors[6] = {Rgb(1, 0, 0), Rgb(0, 1, 1), Rgb(0, 1, 0), Rgb(1, 0, 1), Rgb(0, 0, 1), Rgb(1, 1, 0)};
  return colors[face];
}

}  // namespace brdfbake
