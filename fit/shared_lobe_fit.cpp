#include "shared_lobe_fit.hpp"

#include "color_profile_terms.hpp"

#include <brdfbake/core/error.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>

namespace brdfbake::detail {

namespace {
// nonNegativeLeastSquares with its vectors and matrices of at most MaxP rows held on the stack (MaxP =
// Eigen::Dynamic: on the heap): the shape search solves a few small problems per trial, and their
// allocations were a tenth of its time.
template <int MaxP>
Eigen::VectorXd nonNegativeLeastSquaresOf(const Eigen::MatrixXd& gram, const Eigen::Ref<const Eigen::VectorXd>& rhs) {
  using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, MaxP, 1>;
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, MaxP, MaxP>;
  const Eigen::Index p = rhs.size();
  Vector x = Vector::Zero(p);
  using Flags = Eigen::Matrix<bool, Eigen::Dynamic, 1, 0, MaxP, 1>;
  Flags passive = Flags::Constant(p, false);
  const double scale = std::max(gram.diagonal().maxCoeff(), 1e-300);
  const double tolerance = 1e-13 * std::max(rhs.cwiseAbs().maxCoeff(), 1e-300);
  // The unconstrained least-squares solution on the passive set (others 0), a tiny ridge against
  // columns that are (nearly) dependent.
  auto solvePassive = [&] {
    Eigen::Matrix<Eigen::Index, Eigen::Dynamic, 1, 0, MaxP, 1> index(p);
    Eigen::Index m = 0;
    for (Eigen::Index j = 0; j < p; ++j)
      if (passive[j]) index[m++] = j;
    Matrix g(m, m);
    Vector h(m);
    for (Eigen::Index a = 0; a < m; ++a) {
      h[a] = rhs[index[a]];
      for (Eigen::Index b = 0; b < m; ++b) g(a, b) = gram(index[a], index[b]);
      g(a, a) += 1e-12 * std::max(gram(index[a], index[a]), 1e-300);
    }
    const Vector s = Eigen::LDLT<Matrix>(g).solve(h);
    Vector z = Vector::Zero(p);
    for (Eigen::Index a = 0; a < m; ++a) z[index[a]] = s[a];
    return z;
  };
  for (int outer = 0; outer < 3 * p + 3; ++outer) {
    Vector w = rhs;
    w.noalias() -= gram * x;
    Eigen::Index best = -1;
    for (Eigen::Index j = 0; j < p; ++j) {
      if (!passive[j] && w[j] > tolerance && (best < 0 || w[j] > w[best])) best = j;
    }
    if (best < 0) break;
    passive[best] = true;
    for (int inner = 0; inner < 3 * p + 3; ++inner) {
      const Vector z = solvePassive();
      bool feasible = true;
      double alpha = 1.0;
      for (Eigen::Index j = 0; j < p; ++j) {
        if (passive[j] && z[j] <= 0.0) {
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
        if (passive[j] && x[j] <= 1e-15 * scale) {
          passive[j] = false;
          x[j] = 0.0;
        }
      }
    }
  }
  return x.cwiseMax(0.0);
}
}  // namespace

Eigen::VectorXd nonNegativeLeastSquares(const Eigen::MatrixXd& gram, const Eigen::Ref<const Eigen::VectorXd>& rhs) {
  if (rhs.size() <= 8) return nonNegativeLeastSquaresOf<8>(gram, rhs);
  if (rhs.size() <= 32) return nonNegativeLeastSquaresOf<32>(gram, rhs);
  return nonNegativeLeastSquaresOf<Eigen::Dynamic>(gram, rhs);
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

// Equal to 1e-12 (relative): a warm start's shapes come back through exp and log.
bool nearlyEqual(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max({1.0, std::abs(a), std::abs(b)}); }

bool nearlyEqual(const std::vector<Shape>& a, const std::vector<Shape>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const Shape &x = a[k], &y = b[k];
    if (x.halfVector != y.halfVector || !nearlyEqual(x.logExponent, y.logExponent) || !nearlyEqual(x.cxy, y.cxy))
      return false;
    for (std::size_t j = 0; j < 2; ++j) {
      if (!nearlyEqual(x.logExponentOffset[j], y.logExponentOffset[j]) || !nearlyEqual(x.logGain[j], y.logGain[j]))
        return false;
    }
  }
  return true;
}

// What a compass search depends on besides its start and the table.
struct SearchSettings {
  bool varying;    // the varying coordinates move too
  double penalty;  // the prior's weight on them
  bool lafortune;  // c_xy moves
  double maxExponent;
  int budget;  // shape trials
  int searchChannels;

  bool matches(const SearchSettings& o) const {
    return varying == o.varying && nearlyEqual(penalty, o.penalty) && lafortune == o.lafortune &&
           maxExponent == o.maxExponent && budget == o.budget && searchChannels == o.searchChannels;
  }
};

}  // namespace

class ShapeSearches {
 public:
  const std::vector<Shape>* find(const SearchSettings& settings, const std::vector<Shape>& start) const {
    for (const Entry& e : entries_) {
      if (e.settings.matches(settings) && nearlyEqual(e.start, start)) return &e.result;
    }
    return nullptr;
  }
  void add(const SearchSettings& settings, std::vector<Shape> start, std::vector<Shape> result) {
    entries_.push_back({settings, std::move(start), std::move(result)});
  }

 private:
  struct Entry {
    SearchSettings settings;
    std::vector<Shape> start, result;
  };
  std::vector<Entry> entries_;
};

std::shared_ptr<ShapeSearches> makeShapeSearches() { return std::make_shared<ShapeSearches>(); }

namespace {

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
  Eigen::ArrayXd horizontal;    // l_x v_x + l_y v_y and l_z v_z: a Lafortune lobe's cosine is
  Eigen::ArrayXd vertical;      // c_xy horizontal + vertical (LobeGeometry::cosine)
  Eigen::ArrayXd logCosHalf;    // ln n.h
  Eigen::ArrayXd halfScale;     // 1 / (4 (n.l)(n.v)), 0 below the horizon
  Eigen::ArrayXd schlick;       // (1 - l.h)^5
  // Varying lobes: the view elevations' quadratic Bernstein weights (distinct elevations x 3) and each
  // row's elevation, so that n(t) and g(t) cost an exp per elevation, not per row (a Cornell table
  // has ten).
  Eigen::ArrayXXd bernstein;
  std::vector<Eigen::Index> elevation;

  RowFactors(const std::vector<Row>& rows, const LobeModel& range) {
    const auto n = static_cast<Eigen::Index>(rows.size());
    logCosMirror.resize(n), logCosHalf.resize(n), halfScale.resize(n), schlick.resize(n);
    horizontal.resize(n), vertical.resize(n);
    std::map<double, Eigen::Index> elevations;
    for (Eigen::Index i = 0; i < n; ++i) {
      const LobeGeometry& g = rows[static_cast<std::size_t>(i)].geometry;
      logCosMirror[i] = logPositive(g.cosine(-1.0));
      horizontal[i] = g.horizontal, vertical[i] = g.vertical;
      const bool above = g.lightZ > 0.0 && g.viewZ > 0.0;
      logCosHalf[i] = above ? logPositive(g.cosHalf()) : -HUGE_VAL;
      halfScale[i] = above ? 0.25 / (g.lightZ * g.viewZ) : 0.0;
      schlick[i] = g.schlick();
      const double t = range.elevationCoordinate(g.viewZ);
      elevation.push_back(elevations.try_emplace(t, static_cast<Eigen::Index>(elevations.size())).first->second);
    }
    bernstein.resize(static_cast<Eigen::Index>(elevations.size()), kVaryingDegree + 1);
    for (const auto& [t, index] : elevations) {
      double weights[kVaryingDegree + 1];
      bernsteinWeights(kVaryingDegree + 1, t, weights);
      for (int j = 0; j <= kVaryingDegree; ++j) bernstein(index, j) = weights[j];
    }
  }
  static double logPositive(double c) { return c > 0.0 ? std::log(c) : -HUGE_VAL; }
};

// A small cache of recently used values by key (linear search): an entry used by the current
// evaluation is never the one evicted, so references handed out stay valid while the cache holds
// more entries than one evaluation uses.
template <class Key, class Value>
class RecentCache {
 public:
  explicit RecentCache(std::size_t capacity) : capacity_(capacity) { entries_.reserve(capacity); }
  const Value* find(const Key& key) {
    for (Entry& e : entries_) {
      if (e.key == key) {
        e.used = ++clock_;
        return &e.value;
      }
    }
    return nullptr;
  }
  const Value& insert(const Key& key, Value value) {
    if (entries_.size() < capacity_) {
      entries_.push_back({key, std::move(value), ++clock_});
      return entries_.back().value;
    }
    Entry& oldest = *std::min_element(entries_.begin(), entries_.end(),
                                      [](const Entry& a, const Entry& b) { return a.used < b.used; });
    oldest = {key, std::move(value), ++clock_};
    return oldest.value;
  }

 private:
  struct Entry {
    Key key;
    Value value;
    std::uint64_t used;
  };
  std::vector<Entry> entries_;
  std::size_t capacity_;
  std::uint64_t clock_ = 0;
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
      searchLogTargets_.col(s) = data_.logTarget.col(search_[static_cast<std::size_t>(s)]).array().cast<float>();
    }
    diffuseGram_ = searchWeights_.colwise().sum().transpose() / (std::numbers::pi * std::numbers::pi);
    diffuseRhs_ = searchWeightedTargets_.colwise().sum().transpose() / std::numbers::pi;
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
      a.middleCols(column, columns(shape)) = lobeColumnsOf(shape, Precision::Double);
      column += columns(shape);
    }
    return a;
  }

  // What one lobe adds to the search's normal equations, kept for recent shapes: a compass step
  // changes one lobe, so the others' columns and products come from here.
  struct LobeTerms {
    Eigen::MatrixXd columns;  // rows x c (c = columns(shape)), powers in single precision
    Eigen::MatrixXd self;     // searched x c(c+1)/2: sum_i w_s,i a_i,j a_i,k over the lobe's column pairs
    Eigen::MatrixXd diffuse;  // searched x c: the same with the diffuse column
    Eigen::MatrixXd rhs;      // searched x c: sum_i w_s,i f_s,i a_i,j
  };

  const LobeTerms& lobeTerms(const Shape& shape) {
    if (const LobeTerms* hit = termsCache_.find(shape)) return *hit;
    LobeTerms t;
    t.columns = lobeColumnsOf(shape, Precision::Single);
    const Eigen::Index c = t.columns.cols();
    t.self.resize(searchWeights_.cols(), c * (c + 1) / 2);
    for (Eigen::Index j = 0, m = 0; j < c; ++j) {
      for (Eigen::Index k = 0; k <= j; ++k, ++m)
        t.self.col(m) = searchWeights_.transpose() * t.columns.col(j).cwiseProduct(t.columns.col(k));
    }
    // Products this small cost less element by element than through the blocked kernel.
    t.diffuse = searchWeights_.transpose().lazyProduct(t.columns) / std::numbers::pi;
    t.rhs = searchWeightedTargets_.transpose().lazyProduct(t.columns);
    return termsCache_.insert(shape, std::move(t));
  }

  // Products of two lobes' columns (searched x c_j c_k, column b * c_j + a for columns a of j, b of k).
  const Eigen::MatrixXd& crossTerms(const Shape& j, const LobeTerms& tj, const Shape& k, const LobeTerms& tk) {
    const std::pair<Shape, Shape> key{j, k};
    if (const Eigen::MatrixXd* hit = crossCache_.find(key)) return *hit;
    const Eigen::Index cj = tj.columns.cols(), ck = tk.columns.cols();
    Eigen::MatrixXd grams(searchWeights_.cols(), cj * ck);
    for (Eigen::Index b = 0; b < ck; ++b) {
      for (Eigen::Index a = 0; a < cj; ++a)
        grams.col(b * cj + a) = searchWeights_.transpose() * tj.columns.col(a).cwiseProduct(tk.columns.col(b));
    }
    return crossCache_.insert(key, std::move(grams));
  }

  // The precision of the search's exp and log. Single (float) took a third less CPU in a varying
  // three-lobe search; its relative error (1e-7) is far below the differences between shapes the
  // search acts on (the same models chosen on seven tables, docs/fitting.md). The kept fit's design and
  // weights are in double.
  enum class Precision { Single, Double };

  // e^x. In single precision the casts keep the expression scalar, so each element is one call of
  // libm's expf: Eigen's float packets (SSE2) measured 10 % slower over the whole search, libm's
  // double exp 12 % slower.
  static Eigen::ArrayXd exponential(const Eigen::ArrayXd& x, Precision precision) {
    if (precision == Precision::Single) return x.cast<float>().exp().cast<double>();
    return x.exp();
  }

  // A lobe's columns, normalizedLobe and halfVectorLobe of brdf/lobes.hpp with c^n taken as exp(n ln c)
  // from the row factors, with n(t) and the gain g(t) per row (geometricBlend of brdf/lobes.hpp; one
  // value for a constant lobe): the first column is g(t) times the lobe of unit weight, a half-vector
  // lobe's second (C_F) has no gain.
  Eigen::MatrixXd lobeColumnsOf(const Shape& shape, Precision precision) const {
    const auto n = static_cast<Eigen::Index>(data_.rows.size());
    Eigen::ArrayXd exponent, gain;
    if (shape.varies()) {
      const Eigen::ArrayXd b0 = factors_.bernstein.col(0), b1 = factors_.bernstein.col(1);
      const Eigen::ArrayXd byElevation =
          (shape.logExponent + b0 * shape.logExponentOffset[0] + b1 * shape.logExponentOffset[1]).exp();
      const Eigen::ArrayXd gainByElevation = (b0 * shape.logGain[0] + b1 * shape.logGain[1]).exp();
      exponent = byElevation(factors_.elevation);
      gain = gainByElevation(factors_.elevation);
    } else {
      exponent.setConstant(n, std::exp(shape.logExponent));
      gain.setOnes(n);
    }
    const Eigen::ArrayXd norm = (exponent + 2.0) / (2.0 * std::numbers::pi);  // phongNormalization
    Eigen::MatrixXd a(n, columns(shape));
    if (shape.halfVector) {
      const Eigen::ArrayXd lobe = norm * exponential(exponent * factors_.logCosHalf, precision) * factors_.halfScale;
      a.col(0) = (gain * lobe).matrix();
      a.col(1) = (lobe * factors_.schlick).matrix();
    } else if (shape.cxy == -1.0) {
      a.col(0) = (gain * norm * exponential(exponent * factors_.logCosMirror, precision)).matrix();
    } else {  // Lafortune: max(0, c)^n as exp(n ln c), ln c = -inf where c <= 0
      const Eigen::ArrayXd cosine = shape.cxy * factors_.horizontal + factors_.vertical;
      const Eigen::ArrayXd logCos = (cosine > 0.0).select(cosine.max(1e-300).log(), -HUGE_VAL);
      a.col(0) = (gain * norm * exponential(exponent * logCos, precision)).matrix();
    }
    return a;
  }

  // Residuals ln(1 + cos theta_i f) - ln(1 + cos theta_i f_measured) of one column of model values,
  // with ln(1 + v) taken as ln of the rounded 1 + v: its absolute error (1e-16) is far below any
  // residual that matters, and a column expression stays one vectorised pass (no log1p in Eigen's
  // packets, and a colwise broadcast would make the whole expression scalar).
  template <class Values, class Targets>
  auto residuals(const Values& f, const Targets& logTarget) const {
    return (1.0 + data_.cosIn.array() * f).log() - logTarget;
  }

  // The search's residuals of searched channel s from its model values f (negative ones taken as 0),
  // with ln in single precision (Precision) on a plain float array, so that it runs in Eigen's packets
  // (libm's logf per element measured 16 % slower over the whole search).
  Eigen::ArrayXf searchResiduals(const Eigen::ArrayXd& f, Eigen::Index s) const {
    const Eigen::ArrayXf onePlus = (1.0 + data_.cosIn.array() * f.max(0.0)).cast<float>();
    return onePlus.log() - searchLogTargets_.col(s);
  }

  // Every channel's model at coefficients x (p x channels): f = max(A x, 0), residuals r and
  // each channel's sum of squares.
  struct Channels {
    Eigen::MatrixXd x;
    Eigen::ArrayXXd f, r;
    Eigen::ArrayXd objective;
  };

  Channels evaluate(const Eigen::MatrixXd& a, Eigen::MatrixXd x) const {
    Channels state{std::move(x), {}, {}, {}};
    state.f = (a * state.x).array().max(0.0);
    state.r.resize(state.f.rows(), state.f.cols());
    for (Eigen::Index c = 0; c < state.f.cols(); ++c)
      state.r.col(c) = residuals(state.f.col(c), data_.logTarget.col(c).array());
    state.objective = state.r.square().colwise().sum().transpose();
    return state;
  }

  // Each channel's NNLS of A x ~ target weighted by omega^2 (rows x channels), the normal
  // equations of every channel from one product with the column pairs of A. Only the channels in
  // `solved` are solved (their columns of x; the others' are left as they are in x).
  void weightedNnls(const Eigen::MatrixXd& a, const Eigen::MatrixXd& pairs, const Eigen::ArrayXXd& omega,
                    const Eigen::ArrayXXd& target, const std::vector<Eigen::Index>& solved, Eigen::MatrixXd& x) const {
    const auto n = static_cast<Eigen::Index>(solved.size());
    Eigen::MatrixXd w(omega.rows(), n), weightedTarget(omega.rows(), n);
    for (Eigen::Index i = 0; i < n; ++i) {
      w.col(i) = omega.col(solved[i]).square().matrix();
      weightedTarget.col(i) = (w.col(i).array() * target.col(solved[i])).matrix();
    }
    const Eigen::MatrixXd grams = w.transpose() * pairs;  // solved channels x column pairs
    const Eigen::MatrixXd rhs = a.transpose() * weightedTarget;
    const Eigen::Index p = a.cols();
    Eigen::MatrixXd gram(p, p);
    for (Eigen::Index i = 0; i < n; ++i) {
      for (Eigen::Index j = 0, m = 0; j < p; ++j) {
        for (Eigen::Index k = 0; k <= j; ++k, ++m) gram(j, k) = gram(k, j) = grams(i, m);
      }
      x.col(solved[i]) = nonNegativeLeastSquares(gram, rhs.col(i));
    }
  }

  // Every channel's coefficients: a weighted NNLS linearised at the data, then up to `steps`
  // Gauss-Newton steps (each an NNLS of the residual linearised at the current model) with step
  // halving; a channel stops when a step gains less than 1e-9 of its objective.
  Channels solveChannels(const Eigen::MatrixXd& design, int steps) const {
    // Entries below 1e-150 (a sharp lobe far from its axis) are 0 to the fit but not to the
    // processor: the products of two of them in the normal equations are subnormal numbers, which
    // took a profiled fit of Mystique's 31 wavelengths about 3 times as long.
    const Eigen::MatrixXd a = (design.array().abs() < 1e-150).select(0.0, design);
    const Eigen::Index p = a.cols();
    Eigen::MatrixXd pairs(a.rows(), p * (p + 1) / 2);
    for (Eigen::Index j = 0, m = 0; j < p; ++j) {
      for (Eigen::Index k = 0; k <= j; ++k, ++m) pairs.col(m) = a.col(j).cwiseProduct(a.col(k));
    }
    // d r / d f = cos / (1 + cos f): at the data first, then at the current model.
    auto omegaAt = [&](const Eigen::ArrayXXd& f) -> Eigen::ArrayXXd {
      return (1.0 + f.colwise() * data_.cosIn.array()).inverse().colwise() * data_.cosIn.array();
    };
    const Eigen::ArrayXXd measured = data_.measured.array();
    std::vector<Eigen::Index> all(static_cast<std::size_t>(measured.cols()));
    std::iota(all.begin(), all.end(), Eigen::Index(0));
    Eigen::MatrixXd first(p, measured.cols());
    weightedNnls(a, pairs, omegaAt(measured), measured, all, first);
    Channels current = evaluate(a, std::move(first));
    std::vector<bool> active(static_cast<std::size_t>(measured.cols()), true);
    for (int step = 0; step < steps && std::count(active.begin(), active.end(), true) > 0; ++step) {
      // The channels still gaining are solved again; the others' proposal is where they are.
      std::vector<Eigen::Index> gaining;
      for (Eigen::Index c = 0; c < measured.cols(); ++c)
        if (active[static_cast<std::size_t>(c)]) gaining.push_back(c);
      const Eigen::ArrayXXd omega = omegaAt(current.f);
      Eigen::MatrixXd proposal = current.x;
      weightedNnls(a, pairs, omega, current.f - current.r / omega, gaining, proposal);
      std::vector<bool> pending = active;
      for (double alpha = 1.0; alpha > 0.1 && std::count(pending.begin(), pending.end(), true) > 0; alpha *= 0.5) {
        const Channels trial = evaluate(a, current.x + alpha * (proposal - current.x));
        for (Eigen::Index c = 0; c < measured.cols(); ++c) {
          const auto i = static_cast<std::size_t>(c);
          if (!pending[i] || !(trial.objective[c] < current.objective[c])) continue;
          active[i] = current.objective[c] - trial.objective[c] > 1e-9 * trial.objective[c];
          pending[i] = false;
          current.x.col(c) = trial.x.col(c), current.f.col(c) = trial.f.col(c), current.r.col(c) = trial.r.col(c);
          current.objective[c] = trial.objective[c];
        }
      }
      for (std::size_t i = 0; i < active.size(); ++i) active[i] = active[i] && !pending[i];
    }
    return current;
  }

  // The objective the shape search minimises: the log error summed over the searched channels,
  // of each channel's weights by the NNLS linearised at the data (solveChannels' first step; its
  // Gauss-Newton steps change which shapes win too little to pay for themselves, docs/fitting.md).
  // Every channel's normal equations G_s = A^T diag(w_s) A are put together from the products of
  // column pairs, cached per lobe and per pair of lobes (lobeTerms, crossTerms).
  double searchObjective(const std::vector<Shape>& shapes) {
    ++evaluations;
    if (!admissible(shapes)) return HUGE_VAL;
    // The buffers are the fitter's, reused from trial to trial (their allocations were a tenth of
    // this function's time).
    std::vector<const LobeTerms*>& terms = scratch_.terms;
    std::vector<Eigen::Index>& offsets = scratch_.offsets;  // each lobe's first column in the design
    terms.clear(), offsets.clear();
    Eigen::Index p = 1;
    for (const auto& shape : shapes) {
      terms.push_back(&lobeTerms(shape));
      offsets.push_back(p);
      p += columns(shape);
    }
    const Eigen::Index searched = searchWeights_.cols();
    std::vector<Eigen::MatrixXd>& grams = scratch_.grams;
    grams.resize(static_cast<std::size_t>(searched));
    for (auto& g : grams) g.resize(p, p);
    Eigen::MatrixXd& rhs = scratch_.rhs;
    rhs.resize(p, searched);
    for (Eigen::Index s = 0; s < searched; ++s) {
      grams[static_cast<std::size_t>(s)](0, 0) = diffuseGram_[s];
      rhs(0, s) = diffuseRhs_[s];
    }
    for (std::size_t k = 0; k < shapes.size(); ++k) {
      addLobeTerms(*terms[k], offsets[k], grams, rhs);
      for (std::size_t j = 0; j < k; ++j) {
        const Eigen::MatrixXd& cross = crossTerms(shapes[j], *terms[j], shapes[k], *terms[k]);
        const Eigen::Index cj = terms[j]->columns.cols(), ck = terms[k]->columns.cols();
        for (Eigen::Index s = 0; s < searched; ++s) {
          Eigen::MatrixXd& g = grams[static_cast<std::size_t>(s)];
          for (Eigen::Index b = 0; b < ck; ++b) {
            for (Eigen::Index a = 0; a < cj; ++a)
              g(offsets[k] + b, offsets[j] + a) = g(offsets[j] + a, offsets[k] + b) = cross(s, b * cj + a);
          }
        }
      }
    }
    Eigen::MatrixXd& x = scratch_.x;
    x.resize(p, searched);
    for (Eigen::Index s = 0; s < searched; ++s)
      x.col(s) = nonNegativeLeastSquares(grams[static_cast<std::size_t>(s)], rhs.col(s));
    // f = A x one channel and one column at a time: a lobe has one or two columns, too few for a product
    // over them to pay (this took 14 % less time than one lazyProduct per lobe).
    double sum = penalty(shapes);
    Eigen::ArrayXd& f = scratch_.f;
    f.resize(data_.cosIn.size());
    for (Eigen::Index s = 0; s < searched; ++s) {
      f.setConstant(x(0, s) / std::numbers::pi);
      for (std::size_t k = 0; k < shapes.size(); ++k) {
        for (Eigen::Index j = 0; j < terms[k]->columns.cols(); ++j)
          f += x(offsets[k] + j, s) * terms[k]->columns.col(j).array();
      }
      // Squared and summed in double, in packets: the cast in one expression with the sum made it one
      // scalar chain of additions, a seventh of this function's time.
      const Eigen::ArrayXd r = searchResiduals(f, s).cast<double>();
      sum += r.square().sum();
    }
    return sum;
  }

  // A lobe's own products (with itself and the diffuse column) into every channel's normal equations.
  static void addLobeTerms(const LobeTerms& t, Eigen::Index offset, std::vector<Eigen::MatrixXd>& grams,
                           Eigen::MatrixXd& rhs) {
    const Eigen::Index c = t.columns.cols();
    for (std::size_t s = 0; s < grams.size(); ++s) {
      Eigen::MatrixXd& g = grams[s];
      const auto si = static_cast<Eigen::Index>(s);
      for (Eigen::Index j = 0, m = 0; j < c; ++j) {
        g(offset + j, 0) = g(0, offset + j) = t.diffuse(si, j);
        rhs(offset + j, si) = t.rhs(si, j);
        for (Eigen::Index k = 0; k <= j; ++k, ++m)
          g(offset + j, offset + k) = g(offset + k, offset + j) = t.self(si, m);
      }
    }
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
      const double growth = std::log(std::max(1.0, std::abs(s.cxy)));
      for (int j = 0; j <= kVaryingDegree; ++j) {
        const double logN = s.logExponent + (j < 2 ? s.logExponentOffset[static_cast<std::size_t>(j)] : 0.0);
        if (logN < low || logN > high) return false;
        if (growth > 0.0 && std::exp(logN) * growth > kMaxLobeGrowthLog) return false;
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

  // refine, or the same search's result when another fit of this table ran it (SharedFitConfig::searches).
  std::vector<Shape> search(std::vector<Shape> shapes) {
    if (!config_.searches) return refine(std::move(shapes));
    const SearchSettings settings{searchVarying_,
                                  varyingPenalty_,
                                  config_.lafortune,
                                  config_.maxExponent,
                                  searchVarying_ ? config_.maxVaryingEvaluations : config_.maxEvaluations,
                                  config_.searchChannels};
    if (const auto* known = config_.searches->find(settings, shapes)) return *known;
    std::vector<Shape> result = refine(shapes);
    config_.searches->add(settings, std::move(shapes), result);
    return result;
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
    for (int k = static_cast<int>(shapes.size()); k < config_.lobes; ++k) shapes = search(withNewLobe(shapes));
    if (config_.varying && !startVaries) {
      varyingPenalty_ = config_.varyingPrior * searchObjective(shapes);
      searchVarying_ = true;
      shapes = search(std::move(shapes));
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
  // More than one evaluation uses (at most 6 lobes, 15 pairs of them), with room for the shapes a
  // compass search returns to.
  static constexpr std::size_t kTermsCacheSize = 16;
  static constexpr std::size_t kCrossCacheSize = 48;
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
  Eigen::ArrayXXf searchLogTargets_;       // ln(1 + cos theta_i f), single precision (Precision)
  RecentCache<Shape, LobeTerms> termsCache_{kTermsCacheSize};
  RecentCache<std::pair<Shape, Shape>, Eigen::MatrixXd> crossCache_{kCrossCacheSize};
  Eigen::VectorXd diffuseGram_;  // searched: sum_i w_s,i / pi^2
  Eigen::VectorXd diffuseRhs_;   // searched: sum_i w_s,i f_s,i / pi
  std::vector<int> search_;
  struct SearchScratch {  // searchObjective's buffers
    std::vector<const LobeTerms*> terms;
    std::vector<Eigen::Index> offsets;
    std::vector<Eigen::MatrixXd> grams;
    Eigen::MatrixXd rhs, x;
    Eigen::ArrayXd f;
  } scratch_;
  bool searchVarying_ = false;  // the compass search moves the varying coordinates too
  double varyingPenalty_ = 0.0;
};

constexpr double kMinVaryingWeight = 1e-12;

// One channel's diffuse term and lobes from its solution x (columns as SharedFitter::design, expanded
// by withColorProfiles with config.colorProfile: color_profile_terms.hpp).
LobeChannel channelOf(const Eigen::VectorXd& x, const std::vector<Shape>& shapes, const SharedFitConfig& config) {
  LobeChannel channel;
  const ProfiledTerm diffuse = profiledTerm(x, 0, config.colorProfile);
  channel.diffuse = diffuse.weight;
  channel.diffuseProfile = diffuse.profile;
  Eigen::Index column = 1;
  for (const auto& shape : shapes) {
    Lobe lobe;
    const ProfiledTerm weight = profiledTerm(x, column, config.colorProfile);
    for (int j = config.varying ? 0 : kVaryingDegree; j <= kVaryingDegree; ++j) {
      // A varying model's weights must be > 0 (geometric blend): an NNLS zero becomes 1e-12.
      lobe.weight.push_back(config.varying ? std::max(weight.weight * shape.gainAt(j), kMinVaryingWeight)
                                           : weight.weight);
      lobe.exponent.push_back(std::clamp(shape.exponentAt(j), kMinLobeExponent, kMaxLobeExponent));
    }
    lobe.weightProfile = weight.profile;
    lobe.cxy = shape.halfVector ? -1.0 : shape.cxy;
    lobe.halfVector = shape.halfVector;
    if (shape.halfVector) {
      const ProfiledTerm fresnel = profiledTerm(x, column + 1, config.colorProfile);
      lobe.fresnel = fresnel.weight;
      lobe.fresnelProfile = fresnel.profile;
    }
    column += SharedFitter::columns(shape);
    channel.lobes.push_back(std::move(lobe));
  }
  return channel;
}

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
  Eigen::MatrixXd a = fitter.design(shapes);
  if (config.colorProfile) {
    std::vector<double> coordinates;
    for (const Row& row : fitter.data().rows) coordinates.push_back(row.geometry.differenceCoordinate());
    a = withColorProfiles(a, coordinates);
  }

  SharedFitOutcome outcome;
  outcome.rows = used.size();
  outcome.model.elevation = config.varying ? LobeElevation::Varying : LobeElevation::Constant;
  outcome.model.colorProfile = config.colorProfile ? ColorProfile::DifferenceAngle : ColorProfile::None;
  outcome.model.minCos = range.minCos;
  outcome.model.maxCos = range.maxCos;
  if (table.kind == ChannelKind::Spectral) outcome.model.wavelengthsNm = table.wavelengthsNm;
  const auto solved = fitter.solveChannels(a, config.gaussNewtonSteps);
  outcome.objective = solved.objective.sum();
  for (Eigen::Index c = 0; c < channels; ++c) {
    LobeChannel channel = channelOf(solved.x.col(c), shapes, config);
    channel.name = table.channelName(static_cast<std::size_t>(c));
    outcome.model.channels.push_back(std::move(channel));
  }
  outcome.evaluations = fitter.evaluations;
  return outcome;
}

}  // namespace brdfbake::detail
