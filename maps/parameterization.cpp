#include <brdfbake/core/error.hpp>
#include <brdfbake/core/named_values.hpp>
#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/maps/latlong_map.hpp>
#include <brdfbake/maps/paraboloid_map.hpp>
#include <brdfbake/maps/parameterization.hpp>
#include <brdfbake/maps/sphere_map.hpp>

#include <Eigen/Eigenvalues>

namespace brdfbake {

std::string_view toString(ParameterizationKind kind) {
  switch (kind) {
    case ParameterizationKind::Sphere:
      return "sphere";
    case ParameterizationKind::Paraboloid:
      return "paraboloid";
    case ParameterizationKind::Cube:
      return "cube";
    case ParameterizationKind::LatLong:
      return "latlong";
  }
  return "unknown";
}

ParameterizationKind parseParameterizationKind(std::string_view name) {
  return parseByName(name,
                     std::array{ParameterizationKind::Sphere, ParameterizationKind::Paraboloid,
                                ParameterizationKind::Cube, ParameterizationKind::LatLong},
                     "parameterization");
}

Parameterization::Parameterization(int resolution) : resolution_(resolution), inverseResolution_(1.0 / resolution) {
  require(resolution >= 1, "resolution must be >= 1, got " + std::to_string(resolution));
}

Vec3 Parameterization::checkedUnit(const Vec3& direction) {
  // Scale first, so huge or tiny finite vectors normalise without overflow or underflow.
  const double largest = direction.cwiseAbs().maxCoeff();
  if (!(largest > 0.0) || !std::isfinite(largest)) {
    throw Error(Error::Kind::InvalidArgument, "direction must be finite and non-zero");
  }
  return (direction / largest).normalized();
}

void Parameterization::texelCoverageRow(int y, double* coverage) const {
  for (int x = 0; x < width(); ++x) coverage[x] = texelCoverage(x, y);
}

void Parameterization::getDirectionsForRow(double py, const double* px, int count, double* x, double* y, double* z,
                                           unsigned char* valid) const {
  for (int i = 0; i < count; ++i) {
    const auto d = getDirectionFor(Vec2(px[i], py));
    valid[i] = d.has_value();
    const Vec3 v = d.value_or(Vec3::Zero());
    x[i] = v.x(), y[i] = v.y(), z[i] = v.z();
  }
}

namespace {
// Central-difference Jacobian columns of the inverse mapping, in directions per pixel.
std::optional<std::pair<Vec3, Vec3>> jacobian(const Parameterization& map, const Vec2& pixel) {
  constexpr double h = 1e-4;
  const auto xp = map.getDirectionFor(pixel + Vec2(h, 0)), xm = map.getDirectionFor(pixel - Vec2(h, 0));
  const auto yp = map.getDirectionFor(pixel + Vec2(0, h)), ym = map.getDirectionFor(pixel - Vec2(0, h));
  if (!xp || !xm || !yp || !ym) return std::nullopt;
  return std::pair<Vec3, Vec3>((*xp - *xm) / (2 * h), (*yp - *ym) / (2 * h));
}
}  // namespace

double Parameterization::solidAngleDensity(const Vec2& pixel) const {
  const auto j = jacobian(*this, pixel);
  return j ? j->first.cross(j->second).norm() : 0.0;
}

double Parameterization::anisotropy(const Vec2& pixel) const {
  const auto j = jacobian(*this, pixel);
  if (!j) return 1.0;
  Eigen::Matrix2d gram;
  gram << j->first.squaredNorm(), j->first.dot(j->second), j->first.dot(j->second), j->second.squaredNorm();
  const Eigen::Vector2d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(gram).eigenvalues();
  if (!(ev(0) > 0.0)) return std::numeric_limits<double>::infinity();
  return std::sqrt(ev(1) / ev(0));
}

std::unique_ptr<Parameterization> makeParameterization(ParameterizationKind kind, int resolution) {
  switch (kind) {
    case ParameterizationKind::Sphere:
      return std::make_unique<SphereMap>(resolution);
    case ParameterizationKind::Paraboloid:
      return std::make_unique<ParaboloidMap>(resolution);
    case ParameterizationKind::Cube:
      return std::make_unique<CubeMap>(resolution);
    case ParameterizationKind::LatLong:
      return std::make_unique<LatLongMap>(resolution);
  }
  throw Error(Error::Kind::InvalidArgument, "unknown parameterization");
}

}  // namespace brdfbake
