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

// Lobe columns as the shape search sees them: powers cos^n of exponents 2 to 1e4 (nearly collinear
// neighbours), a constant (the diffuse term), a column of zeros (a lobe that misses every row), and a
// target from positive weights of some of them plus noise.
Problem lobeLikeProblem(int rows, std::mt19937& random) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const std::vector<double> exponents{2.0, 3.0, 10.0, 11.0, 100.0, 110.0, 1e4};
  Problem p{Eigen::MatrixXd::Zero(rows, static_cast<Eigen::Index>(exponents.size()) + 2), Eigen::VectorXd(rows)};
  for (int i = 0; i < rows; ++i) {
    const double c = std::pow(uniform(random), 0.05);  // cosines crowded near 1, where sharp lobes live
    p.a(i, 0) = 1.0;
    for (std::size_t k = 0; k < exponents.size(); ++k)
      p.a(i, static_cast<Eigen::Index>(k) + 1) = std::pow(c, exponents[k]);
    p.b[i] = 0.1 + 0.5 * std::pow(c, 10.5) + 0.3 * std::pow(c, 5e3) + 0.01 * (uniform(random) - 0.5);
  }
  return p;
}

TEST(NonNegativeLeastSquares, HandlesNearlyCollinearAndEmptyColumns) {
  std::mt19937 random(13);
  for (int trial = 0; trial < 5; ++trial) {
    const Problem p = lobeLikeProblem(300, random);
    const Eigen::VectorXd x = nonNegativeLeastSquares(p.gram(), p.rhs());
    EXPECT_GE(x.minCoeff(), 0.0);
    EXPECT_EQ(x[x.size() - 1], 0.0);  // the empty column
    // Within a hair of the best over every set of free coefficients (the tiny ridge against
    // dependent columns costs a little).
    const double best = bestBySubsets(p);
    EXPECT_LE(p.objective(x), best * (1.0 + 1e-6) + 1e-12) << trial;
    EXPECT_GE(p.objective(x), best * (1.0 - 1e-9)) << trial;
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
