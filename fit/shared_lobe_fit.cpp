#include "shared_lobe_fit.hpp"

#include <brdfbake/core/error.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace brdfbake::detail {

Eigen::VectorXd nonNegativeLeastSquares(const Eigen::MatrixXd& gram, const Eigen::VectorXd& rhs) {
  const Eigen::Index p = rhs.size();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(p);
  std::vector<bool> passive(static_cast<std::size_t>(p), false);
  const double scale = std::max(gram.diagonal().maxCoeff(), 1e-300);
  const double tolerance = 1e-13 * std::max(rhs.cwiseAbs().maxCoeff(), 1e-300);
  // The unconstrained least-squares solution on the passive set (others 0), a tiny ridge against
  // columns that are (nearly) dependent.
  auto solvePassive = [&] {
    std::vector<Eigen::Index> index;
    for (Eigen::Index j = 0; j < p; ++j)
      if (passive[static_cast<std::size_t>(j)]) index.push_back(j);
    const auto m = static_cast<Eigen::Index>(index.size());
    Eigen::MatrixXd g(m, m);
    Eigen::VectorXd h(m);
    for (Eigen::Index a = 0; a < m; ++a) {
      h[a] = rhs[index[a]];
      for (Eigen::Index b = 0; b < m; ++b) g(a, b) = gram(index[a], index[b]);
      g(a, a) += 1e-12 * std::max(gram(index[a], index[a]), 1e-300);
    }
    const Eigen::VectorXd s = g.ldlt().solve(h);
    Eigen::VectorXd z = Eigen::VectorXd::Zero(p);
    for (Eigen::Index a = 0; a < m; ++a) z[index[a]] = s[a];
    return z;
  };
  for (int outer = 0; outer < 3 * p + 3; ++outer) {
    const Eigen::VectorXd w = rhs - gram * x;
    Eigen::Index best = -1;
    for (Eigen::Index j = 0; j < p; ++j) {
      if (!passive[static_cast<std::size_t>(j)] && w[j] > tolerance && (best < 0 || w[j] > w[best])) best = j;
    }
    if (best < 0) break;
    passive[static_cast<std::size_t>(best)] = true;
    for (int inner = 0; inner < 3 * p + 3; ++inner) {
      Eigen::VectorXd z = solvePassive();
      bool feasible = true;
      double alpha = 1.0;
      for (Eigen::Index j = 0; j < p; ++j) {
        if (passive[static_cast<std::size_t>(j)] && z[j] <= 0.0) {
          feasible = false;
          const double denominator = x[j] - z[j];
          if (denominator > 0.0) alpha = std::min(alpha, x[j] / denominator);
        }
      }
      if (feasible) {
        x = z;
        break;
      }
      x += alpha * (z - x);
      for (Eigen::Index j = 0; j < p; ++j) {
        if (passive[static_cast<std::size_t>(j)] && x[j] <= 1e-15 * scale) {
          passive[static_cast<std::size_t>(j)] = false;
          x[j] = 0.0;
        }
      }
    }
  }
  return x.cwiseMax(0.0);
}

namespace {

struct Row {
  double cosIn;
  LobeGeometry geometry;
};

struct Shape {
  double logExponent;
  double cxy;               // -1 for half-vector lobes
  bool halfVector = false;  // halfVectorLobe (weight columns C and C_F)
};

// The fitted rows and their targets.
struct Data {
  std::vector<Row> rows;
  Eigen::MatrixXd measured;  // rows x channels, max(f, 0)
  Eigen::MatrixXd logTarget; // ln(1 + cos theta_i max(f, 0))
  Eigen::VectorXd cosIn;
};

class SharedFitter {
 public:
  SharedFitter(Data data, const SharedFitConfig& config) : data_(std::move(data)), config_(config) {
    const auto channels = static_cast<int>(data_.measured.cols());
    const int searched = std::min(config.searchChannels, channels);
    for (int s = 0; s < searched; ++s) {
      search_.push_back(searched == 1 ? channels - 1 : static_cast<int>(std::lround(double(s) * (channels - 1) / (searched - 1))));
    }
  }

  // Weight columns of one lobe: 1, or 2 for a half-vector lobe (C and its Fresnel weight C_F).
  static int columns(const Shape& shape) { return shape.halfVector ? 2 : 1; }

  // The design matrix: 1/pi for the diffuse term, then the columns of each lobe of unit weight (a
  // half-vector lobe's C, then its C_F).
  Eigen::MatrixXd design(const std::vector<Shape>& shapes) const {
    const auto n = static_cast<Eigen::Index>(data_.rows.size());
    Eigen::Index total = 1;
    for (const auto& shape : shapes) total += columns(shape);
    Eigen::MatrixXd a(n, total);
    a.col(0).setConstant(1.0 / std::numbers::pi);
    Eigen::Index column = 1;
    for (const auto& shape : shapes) {
      const double exponent = std::exp(shape.logExponent);
      for (Eigen::Index i = 0; i < n; ++i) {
        const LobeGeometry& g = data_.rows[static_cast<std::size_t>(i)].geometry;
        if (!shape.halfVector) {
          a(i, column) = normalizedLobe(1.0, exponent, g.cosine(shape.cxy));
        } else {
          a(i, column) = halfVectorLobe(1.0, 0.0, exponent, g);
          a(i, column + 1) = halfVectorLobe(0.0, 1.0, exponent, g);
        }
      }
      column += columns(shape);
    }
    return a;
  }

  // Sum of r_i^2 of one channel for coefficients x.
  double channelObjective(const Eigen::MatrixXd& a, int channel, const Eigen::VectorXd& x) const {
    const Eigen::VectorXd f = a * x;
    double sum = 0.0;
    for (Eigen::Index i = 0; i < f.size(); ++i) {
      const double r = std::log1p(data_.cosIn[i] * std::max(f[i], 0.0)) - data_.logTarget(i, channel);
      sum += r * r;
    }
    return sum;
  }

  // Coefficients of one channel: a weighted NNLS linearised at the data, then Gauss-Newton steps
  // (each an NNLS of the residual linearised at the current model) with step halving.
  Eigen::VectorXd solveChannel(const Eigen::MatrixXd& a, int channel, int steps, double* objective) const {
    const Eigen::Index n = a.rows();
    Eigen::VectorXd omega(n), target(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double y = data_.measured(i, channel);
      omega[i] = data_.cosIn[i] / (1.0 + data_.cosIn[i] * y);
      target[i] = y;
    }
    auto weightedNnls = [&] {
      const Eigen::MatrixXd aw = omega.asDiagonal() * a;
      const Eigen::VectorXd bw = omega.cwiseProduct(target);
      return nonNegativeLeastSquares(aw.transpose() * aw, aw.transpose() * bw);
    };
    Eigen::VectorXd x = weightedNnls();
    double current = channelObjective(a, channel, x);
    for (int step = 0; step < steps; ++step) {
      const Eigen::VectorXd f = a * x;
      for (Eigen::Index i = 0; i < n; ++i) {
        const double fi = std::max(f[i], 0.0);
        omega[i] = data_.cosIn[i] / (1.0 + data_.cosIn[i] * fi);
        const double r = std::log1p(data_.cosIn[i] * fi) - data_.logTarget(i, channel);
        target[i] = fi - r / omega[i];
      }
      const Eigen::VectorXd proposal = weightedNnls();
      bool improved = false;
      for (double alpha = 1.0; alpha > 0.1; alpha *= 0.5) {
        const Eigen::VectorXd trial = x + alpha * (proposal - x);
        const double value = channelObjective(a, channel, trial);
        if (value < current) {
          const double gain = current - value;
          x = trial;
          current = value;
          improved = gain > 1e-9 * current;
          break;
        }
      }
      if (!improved) break;
    }
    if (objective) *objective = current;
    return x;
  }

  // The objective the shape search minimises: summed over the searched channels.
  double searchObjective(const std::vector<Shape>& shapes) {
    ++evaluations;
    if (!admissible(shapes)) return HUGE_VAL;
    const Eigen::MatrixXd a = design(shapes);
    double sum = 0.0;
    for (int c : search_) {
      double value = 0.0;
      solveChannel(a, c, 2, &value);
      sum += value;
    }
    return sum;
  }

  bool admissible(const std::vector<Shape>& shapes) const {
    for (const auto& s : shapes) {
      if (s.logExponent < std::log(kMinLobeExponent) || s.logExponent > std::log(config_.maxExponent)) return false;
      if (std::abs(s.cxy) > kMaxLobeCxy) return false;
      if (std::exp(s.logExponent) * std::log(std::max(1.0, std::abs(s.cxy))) > kMaxLobeGrowthLog) return false;
    }
    return true;
  }

  // Greedy start for one more lobe: a grid of exponents (and c_xy), the others fixed.
  std::vector<Shape> withNewLobe(const std::vector<Shape>& shapes) {
    std::vector<double> cxys;
    if (config_.mirror) cxys = {-1.0};
    if (config_.lafortune) cxys = {-1.0, -1.3, -2.0, -0.7, 0.0, 0.7, 1.0, 1.3, 2.0};
    std::vector<std::pair<double, bool>> axes;  // (c_xy, half-vector)
    if (config_.halfVector) axes.emplace_back(-1.0, true);
    for (double cxy : cxys) axes.emplace_back(cxy, false);
    double best = HUGE_VAL;
    std::vector<Shape> chosen = shapes;
    for (const auto& [cxy, halfVector] : axes) {
      for (double n = 2.0; n <= config_.maxExponent * 1.0001; n *= 2.0) {
        std::vector<Shape> trial = shapes;
        trial.push_back({std::log(n), cxy, halfVector});
        const double value = searchObjective(trial);
        if (value < best) {
          best = value;
          chosen = std::move(trial);
        }
      }
    }
    return chosen;
  }

  // Compass search on (ln n_k, c_xy,k) of every lobe.
  std::vector<Shape> refine(std::vector<Shape> shapes) {
    double value = searchObjective(shapes);
    double logStep = 0.35, cxyStep = 0.2;
    const int budget = evaluations + config_.maxEvaluations;
    while ((logStep > 0.01 || (config_.lafortune && cxyStep > 0.005)) && evaluations < budget) {
      bool improved = false;
      for (std::size_t k = 0; k < shapes.size(); ++k) {
        for (int coordinate = 0; coordinate < (config_.lafortune && !shapes[k].halfVector ? 2 : 1); ++coordinate) {
          for (double sign : {1.0, -1.0}) {
            std::vector<Shape> trial = shapes;
            (coordinate == 0 ? trial[k].logExponent : trial[k].cxy) += sign * (coordinate == 0 ? logStep : cxyStep);
            const double v = searchObjective(trial);
            if (v < value * (1.0 - 1e-9)) {
              value = v;
              shapes = std::move(trial);
              improved = true;
              break;
            }
          }
        }
      }
      if (!improved) {
        logStep *= 0.5;
        cxyStep *= 0.5;
      }
    }
    return shapes;
  }

  std::vector<Shape> fitShapes() {
    std::vector<Shape> shapes;
    for (const Lobe& lobe : config_.startLobes) {
      if (static_cast<int>(shapes.size()) == config_.lobes) break;
      shapes.push_back({std::log(lobe.exponent.at(0)), lobe.halfVector ? -1.0 : lobe.cxy, lobe.halfVector});
    }
    for (int k = static_cast<int>(shapes.size()); k < config_.lobes; ++k) shapes = refine(withNewLobe(shapes));
    return shapes;
  }

  const Data& data() const { return data_; }
  int evaluations = 0;

 private:
  Data data_;
  SharedFitConfig config_;
  std::vector<int> search_;
};

}  // namespace

SharedFitOutcome fitSharedLobes(const MeasuredTable& table, const SharedFitConfig& config, const LobeModel& range) {
  Data data;
  std::vector<std::size_t> used;
  for (std::size_t i = 0; i < table.size(); ++i) {
    const Vec3 wi = table.incidentDirection(i), wo = table.outgoingDirection(i);
    if (!(wi.z() > 0.0) || !(wo.z() > 0.0)) continue;
    data.rows.push_back({wi.z(), LobeGeometry::local(wi, wo)});
    used.push_back(i);
  }
  if (used.empty()) throw Error(Error::Kind::InvalidInput, "fit: no sample has both directions above the horizon");
  const auto n = static_cast<Eigen::Index>(used.size());
  const auto channels = static_cast<Eigen::Index>(table.channelCount());
  data.measured.resize(n, channels);
  data.logTarget.resize(n, channels);
  data.cosIn.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    data.cosIn[i] = data.rows[static_cast<std::size_t>(i)].cosIn;
    for (Eigen::Index c = 0; c < channels; ++c) {
      const double f = std::max(table.values(static_cast<Eigen::Index>(used[static_cast<std::size_t>(i)]), c), 0.0);
      data.measured(i, c) = f;
      data.logTarget(i, c) = std::log1p(data.cosIn[i] * f);
    }
  }
  SharedFitter fitter(std::move(data), config);
  const std::vector<Shape> shapes = fitter.fitShapes();
  const Eigen::MatrixXd a = fitter.design(shapes);

  SharedFitOutcome outcome;
  outcome.rows = used.size();
  outcome.model.elevation = LobeElevation::Constant;
  outcome.model.minCos = range.minCos;
  outcome.model.maxCos = range.maxCos;
  if (table.kind == ChannelKind::Spectral) outcome.model.wavelengthsNm = table.wavelengthsNm;
  for (Eigen::Index c = 0; c < channels; ++c) {
    double objective = 0.0;
    const Eigen::VectorXd x = fitter.solveChannel(a, static_cast<int>(c), 8, &objective);
    outcome.objective += objective;
    LobeChannel channel;
    channel.name = static_cast<std::size_t>(c) < table.channelNames.size() ? table.channelNames[static_cast<std::size_t>(c)]
                                                                            : std::to_string(c);
    channel.diffuse = x[0];
    Eigen::Index column = 1;
    for (const auto& shape : shapes) {
      Lobe lobe;
      lobe.weight = {x[column]};
      lobe.exponent = {std::clamp(std::exp(shape.logExponent), kMinLobeExponent, kMaxLobeExponent)};
      lobe.cxy = shape.halfVector ? -1.0 : shape.cxy;
      lobe.halfVector = shape.halfVector;
      if (shape.halfVector) lobe.fresnel = x[column + 1];
      column += SharedFitter::columns(shape);
      channel.lobes.push_back(std::move(lobe));
    }
    outcome.model.channels.push_back(std::move(channel));
  }
  outcome.evaluations = fitter.evaluations;
  return outcome;
}

}  // namespace brdfbake::detail
