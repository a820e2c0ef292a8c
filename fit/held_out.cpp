#include <brdfbake/core/context.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/held_out.hpp>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <sstream>

namespace brdfbake {

void HeldOutOptions::validate() const {
  require(folds >= 2 && folds <= 20, "held-out: folds must be in 2..20");
  require(std::isfinite(minMirrorOffsetDegrees) && minMirrorOffsetDegrees >= 0.0 && minMirrorOffsetDegrees <= 90.0,
          "held-out: minMirrorOffsetDegrees must be in [0, 90]");
  for (double e : elevationsDegrees) {
    require(std::isfinite(e) && e >= 0.0 && e <= 90.0, "held-out: elevations must be in [0, 90] degrees");
  }
}

HeldOutSplit HeldOutReport::pooledElevations() const {
  HeldOutSplit pooled;
  pooled.name = "elevations held out";
  double fit = 0.0, lambert = 0.0;
  for (const auto& e : elevations) {
    fit += e.error * e.error * static_cast<double>(e.heldRows);
    lambert += e.lambertError * e.lambertError * static_cast<double>(e.heldRows);
    pooled.heldRows += e.heldRows;
  }
  if (pooled.heldRows > 0) {
    pooled.error = std::sqrt(fit / static_cast<double>(pooled.heldRows));
    pooled.lambertError = std::sqrt(lambert / static_cast<double>(pooled.heldRows));
  }
  return pooled;
}

double HeldOutReport::score() const {
  if (elevations.empty()) return kfold.ratio();
  return std::max(kfold.ratio(), pooledElevations().ratio());
}

double HeldOutReport::otherScore() const {
  if (elevations.empty()) return kfold.ratio();
  return std::min(kfold.ratio(), pooledElevations().ratio());
}

bool HeldOutReport::improvesOn(const HeldOutReport& other, double margin) const {
  const double worse = score(), otherWorse = other.score();
  if (worse < (1.0 - margin) * otherWorse) return true;
  return worse <= otherWorse && otherScore() < (1.0 - margin) * other.otherScore();
}

MeasuredTable tableRows(const MeasuredTable& table, const std::vector<std::size_t>& rows) {
  MeasuredTable out;
  out.kind = table.kind;
  out.channelNames = table.channelNames;
  out.wavelengthsNm = table.wavelengthsNm;
  out.sourceFile = table.sourceFile;
  out.format = table.format;
  out.header = table.header;
  out.notes = table.notes;
  out.values.resize(static_cast<Eigen::Index>(rows.size()), table.values.cols());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    require(rows[r] < table.size(), "tableRows: row out of range");
    out.angles.push_back(table.angles[rows[r]]);
    out.values.row(static_cast<Eigen::Index>(r)) = table.values.row(static_cast<Eigen::Index>(rows[r]));
  }
  return out;
}

double mirrorOffsetDegrees(const MeasuredTable& table, std::size_t row) {
  const Vec3 wi = table.incidentDirection(row), wo = table.outgoingDirection(row);
  const Vec3 mirror(-wi.x(), -wi.y(), wi.z());
  return degrees(std::acos(std::clamp(mirror.dot(wo), -1.0, 1.0)));
}

namespace {
double logTerm(double cosIn, double f) { return std::log1p(cosIn * std::max(f, 0.0)); }
double cosIncident(const MeasuredTable& table, std::size_t row) {
  const Vec3 wi = table.incidentDirection(row), wo = table.outgoingDirection(row);
  return wi.z() > 0.0 && wo.z() > 0.0 ? wi.z() : 0.0;
}
}  // namespace

LogErrorSum cosineLogError(const LobeModel& model, const MeasuredTable& table, const std::vector<std::size_t>& rows) {
  require(model.channelCount() == table.channelCount(),
          "held-out: the model and the table have different channel counts");
  // A varying model frozen once per view elevation (a Cornell table has ten), not per sample.
  std::map<double, LobeModel> frozen;
  auto atView = [&](double viewZ) -> const LobeModel& {
    if (model.elevation == LobeElevation::Constant || !(viewZ > 0.0)) return model;
    auto it = frozen.find(viewZ);
    if (it == frozen.end()) it = frozen.emplace(viewZ, model.atElevation(viewZ)).first;
    return it->second;
  };
  LogErrorSum sum;
  for (std::size_t i : rows) {
    const double c = cosIncident(table, i);
    const Vec3 wo = table.outgoingDirection(i);
    const Eigen::VectorXd fitted = atView(wo.z()).evaluate(table.incidentDirection(i), wo);
    double rowSquares = 0.0;
    for (Eigen::Index ch = 0; ch < table.values.cols(); ++ch) {
      const double r = logTerm(c, fitted[ch]) - logTerm(c, table.values(static_cast<Eigen::Index>(i), ch));
      rowSquares += r * r;
      ++sum.terms;
    }
    sum.squares += rowSquares;
    if (rowSquares > sum.largestRowSquares) sum.largestRowSquares = rowSquares, sum.largestRow = i;
  }
  return sum;
}

namespace {
// The constant k in [0, upper] minimising g(k) = sum_j (ln(1 + c_j k) - m_j)^2: a root of
// g'(k) = 2 sum_j r_j c_j / (1 + c_j k) by Newton steps kept inside a bracket where g' changes
// sign, bisecting when a step leaves it (Press et al.'s rtsafe). ~10 passes over the rows where a
// golden-section search took 120.
double lambertianConstant(const std::vector<double>& cosines, const std::vector<double>& measured, double upper) {
  // g'/2 and g''/2 at k.
  auto slopes = [&](double k) {
    double first = 0.0, second = 0.0;
    for (std::size_t j = 0; j < cosines.size(); ++j) {
      const double c = cosines[j], d = 1.0 / (1.0 + c * k), r = std::log1p(c * k) - measured[j];
      first += r * c * d;
      second += c * c * d * d * (1.0 - r);
    }
    return std::pair{first, second};
  };
  double lo = 0.0, hi = upper;
  if (slopes(lo).first >= 0.0) return lo;
  if (slopes(hi).first <= 0.0) return hi;
  double k = 0.5 * (lo + hi);
  for (int it = 0; it < 100; ++it) {
    const auto [first, second] = slopes(k);
    (first < 0.0 ? lo : hi) = k;
    double next = second > 0.0 ? k - first / second : -1.0;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const double step = std::abs(next - k);
    k = next;
    if (step <= 1e-14 * upper || hi - lo <= 1e-14 * upper) break;
  }
  return k;
}
}  // namespace

std::vector<double> lambertianFit(const MeasuredTable& table, const std::vector<std::size_t>& rows) {
  std::vector<double> k(table.channelCount(), 0.0);
  std::vector<double> cosines, measured(rows.size());
  cosines.reserve(rows.size());
  for (std::size_t i : rows) cosines.push_back(cosIncident(table, i));
  for (std::size_t ch = 0; ch < k.size(); ++ch) {
    const auto column = static_cast<Eigen::Index>(ch);
    double upper = 1e-9;
    for (std::size_t j = 0; j < rows.size(); ++j) {
      const double f = table.values(static_cast<Eigen::Index>(rows[j]), column);
      measured[j] = logTerm(cosines[j], f);
      upper = std::max(upper, f);
    }
    k[ch] = lambertianConstant(cosines, measured, upper);
  }
  return k;
}

LogErrorSum lambertianLogError(const std::vector<double>& k, const MeasuredTable& table,
                               const std::vector<std::size_t>& rows) {
  LogErrorSum sum;
  for (std::size_t i : rows) {
    const double c = cosIncident(table, i);
    for (Eigen::Index ch = 0; ch < table.values.cols(); ++ch) {
      const double r =
          logTerm(c, k[static_cast<std::size_t>(ch)]) - logTerm(c, table.values(static_cast<Eigen::Index>(i), ch));
      sum.squares += r * r;
      ++sum.terms;
    }
  }
  return sum;
}

namespace {
// The k-fold splits: the rows away from the mirror in a seeded shuffle, every folds-th one held out.
void addFolds(const MeasuredTable& table, const HeldOutOptions& options, std::vector<std::vector<bool>>& held) {
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < table.size(); ++i) {
    if (mirrorOffsetDegrees(table, i) > options.minMirrorOffsetDegrees) candidates.push_back(i);
  }
  if (candidates.size() < static_cast<std::size_t>(options.folds)) {
    throw Error(Error::Kind::InvalidInput, "held-out: " + std::to_string(candidates.size()) + " row(s) farther than " +
                                               std::to_string(options.minMirrorOffsetDegrees) +
                                               " degrees from the mirror cannot make " + std::to_string(options.folds) +
                                               " folds");
  }
  std::mt19937_64 rng(options.seed);
  std::shuffle(candidates.begin(), candidates.end(), rng);
  for (int f = 0; f < options.folds; ++f) {
    std::vector<bool> rows(table.size(), false);
    for (std::size_t j = static_cast<std::size_t>(f); j < candidates.size();
         j += static_cast<std::size_t>(options.folds))
      rows[candidates[j]] = true;
    held.push_back(std::move(rows));
  }
}

// The held-out incident elevations: every interior one, or those listed.
std::vector<double> heldOutElevations(const MeasuredTable& table, const HeldOutOptions& options) {
  const std::vector<double> thetas = table.incidentThetas();
  std::vector<double> elevations;
  if (options.elevationsDegrees.empty()) {
    for (std::size_t t = 1; t + 1 < thetas.size(); ++t) elevations.push_back(thetas[t]);
    return elevations;
  }
  for (double e : options.elevationsDegrees) {
    const auto it =
        std::find_if(thetas.begin(), thetas.end(), [&](double t) { return std::abs(degrees(t) - e) < 0.01; });
    if (it == thetas.end()) {
      std::ostringstream text;
      text << "held-out: the table has no incident elevation " << e << " deg";
      throw Error(Error::Kind::InvalidArgument, text.str());
    }
    elevations.push_back(*it);
  }
  std::sort(elevations.begin(), elevations.end());
  return elevations;
}
}  // namespace

HeldOutSplits::HeldOutSplits(const MeasuredTable& table, const HeldOutOptions& options, const Context& context)
    : table_(&table), options_(options), context_(context) {
  options.validate();
  std::vector<std::vector<bool>> held;
  addFolds(table, options, held);
  for (double theta : heldOutElevations(table, options)) {
    std::vector<bool> rows(table.size(), false);
    for (std::size_t i : table.samplesAtIncidentTheta(theta)) rows[i] = true;
    held.push_back(std::move(rows));
    HeldOutSplit entry;
    std::ostringstream name;
    name << "theta_i " << std::lround(degrees(theta)) << " deg";
    entry.name = name.str();
    entry.elevationDegrees = degrees(theta);
    entries_.elevations.push_back(entry);
  }
  entries_.kfold.name = "off-mirror " + std::to_string(options.folds) + "-fold";
  splits_.resize(held.size());
  for (std::size_t s = 0; s < held.size(); ++s) {
    Split& split = splits_[s];
    split.entry = s < static_cast<std::size_t>(options.folds) ? -1 : static_cast<int>(s) - options.folds;
    for (std::size_t i = 0; i < table.size(); ++i) (held[s][i] ? split.held : split.train).push_back(i);
  }
  tbb::task_arena arena(context_.arenaThreads());
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), splits_.size(), [&](std::size_t s) {
      context_.checkCancelled();
      Split& split = splits_[s];
      split.training = tableRows(table, split.train);
      split.lambertConstants = lambertianFit(table, split.train);
      split.lambert = lambertianLogError(split.lambertConstants, table, split.held);
    });
  });
}

namespace {
// The split's largest row (HeldOutSplit::largestRowShare) from its fit's error sum, and the part of
// Lambert's error (`lambert`, with the constants `k`) that row holds.
void setLargestRow(HeldOutSplit& split, const LogErrorSum& fitted, const LogErrorSum& lambert,
                   const std::vector<double>& k, const MeasuredTable& table) {
  if (!(std::isfinite(fitted.squares) && fitted.squares > 0.0)) return;
  split.largestRowShare = std::min(fitted.largestRowSquares / fitted.squares, 1.0);
  if (lambert.squares > 0.0) {
    const double rowSquares = lambertianLogError(k, table, {fitted.largestRow}).squares;
    split.largestRowLambertShare = std::min(rowSquares / lambert.squares, 1.0);
  }
  split.largestRow = table.angles[fitted.largestRow];
  split.largestRowMirrorOffset = mirrorOffsetDegrees(table, fitted.largestRow);
}
}  // namespace

double HeldOutSplit::ratioWithoutLargestRow() const {
  const double rest = 1.0 - largestRowLambertShare;
  return rest > 1e-12 ? ratio() * std::sqrt(std::max(1.0 - largestRowShare, 0.0) / rest) : ratio();
}

HeldOutReport HeldOutSplits::estimate(const SplitFitter& fit) const {
  const auto start = std::chrono::steady_clock::now();
  std::vector<LogErrorSum> fitted(splits_.size());
  tbb::task_arena arena(context_.arenaThreads());
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), splits_.size(), [&](std::size_t s) {
      context_.checkCancelled();
      fitted[s] = cosineLogError(fit(s, splits_[s].training), *table_, splits_[s].held);
    });
  });
  HeldOutReport report = entries_;
  LogErrorSum kfoldFit, kfoldLambert;
  std::size_t kfoldLargest = 0;  // the fold whose held-out rows hold the k-fold split's largest row
  for (std::size_t s = 0; s < splits_.size(); ++s) {
    const Split& split = splits_[s];
    if (split.entry < 0) {
      if (fitted[s].largestRowSquares > kfoldFit.largestRowSquares) kfoldLargest = s;
      kfoldFit.add(fitted[s]);
      kfoldLambert.add(split.lambert);
      report.kfold.heldRows += split.held.size();
    } else {
      HeldOutSplit& e = report.elevations[static_cast<std::size_t>(split.entry)];
      e.heldRows = split.held.size();
      e.error = fitted[s].rms();
      e.lambertError = split.lambert.rms();
      setLargestRow(e, fitted[s], split.lambert, split.lambertConstants, *table_);
    }
  }
  report.kfold.error = kfoldFit.rms();
  report.kfold.lambertError = kfoldLambert.rms();
  if (!splits_.empty())
    setLargestRow(report.kfold, kfoldFit, kfoldLambert, splits_[kfoldLargest].lambertConstants, *table_);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

HeldOutReport estimateHeldOutError(const MeasuredTable& table, const TableFitter& fit, const HeldOutOptions& options,
                                   const Context& context) {
  return HeldOutSplits(table, options, context).estimate([&](std::size_t, const MeasuredTable& training) {
    return fit(training);
  });
}

}  // namespace brdfbake
