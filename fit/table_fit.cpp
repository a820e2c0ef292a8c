#include "table_fit.hpp"

#include <brdfbake/core/error.hpp>

#include <Eigen/Cholesky>

#include <algorithm>

namespace brdfbake::detail {
namespace {

// The normal equations of the data term: A^T A and A^T y (one column per channel), and each
// channel's range of y.
struct NormalEquations {
  Eigen::MatrixXd gram;
  Eigen::MatrixXd rhs;
  std::size_t rows = 0;
  Eigen::VectorXd lowest, highest;
};

// The normal equations of the rows with light and view above the horizon.
NormalEquations dataTerm(const MeasuredTable& table) {
  const int n = kFittedTableShape.coefficientCount();
  const auto channels = static_cast<Eigen::Index>(table.channelCount());
  NormalEquations eq{Eigen::MatrixXd::Zero(n, n), Eigen::MatrixXd::Zero(n, channels), 0,
                     Eigen::VectorXd::Constant(channels, HUGE_VAL), Eigen::VectorXd::Constant(channels, -HUGE_VAL)};
  int index[2 * (kMaxTableDegree + 1)];
  double value[2 * (kMaxTableDegree + 1)];
  for (std::size_t i = 0; i < table.size(); ++i) {
    const Vec3 light = table.incidentDirection(i), view = table.outgoingDirection(i);
    if (!(light.z() > 0.0) || !(view.z() > 0.0)) continue;
    const LobeGeometry geometry = LobeGeometry::local(light, view);
    const auto row = static_cast<Eigen::Index>(i);
    Eigen::VectorXd target(channels);
    for (Eigen::Index c = 0; c < channels; ++c) target[c] = std::log(std::max(table.values(row, c), kTableFloor));
    eq.lowest = eq.lowest.cwiseMin(target);
    eq.highest = eq.highest.cwiseMax(target);
    const auto basis = halfDifferenceBasis(kFittedTableShape, geometry);
    int terms = 0;
    basis.forEachTerm([&](int k, double v) {
      index[terms] = k;
      value[terms++] = v;
    });
    for (int a = 0; a < terms; ++a) {
      for (int b = 0; b < terms; ++b) eq.gram(index[a], index[b]) += value[a] * value[b];
      eq.rhs.row(index[a]) += value[a] * target.transpose();
    }
    ++eq.rows;
  }
  return eq;
}

// P^T P, P the second differences of the coefficients along both coordinates (see the header).
Eigen::MatrixXd smoothnessPenalty() {
  const int knots = kFittedTableShape.halfAngleKnots, stride = kFittedTableShape.differenceDegree + 1;
  const int n = kFittedTableShape.coefficientCount();
  Eigen::MatrixXd penalty = Eigen::MatrixXd::Zero(n, n);
  const auto addDifference = [&](int first, int step) {
    const int at[3] = {first, first + step, first + 2 * step};
    const double weight[3] = {1.0, -2.0, 1.0};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) penalty(at[a], at[b]) += weight[a] * weight[b];
  };
  for (int k = 0; k < knots; ++k) {
    for (int j = 0; j < stride; ++j) {
      if (k + 2 < knots) addDifference(k * stride + j, stride);
      if (j + 2 < stride) addDifference(k * stride + j, 1);
    }
  }
  return penalty;
}

// Every channel's coefficients (one column each) of the penalised least squares of the header, clamped
// to the channel's range of ln f widened by kTableRangeMargin.
Eigen::MatrixXd solveTable(const MeasuredTable& table) {
  const int n = kFittedTableShape.coefficientCount();
  NormalEquations eq = dataTerm(table);
  if (eq.rows < static_cast<std::size_t>(n)) {
    throw Error(Error::Kind::InvalidArgument, table.label() + ": " + std::to_string(eq.rows) +
                                                  " usable sample(s) cannot determine a half-difference table of " +
                                                  std::to_string(n) + " coefficients per channel");
  }
  const double scale = std::max(eq.gram.trace() / n, 1e-300);
  eq.gram += kTableSmoothing * scale * smoothnessPenalty();
  eq.gram.diagonal().array() += 1e-9 * scale;
  Eigen::MatrixXd coefficients = eq.gram.llt().solve(eq.rhs);
  for (Eigen::Index c = 0; c < coefficients.cols(); ++c) {
    const double lowest = std::max(eq.lowest[c] - kTableRangeMargin, -kMaxTableLogValue);
    const double highest = std::min(eq.highest[c] + kTableRangeMargin, kMaxTableLogValue);
    for (Eigen::Index k = 0; k < coefficients.rows(); ++k)
      coefficients(k, c) = clampFinite(coefficients(k, c), lowest, highest);
  }
  return coefficients;
}

std::vector<double> channelCoefficients(const Eigen::MatrixXd& coefficients, Eigen::Index channel) {
  const auto column = coefficients.col(channel);
  return {column.begin(), column.end()};
}

}  // namespace

std::size_t usableRows(const MeasuredTable& table) {
  std::size_t usable = 0;
  for (std::size_t i = 0; i < table.size(); ++i)
    usable += table.incidentDirection(i).z() > 0.0 && table.outgoingDirection(i).z() > 0.0;
  return usable;
}

bool canFitHalfDifferenceTable(const MeasuredTable& table) {
  return usableRows(table) >= static_cast<std::size_t>(kFittedTableShape.coefficientCount());
}

LobeModel fitHalfDifferenceTable(const MeasuredTable& table) {
  const Eigen::MatrixXd coefficients = solveTable(table);
  LobeModel model;
  model.halfDifference = kFittedTableShape;
  if (table.kind == ChannelKind::Spectral) model.wavelengthsNm = table.wavelengthsNm;
  for (Eigen::Index c = 0; c < coefficients.cols(); ++c) {
    LobeChannel channel;
    channel.name = table.channelName(static_cast<std::size_t>(c));
    channel.halfDifferenceCoefficients = channelCoefficients(coefficients, c);
    model.channels.push_back(std::move(channel));
  }
  model.validate();
  return model;
}

}  // namespace brdfbake::detail
