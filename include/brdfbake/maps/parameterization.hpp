#pragma once
/// @file
/// Direction <-> texture mappings ("parameterizations") of environment maps.
///
/// Conventions (docs/conventions.md, pinned by tests/bake/test_conventions.cpp):
/// - Positions in an image are continuous *pixel coordinates* (x right, y down, in texels); texel
///   (i, j) covers [i, i+1) x [j, j+1) and its centre is (i + 0.5, j + 0.5). Row 0 is the top row.
/// - Directions are unit vectors in the map's own frame. A sphere map's frame is eye space: the
///   viewer looks down -z, so the view vector towards the viewer is +z, and y is up.
/// - Texture coordinates (s, t) follow each map's classic definition (GL_SPHERE_MAP, Heidrich's
///   paraboloid, the OpenGL cube-face table); the pixel-coordinate conversion per map is stated
///   on each class.

#include <brdfbake/core/math.hpp>

#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace brdfbake {

enum class ParameterizationKind { Sphere, Paraboloid, Cube, LatLong };

/// "sphere", "paraboloid", "cube", "latlong".
std::string_view toString(ParameterizationKind kind);
/// Inverse of toString; throws Error(InvalidArgument) naming the accepted values.
ParameterizationKind parseParameterizationKind(std::string_view name);

/// A rectangle of texels: the part of the image one region (hemisphere, cube face) occupies.
struct TexelRect {
  int x0 = 0, y0 = 0, width = 0, height = 0;
  bool contains(int x, int y) const { return x >= x0 && y >= y0 && x < x0 + width && y < y0 + height; }
};

/// Where a direction lands in the image.
struct MapAddress {
  Vec2 pixel;      ///< continuous pixel coordinates
  int region = 0;  ///< which region (hemisphere, face) the direction belongs to
};

/// A direction mapping over an image of width() x height() texels. Implementations are immutable
/// and thread-safe.
class Parameterization {
 public:
  explicit Parameterization(int resolution);
  virtual ~Parameterization() = default;

  virtual ParameterizationKind kind() const = 0;
  /// The resolution the map was made with: per side (sphere), per hemisphere (paraboloid),
  /// per face (cube), rows (lat-long).
  int resolution() const { return resolution_; }
  virtual int width() const = 0;
  virtual int height() const = 0;

  /// Forward: unit direction -> image position. Total: never NaN for finite non-zero input
  /// (throws Error(InvalidArgument) for zero or non-finite input).
  virtual MapAddress getAddressFor(const Vec3& direction) const = 0;
  /// Inverse: image position -> unit direction, or nullopt where the image holds no direction
  /// (unused cells of the cube cross). Maps whose domain is a disc extend it as documented
  /// per class.
  virtual std::optional<Vec3> getDirectionFor(const Vec2& pixel) const = 0;

  /// Batch inverse for one row of positions at height `py`: writes the direction of
  /// (px[i], py) to (x[i], y[i], z[i]) and valid[i] = 0 where there is none. The default calls
  /// getDirectionFor; maps override it with a tight loop (the baker's hot path).
  virtual void getDirectionsForRow(double py, const double* px, int count, double* x, double* y, double* z,
                                   unsigned char* valid) const;

  /// Number of regions and the texels each occupies. Bilinear lookups clamp to a region.
  virtual int regionCount() const { return 1; }
  virtual TexelRect region(int index) const { return {0, 0, width(), height()}; }
  /// True if bilinear lookups wrap around horizontally (lat-long).
  virtual bool wrapsHorizontally() const { return false; }

  /// Fraction of texel (x, y) inside the valid domain, in [0, 1] (stored as the map's alpha).
  virtual double texelCoverage(int x, int y) const = 0;
  /// texelCoverage(x, y) of every texel of row y into coverage[0, width()). The default calls
  /// texelCoverage; maps override it with a tight loop (the baker writes it per row).
  virtual void texelCoverageRow(int y, double* coverage) const;
  /// Exact solid angle (sr) of the part of texel (x, y) inside the valid domain.
  virtual double texelSolidAngle(int x, int y) const = 0;

  /// Solid angle per unit pixel area at a position, |d(dir)/dx x d(dir)/dy|, by central
  /// differences of getDirectionFor (an independent check of texelSolidAngle).
  double solidAngleDensity(const Vec2& pixel) const;
  /// Ratio of the larger to the smaller singular value of the Jacobian of getDirectionFor
  /// (1 = conformal; grows where texels are stretched).
  double anisotropy(const Vec2& pixel) const;

 protected:
  /// Unit direction from a finite non-zero vector, or Error(InvalidArgument).
  static Vec3 checkedUnit(const Vec3& direction);
  /// 1 / resolution(), kept so the per-sample mappings multiply instead of divide.
  double inverseResolution() const { return inverseResolution_; }

 private:
  int resolution_;
  double inverseResolution_;
};

/// Makes a parameterization. Throws Error(InvalidArgument) for resolution < 1.
std::unique_ptr<Parameterization> makeParameterization(ParameterizationKind kind, int resolution);

}  // namespace brdfbake
