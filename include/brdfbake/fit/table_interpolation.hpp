#pragma once
/// @file
/// A measured table evaluated at any pair of directions (`brdfbake eval TABLE`), without a model:
///
/// 1. Isotropy: only the azimuth difference matters, so the query is rotated about the normal to
///    the azimuth of the table's incident directions.
/// 2. Incident angle: the samples whose theta_i is nearest the query's (no blending between
///    incident angles: a highlight moves with theta_i, and blending two tables at a fixed view
///    would smear it into two half-height peaks).
/// 3. Outgoing direction: inverse-distance weighting over the `neighbours` (default 4) samples of
///    that incident angle nearest the query's outgoing direction by angle on the sphere, with
///    weights 1 / angle^2; a sample within 1e-9 rad is returned as is. The mirror symmetry of an
///    isotropic surface (the outgoing azimuth mirrored about the plane of incidence) is used:
///    each sample's distance is the smaller of its distance to the query and to the query's mirror
///    image, so Cornell's half-hemisphere tables cover the whole hemisphere.
///
/// Directions at or below the horizon (z <= 0) give 0. The result has the table's channels.

#include <brdfbake/measured/measured_table.hpp>

#include <Eigen/Core>

#include <vector>

namespace brdfbake {

class TableInterpolator {
 public:
  /// Keeps a copy of the table (validated: Error(InvalidInput)); `neighbours` >= 1
  /// (Error(InvalidArgument)). Throws Error(InvalidInput) for a table without samples.
  explicit TableInterpolator(MeasuredTable table, int neighbours = 4);

  /// BRDF (1/sr) per channel for light `wi` and view `wo` (local frame, z = normal; need not be
  /// unit length but must be finite and non-zero, else Error(InvalidArgument)).
  Eigen::VectorXd evaluate(const Vec3& wi, const Vec3& wo) const;

  const MeasuredTable& table() const { return table_; }

 private:
  struct Group {
    double thetaIn, phiIn;
    std::vector<std::size_t> samples;
    std::vector<Vec3> outgoing;
  };
  MeasuredTable table_;
  int neighbours_;
  std::vector<Group> groups_;
};

}  // namespace brdfbake
