// Non-negative least squares of the shared fit (fit/shared_lobe_fit.hpp, Lawson & Hanson 1974 on the
// normal equations), against the optimality conditions of the problem and, for small problems, the
// best of every set of free coefficients solved by hand: sizes on both sides of the stack-held sizes
// (8 and 32) and beyond.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>

#include "../../fit/shared_lobe_fit.hpp"

namespace brdfbake::detail {
namespace {

struct Problem {
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  Eigen::MatrixXd gram() const { return a.transpose() * a; }
  Eigen::VectorXd rhs() const { return a.transpose() * b; }
  double objective(const Eigen::VectorXd& x) const { return (a * x - b).squaredNorm(); }
};

// Positive, correlated columns, as lobes' columns are, and a target some of them cannot reach
// without negative coefficients.
Problem randomProblem(int rows, int columns, std::mt19937& random) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Problem p{Eigen::MatrixXd(rows, columns), Eigen::VectorXd(rows)};
  for (int j = 0; j < columns; ++j)
    for (int i = 0; i < rows; ++i) p.a(i, j) = std::pow(uniform(random), 1.0 + 3.0 * j / columns);
  for (int i = 0; i < rows; ++i) p.b[i] = uniform(random) - 0.3;
  return p;
}

// The minimum over every set of free coefficients whose unconstrained solution is non-negative.
double bestBySubsets(const Problem& p) {
  const auto n = static_cast<int>(p.a.cols());
  double best = p.b.squaredNorm();  // x = 0
  for (unsigned mask = 1; mask < (1u << n); ++mask) {
    std::vector<int> free;
    for (int j = 0; j < n; ++j)
      if (mask & (1u << j)) free.push_back(j);
    Eigen::MatrixXd sub(p.a.rows(), static_cast<Eigen::Index>(free.size()));
    for (std::size_t k = 0; k < free.size(); ++k) sub.col(static_cast<Eigen::Index>(k)) = p.a.col(free[k]);
    const Eigen::VectorXd z = sub.colPivHouseholderQr().solve(p.b);
    if (z.minCoeff() < 0.0) continue;
    best = std::min(best, (sub * z - p.b).squaredNorm());
  }
  return best;
}

TEST(NonNegativeLeastSquares, MeetsTheOptimalityConditions) {
  // x >= 0, the gradient G x - h >= 0 everywhere and 0 where x > 0 (Karush-Kuhn-Tucker).
  std::mt19937 random(11);
  for (int columns : {1, 3, 7, 8, 9, 16, 32, 33, 48}) {
    for (int trial = 0; trial < 5; ++trial) {
      const Problem p = randomProblem(4 * columns + 20, columns, random);
      const Eigen::MatrixXd g = p.gram();
      const Eigen::VectorXd h = p.rhs();
      const Eigen::VectorXd x = nonNegativeLeastSquares(g, h);
      ASSERT_EQ(x.size(), columns);
      const Eigen::VectorXd gradient = g * x - h;
      const double scale = h.cwiseAbs().maxCoeff();
      EXPECT_GE(x.minCoeff(), 0.0) << columns;
      for (int j = 0; j < columns; ++j) {
        EXPECT_GE(gradient[j], -1e-8 * scale) << columns << " coefficient " << j;
        if (x[j] > 1e-9) {
          EXPECT_NEAR(gradient[j], 0.0, 1e-8 * scale) << columns << " coefficient " << j;
        }
      }
    }
  }
}

TEST(NonNegativeLeastSquares, FindsTheBestSetOfFreeCoefficients) {
  std::mt19937 random(12);
  for (int columns : {2, 5, 8, 9, 10}) {
    for (int trial = 0; trial < 4; ++trial) {
      const Problem p = randomProblem(40, columns, random);
      const double best = bestBySubsets(p);
      EXPECT_NEAR(p.objective(nonNegativeLeastSquares(p.gram(), p.rhs())), best, 1e-9 * (1.0 + best)) << columns;
    }
  }
}

}  // namespace
}  // namespace brdfbake::detail
