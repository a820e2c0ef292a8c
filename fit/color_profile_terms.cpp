#include "color_profile_terms.hpp"

#include <brdfbake/brdf/lobes.hpp>

namespace brdfbake::detail {

Eigen::MatrixXd withColorProfiles(const Eigen::MatrixXd& a, const std::vector<double>& coordinates) {
  Eigen::MatrixXd bernstein(a.rows(), kColorProfileCount);
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    double weights[kColorProfileCount];
    bernsteinWeights(kColorProfileCount, coordinates[static_cast<std::size_t>(i)], weights);
    for (int j = 0; j < kColorProfileCount; ++j) bernstein(i, j) = weights[j];
  }
  Eigen::MatrixXd expanded(a.rows(), a.cols() * kColorProfileCount);
  for (Eigen::Index m = 0; m < a.cols(); ++m) {
    for (int j = 0; j < kColorProfileCount; ++j)
      expanded.col(m * kColorProfileCount + j) = a.col(m).cwiseProduct(bernstein.col(j));
  }
  return expanded;
}

ProfiledTerm profiledTerm(const Eigen::VectorXd& x, Eigen::Index column, bool profiled) {
  if (!profiled) return {x[column], {}};
  const Eigen::VectorXd p = x.segment(column * kColorProfileCount, kColorProfileCount);
  const double peak = p.maxCoeff();
  ProfiledTerm term{peak, std::vector<double>(kColorProfileCount, 1.0)};
  if (peak > 0.0)
    for (int j = 0; j < kColorProfileCount; ++j) term.profile[static_cast<std::size_t>(j)] = p[j] / peak;
  return term;
}

}  // namespace brdfbake::detail
