#include "shared_lobe_fit.hpp"

#include <brdfbake/core/error.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
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
  double logExponent;       // ln n at the most normal view (t = 1)
  double cxy;               // -1 for half-vector lobes
  bool halfVector = false;  // halfVectorLobe (weight columns C and C_F)
  // Varying lobes: ln n_j - ln n_2 and ln g_j (g_2 = 1) at the Bernstein nodes j = 0, 1 (t = 0 is
  // the most grazing view); all 0 for a constant lobe.
  std::array<double, 2> logExponentOffset{0.0, 0.0};
  std::array<double, 2> logGain{0.0, 0.0};

  bool operator==(const Shape&) const = default;
  bool varies() const { return logExponentOffset != std::array{0.0, 0.0} || logGain != std::array{0.0, 0.0}; }
  // Value j = 0, 1, 2 of the exponent and of the gain (LobeElevation::Varying's p0, p1, p2).
  double exponentAt(int j) const { return std::exp(logExponent + (j < 2 ? logExponentOffset[j] : 0.0)); }
  double gainAt(int j) const { return j < 2 ? std::exp(logGain[j]) : 1.0; }
};

// The fitted rows and their targets.
struct Data {
  std::vector<Row> rows;
  Eigen::MatrixXd measured;   // rows x channels, max(f, 0)
  Eigen::MatrixXd logTarget;  // ln(1 + cos theta_i max(f, 0))
  Eigen::VectorXd cosIn;
};

// What a lobe column needs of each row that does not depend on the shape, so that a trial costs one
// exp per row and lobe instead of pow: c^n = exp(n ln c), ln c = -inf where the lobe is 0.
struct RowFactors {
  Eigen::ArrayXd logCosMirror;  // ln cos to the mirrored view (c_xy = -1)
  Eigen::ArrayXd logCosHalf;    // ln n.h
  Eigen::ArrayXd halfScale;     // 1 / (4 (n.l)(n.v)), 0 below the horizon
  Eigen::ArrayXd schlick;       // (1 - l.h)^5
  Eigen::ArrayXXd bernstein;    // rows x 3: quadratic Bernstein weights at the view's elevation coordinate

  RowFactors(const std::vector<Row>& rows, const LobeModel& range) {
    const auto n = static_cast<Eigen::Index>(rows.size());
    logCosMirror.resize(n), logCosHalf.resize(n), halfScale.resize(n), schlick.resize(n);
    bernstein.resize(n, kVaryingDegree + 1);
    for (Eigen::Index i = 0; i < n; ++i) {
      const LobeGeometry& g = rows[static_cast<std::size_t>(i)].geometry;
      logCosMirror[i] = logPositive(g.cosine(-1.0));
      const bool above = g.lightZ > 0.0 && g.viewZ > 0.0;
      logCosHalf[i] = above ? logPositive(g.cosHalf()) : -HUGE_VAL;
      halfScale[i] = above ? 0.25 / (g.lightZ * g.viewZ) : 0.0;
      schlick[i] = g.schlick();
      double weights[kVaryingDegree + 1];
      bernsteinWeights(kVaryingDegree + 1, range.elevationCoordinate(g.viewZ), weights);
      for (int j = 0; j <= kVaryingDegree; ++j) bernstein(i, j) = weights[j];
    }
  }
  static double logPositive(double c) { return c > 0.0 ? std::log(c) : -HUGE_VAL; }
};

class SharedFitter {
 public:
  SharedFitter(Data data, const SharedFitConfig& config, const LobeModel& range)
      : data_(std::move(data)), factors_(data_.rows, range), config_(config) {
    const auto channels = static_cast<int>(data_.measured.cols());
    const int searched = std::min(config.searchChannels, channels);
    for (int s = 0; s < searched; ++s) {
      search_.push_back(searched == 1 ? channels - 1
                                      : static_cast<int>(std::lround(double(s) * (channels - 1) / (searched - 1))));
    }
    // The search's weighted least squares, linearised at the data: omega = d r / d f there.
    const auto n = data_.cosIn.size();
    searchWeights_.resize(n, searched), searchWeightedTargets_.resize(n, searched),
        searchLogTargets_.resize(n, searched);
    for (int s = 0; s < searched; ++s) {
      const Eigen::ArrayXd y = data_.measured.col(search_[static_cast<std::size_t>(s)]).array();
      const Eigen::ArrayXd omega2 = (data_.cosIn.array() / (1.0 + data_.cosIn.array() * y)).square();
      searchWeights_.col(s) = omega2.matrix();
      searchWeightedTargets_.col(s) = (omega2 * y).matrix();
      searchLogTargets_.col(s) = data_.logTarget.col(search_[static_cast<std::size_t>(s)]);
    }
  }

  // Weight columns of one lobe: 1, or 2 for a half-vector lobe (C and its Fresnel weight C_F).
  static int columns(const Shape& shape) { return shape.halfVector ? 2 : 1; }

  // The design matrix: 1/pi for the diffuse term, then the columns of each lobe of unit weight (a
  // half-vector lobe's C, then its C_F).
  Eigen::MatrixXd design(const std::vector<Shape>& shapes) {
    Eigen::Index total = 1;
    for (const auto& shape : shapes) total += columns(shape);
    Eigen::MatrixXd a(data_.cosIn.size(), total);
    a.col(0).setConstant(1.0 / std::numbers::pi);
    Eigen::Index column = 1;
    for (const auto& shape : shapes) {
      a.middleCols(column, columns(shape)) = lobeColumns(shape);
      column += columns(shape);
    }
    return a;
  }

  // One lobe's columns: normalizedLobe and halfVectorLobe of brdf/lobes.hpp, with c^n taken as
  // exp(n ln c) from the row factors. A compass step changes one lobe, so the others come from a
  // cache of recent shapes.
  const Eigen::MatrixXd& lobeColumns(const Shape& shape) {
    for (const auto& [key, value] : columnCache_) {
      if (key == shape) return value;
    }
    if (columnCache_.size() >= kColumnCacheSize) columnCache_.pop_front();
    Eigen::MatrixXd a = shape.varies() ? varyingLobeColumns(shape) : constantLobeColumns(shape);
    columnCache_.emplace_back(shape, std::move(a));
    return columnCache_.back().second;
  }

  Eigen::MatrixXd constantLobeColumns(const Shape& shape) const {
    const auto n = static_cast<Eigen::Index>(data_.rows.size());
    Eigen::MatrixXd a(n, columns(shape));
    const double exponent = std::exp(shape.logExponent);
    const double norm = phongNormalization(exponent);
    if (shape.halfVector) {
      a.col(0) = (norm * (exponent * factors_.logCosHalf).exp() * factors_.halfScale).matrix();
      a.col(1) = (a.col(0).array() * factors_.schlick).matrix();
    } else if (shape.cxy == -1.0) {
      a.col(0) = (norm * (exponent * factors_.logCosMirror).exp()).matrix();
    } else {
      for (Eigen::Index i = 0; i < n; ++i) {
        a(i, 0) = normalizedLobe(1.0, exponent, data_.rows[static_cast<std::size_t>(i)].geometry.cosine(shape.cxy));
      }
    }
    return a;
  }

  // The same with n(t) and the gain g(t) blended per row (geometricBlend of brdf/lobes.hpp): the
  // first column is g(t) times the lobe of unit weight, a half-vector lobe's second (C_F) has no gain.
  Eigen::MatrixXd varyingLobeColumns(const Shape& shape) const {
    const auto n = static_cast<Eigen::Index>(data_.rows.size());
    const Eigen::ArrayXd logExponent = shape.logExponent + factors_.bernstein.col(0) * shape.logExponentOffset[0] +
                                       factors_.bernstein.col(1) * shape.logExponentOffset[1];
    const Eigen::ArrayXd gain =
        (factors_.bernstein.col(0) * shape.logGain[0] + factors_.bernstein.col(1) * shape.logGain[1]).exp();
    const Eigen::ArrayXd exponent = logExponent.exp();
    const Eigen::ArrayXd norm = (exponent + 2.0) / (2.0 * std::numbers::pi);
    Eigen::MatrixXd a(n, columns(shape));
    if (shape.halfVector) {
      const Eigen::ArrayXd lobe = norm * (exponent * factors_.logCosHalf).exp() * factors_.halfScale;
      a.col(0) = (gain * lobe).matrix();
      a.col(1) = (lobe * factors_.schlick).matrix();
    } else if (shape.cxy == -1.0) {
      a.col(0) = (gain * norm * (exponent * factors_.logCosMirror).exp()).matrix();
    } else {
      for (Eigen::Index i = 0; i < n; ++i) {
        a(i, 0) = gain[i] *
                  normalizedLobe(1.0, exponent[i], data_.rows[static_cast<std::size_t>(i)].geometry.cosine(shape.cxy));
      }
    }
    return a;
  }

  // One channel's model at coefficients x: f = max(A x, 0), residuals r_i and their sum of squares.
  struct ChannelState {
    Eigen::VectorXd x;
    Eigen::ArrayXd f, r;
    double objective = 0.0;
  };

  ChannelState evaluate(const Eigen::MatrixXd& a, int channel, Eigen::VectorXd x) const {
    ChannelState state{std::move(x), {}, {}, 0.0};
    state.f = (a * state.x).array().max(0.0);
    state.r = log1p(data_.cosIn.array() * state.f).col(0) - data_.logTarget.col(channel).array();
    state.objective = state.r.square().sum();
    return state;
  }

  // Coefficients of one channel: a weighted NNLS linearised at the data, then up to `steps`
  // Gauss-Newton steps (each an NNLS of the residual linearised at the current model) with step
  // halving, until a step gains less than 1e-9 of the objective.
  ChannelState solveChannel(const Eigen::MatrixXd& a, int channel, int steps) const {
    const Eigen::ArrayXd& cosIn = data_.cosIn.array();
    // d r / d f = cos / (1 + cos f): at the data first, then at the current model.
    Eigen::ArrayXd omega = cosIn / (1.0 + cosIn * data_.measured.col(channel).array());
    auto weightedNnls = [&](const Eigen::ArrayXd& target) {
      return nonNegativeLeastSquares(weightedGram(a, omega), a.transpose() * (omega.square() * target).matrix());
    };
    ChannelState current = evaluate(a, channel, weightedNnls(data_.measured.col(channel).array()));
    for (int step = 0; step < steps; ++step) {
      omega = cosIn / (1.0 + cosIn * current.f);
      const Eigen::VectorXd proposal = weightedNnls(current.f - current.r / omega);
      bool improved = false;
      for (double alpha = 1.0; alpha > 0.1; alpha *= 0.5) {
        ChannelState trial = evaluate(a, channel, current.x + alpha * (proposal - current.x));
        if (trial.objective < current.objective) {
          improved = current.objective - trial.objective > 1e-9 * trial.objective;
          current = std::move(trial);
          break;
        }
      }
      if (!improved) break;
    }
    return current;
  }

  // The objective the shape search minimises: the log error summed over the searched channels,
  // of each channel's weights by the NNLS linearised at the data (solveChannel's first step; its
  // Gauss-Newton steps change which shapes win too little to pay for themselves, docs/fitting.md).
  // Every channel's normal equations at once: G_s = A^T diag(w_s) A from the products of column
  // pairs, one matrix product (searched channels x column pairs) for all of them.
  double searchObjective(const std::vector<Shape>& shapes) {
    ++evaluations;
    if (!admissible(shapes)) return HUGE_VAL;
    const Eigen::MatrixXd a = design(shapes);
    const Eigen::Index p = a.cols();
    pairs_.resize(a.rows(), p * (p + 1) / 2);
    for (Eigen::Index j = 0, m = 0; j < p; ++j) {
      for (Eigen::Index k = 0; k <= j; ++k, ++m) pairs_.col(m) = a.col(j).cwiseProduct(a.col(k));
    }
    const Eigen::MatrixXd grams = searchWeights_.transpose() * pairs_;  // searched x column pairs
    // Products this small cost less element by element than through the blocked kernel.
    const Eigen::MatrixXd rhs = searchWeightedTargets_.transpose().lazyProduct(a);  // searched x p
    Eigen::MatrixXd x(p, grams.rows());
    Eigen::MatrixXd gram(p, p);
    for (Eigen::Index s = 0; s < grams.rows(); ++s) {
      for (Eigen::Index j = 0, m = 0; j < p; ++j) {
        for (Eigen::Index k = 0; k <= j; ++k, ++m) gram(j, k) = gram(k, j) = grams(s, m);
      }
      x.col(s) = nonNegativeLeastSquares(gram, rhs.row(s).transpose());
    }
    const Eigen::ArrayXXd f = a.lazyProduct(x).array().max(0.0);
    return (log1p(f.colwise() * data_.cosIn.array()) - searchLogTargets_.array()).square().sum() + penalty(shapes);
  }

  // ln(1 + v) elementwise through Eigen's vectorised log: ln(u) v / (u - 1), u = 1 + v, exact
  // to a few ulps (Goldberg 1991, "What every computer scientist should know about
  // floating-point arithmetic", theorem 4); v where u rounds to 1.
  template <class Derived>
  static Eigen::ArrayXXd log1p(const Eigen::ArrayBase<Derived>& v) {
    const Eigen::ArrayXXd u = 1.0 + v;
    const Eigen::ArrayXXd product = u.log() * v / (u - 1.0);  // vectorised here; select() is not
    return (u == 1.0).select(v, product);
  }

  // The prior on varying shapes: varyingPenalty_ (SharedFitConfig::varyingPrior times the constant
  // fit's objective) times the squared offsets of ln n and ln g from their values at the most normal
  // view (0 for constant lobes).
  double penalty(const std::vector<Shape>& shapes) const {
    double sum = 0.0;
    for (const auto& s : shapes) {
      for (std::size_t j = 0; j < 2; ++j)
        sum += s.logExponentOffset[j] * s.logExponentOffset[j] + s.logGain[j] * s.logGain[j];
    }
    return varyingPenalty_ * sum;
  }

  bool admissible(const std::vector<Shape>& shapes) const {
    const double low = std::log(kMinLobeExponent), high = std::log(config_.maxExponent);
    for (const auto& s : shapes) {
      for (int j = 0; j <= kVaryingDegree; ++j) {
        const double logN = std::log(s.exponentAt(j));
        if (logN < low || logN > high) return false;
        if (s.exponentAt(j) * std::log(std::max(1.0, std::abs(s.cxy))) > kMaxLobeGrowthLog) return false;
      }
      if (std::abs(s.cxy) > kMaxFitCxy) return false;
      if (std::abs(s.logGain[0]) > kMaxLogGain || std::abs(s.logGain[1]) > kMaxLogGain) return false;
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
      for (double n = 2.0; n <= config_.maxExponent * 1.0001; n *= kGreedyExponentFactor) {
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

  // The coordinates of a lobe's shape the compass search moves: ln n, then c_xy (Lafortune lobes),
  // then the offsets of ln n and ln g at t = 0 and 1 (varying lobes).
  std::vector<double*> coordinates(Shape& shape) const {
    std::vector<double*> out{&shape.logExponent};
    if (config_.lafortune && !shape.halfVector) out.push_back(&shape.cxy);
    if (searchVarying_) {
      for (std::size_t j = 0; j < 2; ++j) out.push_back(&shape.logExponentOffset[j]);
      for (std::size_t j = 0; j < 2; ++j) out.push_back(&shape.logGain[j]);
    }
    return out;
  }

  // Compass search on the coordinates of every lobe (steps in c_xy are 0.2 / 0.35 of those in logarithms).
  std::vector<Shape> refine(std::vector<Shape> shapes) {
    double value = searchObjective(shapes);
    double logStep = 0.35;
    const int budget = evaluations + (searchVarying_ ? config_.maxVaryingEvaluations : config_.maxEvaluations);
    while (logStep > kFinalLogStep && evaluations < budget) {
      bool improved = false;
      for (std::size_t k = 0; k < shapes.size(); ++k) {
        const std::size_t count = coordinates(shapes[k]).size();
        for (std::size_t coordinate = 0; coordinate < count; ++coordinate) {
          for (double sign : {1.0, -1.0}) {
            std::vector<Shape> trial = shapes;
            double* moved = coordinates(trial[k])[coordinate];
            *moved += sign * (moved == &trial[k].cxy ? logStep * (0.2 / 0.35) : logStep);
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
      if (!improved) logStep *= 0.5;
    }
    return shapes;
  }

  std::vector<Shape> fitShapes() {
    std::vector<Shape> shapes;
    for (const Lobe& lobe : config_.startLobes) {
      if (static_cast<int>(shapes.size()) == config_.lobes) break;
      shapes.push_back(startShape(lobe));
    }
    // Constant shapes first (greedily, lobe by lobe), then, for varying lobes, every coordinate
    // from there: the constant fit is a good start that a varying one can only improve on.
    const bool startVaries = std::any_of(shapes.begin(), shapes.end(), [](const Shape& s) { return s.varies(); });
    searchVarying_ = startVaries;
    for (int k = static_cast<int>(shapes.size()); k < config_.lobes; ++k) shapes = refine(withNewLobe(shapes));
    if (config_.varying && !startVaries) {
      varyingPenalty_ = config_.varyingPrior * searchObjective(shapes);
      searchVarying_ = true;
      shapes = refine(std::move(shapes));
    }
    return shapes;
  }

  // A warm start's lobe as a shape: constant, or the exponent and weight ratios of a varying lobe
  // (its weights' profile is shared by every channel, so the first channel's serves).
  Shape startShape(const Lobe& lobe) const {
    Shape shape{std::log(lobe.exponent.back()), lobe.halfVector ? -1.0 : lobe.cxy, lobe.halfVector};
    if (!config_.varying || lobe.exponent.size() != 3 || lobe.weight.size() != 3) return shape;
    for (std::size_t j = 0; j < 2; ++j) {
      shape.logExponentOffset[j] = std::log(lobe.exponent[j] / lobe.exponent[2]);
      shape.logGain[j] = std::clamp(std::log(lobe.weight[j] / lobe.weight[2]), -kMaxLogGain, kMaxLogGain);
    }
    return shape;
  }

  const Data& data() const { return data_; }
  int evaluations = 0;

 private:
  // A^T diag(omega^2) A, column pair by column pair (a few columns: cheaper than a general product).
  static Eigen::MatrixXd weightedGram(const Eigen::MatrixXd& a, const Eigen::ArrayXd& omega) {
    const Eigen::ArrayXd w2 = omega.square();
    const Eigen::Index p = a.cols();
    Eigen::MatrixXd gram(p, p);
    for (Eigen::Index j = 0; j < p; ++j) {
      const Eigen::ArrayXd weighted = w2 * a.col(j).array();
      for (Eigen::Index k = 0; k <= j; ++k) gram(j, k) = gram(k, j) = (weighted * a.col(k).array()).sum();
    }
    return gram;
  }

  static constexpr std::size_t kColumnCacheSize = 16;
  // The greedy grid of a new lobe's exponent (2, 8, 32, ...; the compass search walks from there)
  // and the compass search's last step in ln n (1 %); docs/fitting.md has what other values scored.
  static constexpr double kGreedyExponentFactor = 4.0;
  static constexpr double kFinalLogStep = 0.01;
  // Largest |c_xy| the search takes (the model allows kMaxLobeCxy): a bound as a prior, since free
  // c_xy up to 8 fitted lobes that grow steeply towards grazing, and two such lobes predicted held-out
  // rows worse than a Lambertian fit (docs/fitting.md).
  static constexpr double kMaxFitCxy = 2.0;
  // Largest |ln g| of a varying lobe's gain at t = 0 and 1: a factor of 1e4 either way.
  static constexpr double kMaxLogGain = 9.2;

  Data data_;
  RowFactors factors_;
  SharedFitConfig config_;
  Eigen::MatrixXd searchWeights_;          // rows x searched channels: omega^2 at the data
  Eigen::MatrixXd searchWeightedTargets_;  // omega^2 f
  Eigen::MatrixXd searchLogTargets_;       // ln(1 + cos theta_i f)
  std::deque<std::pair<Shape, Eigen::MatrixXd>> columnCache_;
  Eigen::MatrixXd pairs_;  // rows x column pairs: products of the design's columns (searchObjective)
  std::vector<int> search_;
  bool searchVarying_ = false;  // the compass search moves the varying coordinates too
  double varyingPenalty_ = 0.0;
};

constexpr double kMinVaryingWeight = 1e-12;

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
  SharedFitter fitter(std::move(data), config, range);
  const std::vector<Shape> shapes = fitter.fitShapes();
  const Eigen::MatrixXd a = fitter.design(shapes);

  SharedFitOutcome outcome;
  outcome.rows = used.size();
  outcome.model.elevation = config.varying ? LobeElevation::Varying : LobeElevation::Constant;
  outcome.model.minCos = range.minCos;
  outcome.model.maxCos = range.maxCos;
  if (table.kind == ChannelKind::Spectral) outcome.model.wavelengthsNm = table.wavelengthsNm;
  for (Eigen::Index c = 0; c < channels; ++c) {
    const auto solved = fitter.solveChannel(a, static_cast<int>(c), 8);
    const Eigen::VectorXd& x = solved.x;
    outcome.objective += solved.objective;
    LobeChannel channel;
    channel.name = static_cast<std::size_t>(c) < table.channelNames.size()
                       ? table.channelNames[static_cast<std::size_t>(c)]
                       : std::to_string(c);
    channel.diffuse = x[0];
    Eigen::Index column = 1;
    for (const auto& shape : shapes) {
      Lobe lobe;
      for (int j = config.varying ? 0 : kVaryingDegree; j <= kVaryingDegree; ++j) {
        // A varying model's weights must be > 0 (geometric blend): an NNLS zero becomes 1e-12.
        lobe.weight.push_back(config.varying ? std::max(x[column] * shape.gainAt(j), kMinVaryingWeight) : x[column]);
        lobe.exponent.push_back(std::clamp(shape.exponentAt(j), kMinLobeExponent, kMaxLobeExponent));
      }
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
