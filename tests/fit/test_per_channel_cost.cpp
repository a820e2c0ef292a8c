// The per-channel fit's cost function (fit/per_channel_cost.hpp: every sample of a channel in one residual
// block, the robust loss applied inside) against the plain Ceres formulation it replaces: one residual
// block per sample with Ceres' own loss function, the residual typed out again here (pow rather than the
// library's exp of a logarithm, Ceres' automatic derivatives rather than its per-lobe Jets). Levenberg-
// Marquardt sees a problem through its cost, its gradient and J^T J: they must agree, with the loss in
// its outlier region too, and in every order of evaluation the cost function's cache meets.
#include <gtest/gtest.h>
#include <brdfbake/core/math.hpp>
#include <brdfbake/fit/cornell_grid.hpp>

#include <ceres/ceres.h>

#include <Eigen/Dense>

#include <cmath>
#include <memory>
#include <vector>

#include "../../fit/per_channel_cost.hpp"
#include "../../fit/per_channel_fit.hpp"

namespace brdfbake::detail {
namespace {

// r = cbrt(cos theta_i f + eps) - target for one sample, f = k_d / pi + sum_k C_k (n_k + 2) / (2 pi)
// (r_v . l)^n_k, with C_k, n_k themselves (count 1) or exp(sum_j b_j ln p_j) (Bernstein weights b_j).
struct SampleResidual {
  FitSample sample;
  int lobes, count;
  double eps;

  template <class T>
  bool operator()(T const* const* parameters, T* residual) const {
    const T* x = parameters[0];
    T f = x[0] / kPi;
    for (int k = 0; k < lobes; ++k) {
      const T* p = x + 1 + k * 2 * count;
      T weight = p[0], exponent = p[1];
      if (count > 1) {
        T logWeight(0.0), logExponent(0.0);
        for (int j = 0; j < count; ++j) {
          logWeight += sample.bernstein[j] * p[j];
          logExponent += sample.bernstein[j] * p[count + j];
        }
        weight = exp(logWeight), exponent = exp(logExponent);
      }
      if (sample.cosToMirror > 0.0) f += weight * (exponent + 2.0) / (2.0 * kPi) * pow(T(sample.cosToMirror), exponent);
    }
    residual[0] = cbrt(sample.cosIn * f + eps) - sample.target;
    return true;
  }
};

struct Evaluation {
  double cost = 0.0;
  std::vector<double> gradient;
  Eigen::MatrixXd normal;  // J^T J
};

Evaluation evaluate(ceres::Problem& problem) {
  Evaluation e;
  ceres::CRSMatrix crs;
  problem.Evaluate(ceres::Problem::EvaluateOptions(), &e.cost, nullptr, &e.gradient, &crs);
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row)
    for (int at = crs.rows[row]; at < crs.rows[row + 1]; ++at) jacobian(row, crs.cols[at]) = crs.values[at];
  e.normal = jacobian.transpose() * jacobian;
  return e;
}

// One block per sample with `loss` (may be null), as the fit was before.
Evaluation perSample(const ChannelData& data, std::vector<double> x, int lobes, int count, ceres::LossFunction* loss) {
  ceres::Problem::Options options;
  options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(options);
  for (const auto& sample : data.samples) {
    auto* cost =
        new ceres::DynamicAutoDiffCostFunction<SampleResidual>(new SampleResidual{sample, lobes, count, data.eps});
    cost->AddParameterBlock(static_cast<int>(x.size()));
    cost->SetNumResiduals(1);
    problem.AddResidualBlock(cost, loss, x.data());
  }
  return evaluate(problem);
}

Evaluation oneBlock(const ChannelData& data, std::vector<double> x, int lobes, int count,
                    const ceres::LossFunction* loss) {
  ceres::Problem problem;
  problem.AddResidualBlock(makeChannelCost(data, lobes, count, loss), nullptr, x.data());
  return evaluate(problem);
}

void expectSame(const Evaluation& a, const Evaluation& b, const std::string& what) {
  EXPECT_NEAR(a.cost, b.cost, 1e-11 * a.cost) << what;
  ASSERT_EQ(a.gradient.size(), b.gradient.size()) << what;
  double largest = 0.0;
  for (double g : a.gradient) largest = std::max(largest, std::abs(g));
  for (std::size_t i = 0; i < a.gradient.size(); ++i) EXPECT_NEAR(a.gradient[i], b.gradient[i], 1e-9 * largest) << what;
  EXPECT_LT((a.normal - b.normal).cwiseAbs().maxCoeff(), 1e-9 * a.normal.cwiseAbs().maxCoeff()) << what;
}

// A channel of a table made from known lobes, every 97th row 10x too bright (outliers for the loss).
ChannelData channelWithOutliers(const LobeModel& truth) {
  MeasuredTable table = makeSyntheticTable(truth, 0.01, 5);
  for (std::size_t i = 0; i < table.size(); i += 97) table.values.row(static_cast<Eigen::Index>(i)) *= 10.0;
  return channelData(table, 0, fittedRange(table));
}

LobeModel twoLobes(LobeElevation elevation) {
  LobeModel m;
  m.elevation = elevation;
  const bool varying = elevation == LobeElevation::Varying;
  m.minCos = std::cos(radians(79.05));
  m.channels = {{"R",
                 0.15,
                 {{varying ? std::vector<double>{0.3, 0.2, 0.1} : std::vector<double>{0.2},
                   varying ? std::vector<double>{20.0, 12.0, 8.0} : std::vector<double>{12.0}},
                  {varying ? std::vector<double>{0.9, 0.4, 0.3} : std::vector<double>{0.5},
                   varying ? std::vector<double>{300.0, 150.0, 90.0} : std::vector<double>{150.0}}}}};
  return m;
}

// Parameter vectors of 2 lobes: near the truth and far from it (large residuals: the loss's outlier
// region), as the optimiser holds them (varying lobes as logarithms).
std::vector<std::vector<double>> parameterVectors(int count) {
  std::vector<std::vector<double>> vectors;
  for (double factor : {1.0, 1.6, 0.4}) {
    std::vector<double> x = {0.15 * factor};
    for (auto [weight, exponent] : {std::pair{0.25, 14.0}, std::pair{0.6, 160.0}}) {
      for (int j = 0; j < count; ++j) x.push_back(count == 1 ? weight * factor : std::log(weight * factor) - 0.1 * j);
      for (int j = 0; j < count; ++j)
        x.push_back(count == 1 ? exponent / factor : std::log(exponent / factor) + 0.2 * j);
    }
    vectors.push_back(x);
  }
  return vectors;
}

TEST(PerChannelCost, IsOneBlockPerSampleWithCeresLoss) {
  for (LobeElevation elevation : {LobeElevation::Constant, LobeElevation::Varying}) {
    const int count = elevationCoefficientCount(elevation);
    const ChannelData data = channelWithOutliers(twoLobes(elevation));
    const double scale = 0.2 * data.maxTarget;
    std::unique_ptr<ceres::LossFunction> losses[] = {std::make_unique<ceres::CauchyLoss>(scale),
                                                     std::make_unique<ceres::HuberLoss>(scale), nullptr};
    for (const auto& loss : losses) {
      for (const auto& x : parameterVectors(count)) {
        const std::string what =
            "count " + std::to_string(count) + (loss ? "" : " no loss") + " x0 " + std::to_string(x[0]);
        expectSame(perSample(data, x, 2, count, loss.get()), oneBlock(data, x, 2, count, loss.get()), what);
      }
    }
  }
}

TEST(PerChannelCost, TheLossMatters) {
  // Else the comparison above would not see a loss applied wrongly.
  const ChannelData data = channelWithOutliers(twoLobes(LobeElevation::Constant));
  ceres::CauchyLoss cauchy(0.2 * data.maxTarget);
  const auto x = parameterVectors(1)[1];
  EXPECT_GT(oneBlock(data, x, 2, 1, nullptr).cost, 1.2 * oneBlock(data, x, 2, 1, &cauchy).cost);
}

// Residuals, and the Jacobian if asked, of `cost` at x.
std::pair<std::vector<double>, std::vector<double>> evaluateAt(const ceres::CostFunction& cost,
                                                               const std::vector<double>& x, bool jacobian) {
  std::vector<double> residuals(static_cast<std::size_t>(cost.num_residuals()));
  std::vector<double> rows(jacobian ? residuals.size() * x.size() : 0);
  const double* parameters[] = {x.data()};
  double* jacobians[] = {rows.data()};
  EXPECT_TRUE(cost.Evaluate(parameters, residuals.data(), jacobian ? jacobians : nullptr));
  return {residuals, rows};
}

void expectClose(const std::vector<double>& got, const std::vector<double>& expected, const std::string& what) {
  ASSERT_EQ(got.size(), expected.size()) << what;
  for (std::size_t i = 0; i < got.size(); ++i)
    ASSERT_NEAR(got[i], expected[i], 1e-13 * std::max(1.0, std::abs(expected[i]))) << what << ", entry " << i;
}

TEST(PerChannelCost, EveryOrderOfEvaluationGivesWhatAFreshOneGives) {
  const ChannelData data = channelWithOutliers(twoLobes(LobeElevation::Varying));
  ceres::CauchyLoss cauchy(0.2 * data.maxTarget);
  const auto vectors = parameterVectors(kVaryingCount);
  std::unique_ptr<ceres::CostFunction> reused(makeChannelCost(data, 2, kVaryingCount, &cauchy));
  // First a Jacobian, then residuals and the Jacobian at the same point (the cache), then a Jacobian
  // at another point, then back.
  const std::pair<int, bool> order[] = {{0, true},  {1, false}, {1, true},  {2, true},
                                        {2, false}, {0, true},  {0, false}, {1, true}};
  for (const auto& [which, jacobian] : order) {
    std::unique_ptr<ceres::CostFunction> fresh(makeChannelCost(data, 2, kVaryingCount, &cauchy));
    const auto& x = vectors[static_cast<std::size_t>(which)];
    const auto expected = evaluateAt(*fresh, x, jacobian), got = evaluateAt(*reused, x, jacobian);
    // The same to rounding: a cached value comes from the residuals' plain doubles, a fresh one from Jets.
    expectClose(got.first, expected.first, "residuals at x " + std::to_string(which));
    expectClose(got.second, expected.second, "Jacobian at x " + std::to_string(which));
  }
}

}  // namespace
}  // namespace brdfbake::detail
