#include <brdfbake/core/error.hpp>
#include <brdfbake/fit/held_out.hpp>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
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
  require(threads >= 0, "held-out: threads must be >= 0");
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
  return 0.5 * (kfold.ratio() + pooledElevations().ratio());
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
  require(model.channelCount() == table.channelCount(), "held-out: the model and the table have different channel counts");
  LogErrorSum sum;
  for (std::size_t i : rows) {
    const double c = cosIncident(table, i);
    const Eigen::VectorXd fitted = model.evaluate(table.incidentDirection(i), table.outgoingDirection(i));
    for (Eigen::Index ch = 0; ch < table.values.cols(); ++ch) {
      const double r = logTerm(c, fitted[ch]) - logTerm(c, table.values(static_cast<Eigen::Index>(i), ch));
      sum.squares += r * r;
      ++sum.terms;
    }
  }
  return sum;
}

std::vector<double> lambertianFit(const MeasuredTable& table, const std::vector<std::size_t>& rows) {
  std::vector<double> k(table.channelCount(), 0.0);
  // The cosines and measured terms once (the search evaluates the cost 2 x 60 times per channel).
  std::vector<double> cosines, measured(rows.size());
  cosines.reserve(rows.size());
  for (std::size_t i : rows) cosines.push_back(cosIncident(table, i));
  for (std::size_t ch = 0; ch < k.size(); ++ch) {
    const auto column = static_cast<Eigen::Index>(ch);
    for (std::size_t j = 0; j < rows.size(); ++j) measured[j] = logTerm(cosines[j], table.values(static_cast<Eigen::Index>(rows[j]), column));
    auto cost = [&](double value) {
      double s = 0.0;
      for (std::size_t j = 0; j < rows.size(); ++j) {
        const double r = logTerm(cosines[j], value) - measured[j];
        s += r * r;
      }
      return s;
    };
    double a = 0.0, b = 1e-9;
    for (std::size_t i : rows) b = std::max(b, table.values(static_cast<Eigen::Index>(i), column));
    const double g = (std::sqrt(5.0) - 1.0) / 2.0;
    // 60 steps shrink the bracket to 3e-13 of max f (the figures do not move past the 10th digit).
    for (int it = 0; it < 60; ++it) {
      const double c = b - g * (b - a), d = a + g * (b - a);
      if (cost(c) < cost(d)) b = d;
      else a = c;
    }
    k[ch] = 0.5 * (a + b);
  }
  return k;
}

LogErrorSum lambertianLogError(const std::vector<double>& k, const MeasuredTable& table, const std::vector<std::size_t>& rows) {
  LogErrorSum sum;
  for (std::size_t i : rows) {
    const double c = cosIncident(table, i);
    for (Eigen::Index ch = 0; ch < table.values.cols(); ++ch) {
      const double r = logTerm(c, k[static_cast<std::size_t>(ch)]) - logTerm(c, table.values(static_cast<Eigen::Index>(i), ch));
      sum.squares += r * r;
      ++sum.terms;
    }
  }
  return sum;
}

HeldOutReport estimateHeldOutError(const MeasuredTable& table, const TableFitter& fit, const HeldOutOptions& options) {
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  // The splits: (training rows, held-out rows, which report entry).
  struct Split {
    std::vector<std::size_t> train, held;
    int entry;  // -1 = k-fold, else index into elevations
  };
  std::vector<Split> splits;
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < table.size(); ++i) {
    if (mirrorOffsetDegrees(table, i) > options.minMirrorOffsetDegrees) candidates.push_back(i);
  }
  if (candidates.size() < static_cast<std::size_t>(options.folds)) {
    throw Error(Error::Kind::InvalidInput, "held-out: " + std::to_string(candidates.size()) + " row(s) farther than " +
                                               std::to_string(options.minMirrorOffsetDegrees) +
                                               " degrees from the mirror cannot make " + std::to_string(options.folds) + " folds");
  }
  std::mt19937_64 rng(options.seed);
  std::shuffle(candidates.begin(), candidates.end(), rng);
  for (int f = 0; f < options.folds; ++f) {
    std::vector<bool> held(table.size(), false);
    for (std::size_t j = static_cast<std::size_t>(f); j < candidates.size(); j += static_cast<std::size_t>(options.folds)) held[candidates[j]] = true;
    Split split{{}, {}, -1};
    for (std::size_t i = 0; i < table.size(); ++i) (held[i] ? split.held : split.train).push_back(i);
    splits.push_back(std::move(split));
  }
  const std::vector<double> thetas = table.incidentThetas();
  std::vector<double> elevations;
  if (options.elevationsDegrees.empty()) {
    for (std::size_t t = 1; t + 1 < thetas.size(); ++t) elevations.push_back(thetas[t]);
  } else {
    for (double e : options.elevationsDegrees) {
      const auto it = std::find_if(thetas.begin(), thetas.end(), [&](double t) { return std::abs(degrees(t) - e) < 0.01; });
      if (it == thetas.end()) {
        std::ostringstream text;
        text << "held-out: the table has no incident elevation " << e << " deg";
        throw Error(Error::Kind::InvalidArgument, text.str());
      }
      elevations.push_back(*it);
    }
    std::sort(elevations.begin(), elevations.end());
  }
  HeldOutReport report;
  for (double theta : elevations) {
    const auto rows = table.samplesAtIncidentTheta(theta);
    std::vector<bool> held(table.size(), false);
    for (std::size_t i : rows) held[i] = true;
    Split split{{}, {}, static_cast<int>(report.elevations.size())};
    for (std::size_t i = 0; i < table.size(); ++i) (held[i] ? split.held : split.train).push_back(i);
    splits.push_back(std::move(split));
    HeldOutSplit entry;
    std::ostringstream name;
    name << "theta_i " << std::lround(degrees(theta)) << " deg";
    entry.name = name.str();
    entry.elevationDegrees = degrees(theta);
    report.elevations.push_back(entry);
  }

  std::vector<LogErrorSum> fitted(splits.size()), lambert(splits.size());
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), splits.size(), [&](std::size_t s) {
      const MeasuredTable training = tableRows(table, splits[s].train);
      const LobeModel model = fit(training);
      fitted[s] = cosineLogError(model, table, splits[s].held);
      lambert[s] = lambertianLogError(lambertianFit(table, splits[s].train), table, splits[s].held);
    });
  });
  LogErrorSum kfoldFit, kfoldLambert;
  for (std::size_t s = 0; s < splits.size(); ++s) {
    if (splits[s].entry < 0) {
      kfoldFit.squares += fitted[s].squares, kfoldFit.terms += fitted[s].terms;
      kfoldLambert.squares += lambert[s].squares, kfoldLambert.terms += lambert[s].terms;
      report.kfold.heldRows += splits[s].held.size();
    } else {
      HeldOutSplit& e = report.elevations[static_cast<std::size_t>(splits[s].entry)];
      e.heldRows = splits[s].held.size();
      e.error = fitted[s].rms();
      e.lambertError = lambert[s].rms();
    }
  }
  report.kfold.name = "off-mirror " + std::to_string(options.folds) + "-fold";
  report.kfold.error = kfoldFit.rms();
  report.kfold.lambertError = kfoldLambert.rms();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace brdfbake
