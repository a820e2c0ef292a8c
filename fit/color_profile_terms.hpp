#pragma once
// Internal to fit/: colour profiles in the shared fit (ColorProfile::DifferenceAngle, brdf/lobes.hpp).
// Each weight column of the design matrix is split into kColorProfileCount columns, one per cubic
// Bernstein polynomial in s = theta_d / 90 degrees; the non-negative coefficients the fit solves for
// are a term's weight times its profile's coefficients.
#include <Eigen/Core>

#include <vector>

namespace brdfbake::detail {

// The design matrix with colour profiles: column m times the Bernstein polynomial j in row i's
// coordinates[i] (theta_d / 90 degrees) becomes column m kColorProfileCount + j.
Eigen::MatrixXd withColorProfiles(const Eigen::MatrixXd& a, const std::vector<double>& coordinates);

// A term of a channel: its weight and, with colour profiles, its profile.
struct ProfiledTerm {
  double weight = 0.0;
  std::vector<double> profile;  // empty without colour profiles
};

// The term of (unexpanded) design column `column` in solution x: without profiles, x[column]; with
// them, the largest of the column's kColorProfileCount coefficients is the weight and the profile
// holds the coefficients divided by it (all 1 when they are all 0), so the profile's largest value is 1.
ProfiledTerm profiledTerm(const Eigen::VectorXd& x, Eigen::Index column, bool profiled);

}  // namespace brdfbake::detail
