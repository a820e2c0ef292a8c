#pragma once
/// @file
/// Held-out error of a fit: how well a model fitted to part of a measured table predicts the rest.
/// docs/fitting.md, "Held-out error", describes the measure and the splits.
///
/// Error (the cosine-weighted log error, after Low et al. 2012's log-compressed comparison): over
/// held-out samples i and channels c,
///
///     E = sqrt(mean_{i,c} (ln(1 + cos theta_i max(f_fit, 0)) - ln(1 + cos theta_i max(f_measured, 0)))^2),
///
/// f in 1/sr: ln(1 + x) is linear for the dim diffuse and back-scatter values (x << 1) and
/// logarithmic in highlights, so neither dominates. It is reported as a ratio to a Lambertian fit
/// on the same split: one constant per channel minimising the same error on the training rows.
/// Two splits:
///  - k-fold over the rows farther than `minMirrorOffsetDegrees` from the mirror direction (a
///    table samples each highlight once, so holding that sample out leaves its height unknown);
///    the folds are a seeded shuffle, every such row is held out once, and the errors of all folds
///    are pooled;
///  - one incident elevation held out whole (every row of that theta_i), for each elevation that
///    has measured elevations on both sides (interpolation, not extrapolation), or those listed.

#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/core/context.hpp>
#include <brdfbake/measured/measured_table.hpp>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace brdfbake {

struct HeldOutOptions {
  /// Folds of the off-mirror split, 2..20.
  int folds = 5;
  /// Rows of the k-fold split are farther than this from the mirror direction (degrees, 0..90).
  double minMirrorOffsetDegrees = 5.0;
  /// Incident elevations (degrees) held out one at a time; empty = every interior one of the
  /// table. Each must be one of the table's theta_i (within 0.01 degree).
  std::vector<double> elevationsDegrees;
  /// Seed of the k-fold shuffle (std::mt19937_64).
  unsigned long long seed = 1;

  /// Throws Error(InvalidArgument) for values outside the documented ranges.
  void validate() const;
};

/// One split's pooled error.
struct HeldOutSplit {
  std::string name;             ///< "off-mirror 5-fold", "theta_i 30 deg"
  double elevationDegrees = 0;  ///< the held-out theta_i; 0 for the k-fold split
  std::size_t heldRows = 0;     ///< held-out rows (each counted once, over every channel)
  double error = 0.0;           ///< E of the fitted models on the held-out rows
  double lambertError = 0.0;    ///< E of the Lambertian fits on the same rows
  /// error / lambertError, both offset by 1e-9 so that a table Lambert fits exactly (a constant
  /// BRDF) gives a finite ratio, 1 when both vanish.
  double ratio() const { return (error + 1e-9) / (lambertError + 1e-9); }

  /// The held-out row that holds the largest part of the squares of `error`, and that part (0..1; 0,
  /// and no row, when the fit's error is 0). Near 1 the split's figure is one row's: a highlight
  /// narrower than the table's steps, sampled once per elevation (docs/fitting.md, "What one row decides").
  double largestRowShare = 0.0;
  /// The part of the squares of `lambertError` the same row holds (0..1).
  double largestRowLambertShare = 0.0;
  SampleAngles largestRow{};            ///< its angles (radians), as in the table
  double largestRowMirrorOffset = 0.0;  ///< its outgoing direction's angle from the mirror direction, degrees
  /// ratio() with the largest row left out of both errors: ratio() sqrt((1 - share) / (1 - Lambert's
  /// share)); ratio() when Lambert's error has nothing else.
  double ratioWithoutLargestRow() const;
};

struct HeldOutReport {
  HeldOutSplit kfold;
  std::vector<HeldOutSplit> elevations;  ///< ascending theta_i
  double seconds = 0.0;                  ///< wall time, fits included
  /// The leave-one-elevation-out errors pooled over elevations (rows weighted equally).
  HeldOutSplit pooledElevations() const;
  /// What model selection minimises: the worse of the k-fold ratio and the pooled elevation ratio
  /// (the k-fold ratio alone when no elevation was held out), so that neither hides the other.
  double score() const;
  /// The better of the two ratios (the k-fold ratio when no elevation was held out): the second
  /// entry when the two are ordered worst first.
  double otherScore() const;
  /// Whether this report is better than `other` by the fraction `margin` in (0, 1), comparing the two
  /// ratios ordered worst first (a lexicographic minimax): its score() is below (1 - margin)
  /// other.score(), or no higher while its otherScore() is below (1 - margin) other.otherScore().
  /// The worse and the better ratio may be different measures in the two reports (k-fold 0.48 and
  /// elevations 0.43 are improved on by 0.28 and 0.47: worst 0.48 -> 0.47, better 0.43 -> 0.28), so
  /// one measure may rise as long as it stays below the other report's worse one. The automatic
  /// choice of colour profiles keeps them only if they improve so: the score alone cannot see them
  /// lower one measure while the other stays at a floor (Mystique's elevation splits, one sample
  /// nearest a clear coat's mirror; docs/fitting.md). The other choices compare scores alone.
  bool improvesOn(const HeldOutReport& other, double margin) const;
};

/// A fit of a training table (the channels of the table given to estimateHeldOutError).
using TableFitter = std::function<LobeModel(const MeasuredTable& training)>;
/// A fit of split `split`'s training table (HeldOutSplits::estimate): the index lets a caller
/// start one candidate's fit of a split from another candidate's fit of the same split.
using SplitFitter = std::function<LobeModel(std::size_t split, const MeasuredTable& training)>;

/// The rows of `table` at `rows`, in that order (same channels, header and notes).
MeasuredTable tableRows(const MeasuredTable& table, const std::vector<std::size_t>& rows);

/// Angle (degrees) between the outgoing direction of row i and the mirror direction of its light.
double mirrorOffsetDegrees(const MeasuredTable& table, std::size_t row);

/// E (see @file) of `model` on `rows` of `table`: sum of squares and the count of terms, so that
/// splits can be pooled. Rows with a direction at or below the horizon count with cos theta_i = 0
/// (their terms are 0).
struct LogErrorSum {
  double squares = 0.0;
  std::size_t terms = 0;
  double largestRowSquares = 0.0;  ///< the largest sum of one row's squares (over its channels)
  std::size_t largestRow = 0;      ///< that row's index in the table (cosineLogError only)
  double rms() const { return terms ? std::sqrt(squares / static_cast<double>(terms)) : 0.0; }
  /// Pools `other` into this sum (splits' rows are disjoint): squares and terms add, the larger
  /// largest row is kept.
  void add(const LogErrorSum& other) {
    squares += other.squares;
    terms += other.terms;
    if (other.largestRowSquares > largestRowSquares)
      largestRowSquares = other.largestRowSquares, largestRow = other.largestRow;
  }
};
LogErrorSum cosineLogError(const LobeModel& model, const MeasuredTable& table, const std::vector<std::size_t>& rows);

/// Per channel, the constant BRDF k >= 0 (1/sr) minimising sum_i (ln(1 + cos theta_i k) -
/// ln(1 + cos theta_i max(f_i, 0)))^2 over `rows` (safeguarded Newton on [0, max f]).
std::vector<double> lambertianFit(const MeasuredTable& table, const std::vector<std::size_t>& rows);
/// E of the Lambertian constants `k` on `rows`.
LogErrorSum lambertianLogError(const std::vector<double>& k, const MeasuredTable& table,
                               const std::vector<std::size_t>& rows);

/// The splits of one table (see @file), made once with their training tables and Lambertian
/// baselines, so that every candidate model of a search is scored on the same splits for the
/// price of its own fits. Splits 0..folds-1 are the k-fold ones, then one per held-out elevation.
class HeldOutSplits {
 public:
  /// Keeps a reference to `table`, which must outlive the splits. Throws Error(InvalidArgument)
  /// for bad options or a listed elevation the table lacks, Error(InvalidInput) when the table has
  /// fewer off-mirror rows than folds.
  HeldOutSplits(const MeasuredTable& table, const HeldOutOptions& options = {}, const Context& context = {});

  std::size_t size() const { return splits_.size(); }
  const MeasuredTable& training(std::size_t split) const { return splits_.at(split).training; }

  /// Fits every split's training table (in parallel, on the context's threads) and scores the
  /// held-out rows; errors of `fit` propagate.
  HeldOutReport estimate(const SplitFitter& fit) const;

 private:
  struct Split {
    std::vector<std::size_t> train, held;
    int entry = -1;  // -1 = k-fold, else index into the report's elevations
    MeasuredTable training;
    std::vector<double> lambertConstants;  // the Lambertian fit of `train`
    LogErrorSum lambert;                   // its error on `held`
  };
  const MeasuredTable* table_;
  HeldOutOptions options_;
  Context context_;
  std::vector<Split> splits_;
  HeldOutReport entries_;  // names and elevations, no errors yet
};

/// HeldOutSplits(table, options).estimate(fit) for a fit that ignores the split index.
HeldOutReport estimateHeldOutError(const MeasuredTable& table, const TableFitter& fit,
                                   const HeldOutOptions& options = {}, const Context& context = {});

}  // namespace brdfbake
