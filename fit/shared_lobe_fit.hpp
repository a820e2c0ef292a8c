#pragma once
// Internal to fit/: the shared-shape lobe fit behind FitMethod::Shared (docs/fitting.md, "Shared
// shapes"). Every channel has the same lobe shapes (exponent n_k and Lafortune coefficient c_xy,k);
// the per-channel diffuse terms and lobe weights enter the model linearly and are solved by
// non-negative least squares for each trial of shapes (variable projection, Golub & Pereyra 1973),
// on the cosine-weighted log error that held-out checks measure,
//
//     r_i = ln(1 + cos theta_i f(wi, wo)) - ln(1 + cos theta_i max(f_i, 0)),
//
// through Gauss-Newton steps (each one non-negative least squares of the linearised residual).
// The shapes are found greedily (each new lobe from a grid of exponents and c_xy, the others kept)
// and refined together by a compass search (Kolda, Lewis & Torczon 2003) on ln n and c_xy; the
// search scores a trial of shapes by the log error of the weights of the first, linearised step
// (all searched channels in one pass), and only the shapes it returns get the Gauss-Newton steps.
// A half-vector lobe (halfVectorLobe) has the shape ln n alone and two weights per channel, C and C_F.
#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/measured/measured_table.hpp>

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace brdfbake::detail {

// The compass searches run on one table by the fits of several candidates (one fit at a time; not
// thread-safe). A search from the same shapes (to 1e-12) with the same settings returns the same
// shapes, so a later fit takes them from here instead of searching again: mixed lobes repeat the
// half-vector and mirror candidates' searches whenever they pick the same axis for a new lobe.
class ShapeSearches;
std::shared_ptr<ShapeSearches> makeShapeSearches();

// The Gauss-Newton steps of a fit whose weights are kept (SharedFitConfig::gaussNewtonSteps).
inline constexpr int kGaussNewtonSteps = 8;

struct SharedFitConfig {
  int lobes = 1;  // 0 = diffuse only
  // Lobe axes a new lobe may take (at least one): Phong lobes about the mirrored view (c_xy = -1),
  // Lafortune lobes (c_xy free, includes the mirror), half-vector lobes (halfVectorLobe, weights C
  // and C_F). Half-vector lobes alone: mixing in Lafortune ones measured no better held out
  // (docs/fitting.md) and costs a c_xy search.
  bool mirror = true;
  bool lafortune = false;
  bool halfVector = false;
  // Lobes that vary with elevation (LobeElevation::Varying): each lobe's exponent n(t) and a gain
  // g(t) on its weights are geometric quadratic Bernstein blends in the elevation coordinate t
  // (LobeModel::elevationCoordinate), shared by every channel like the other shape parameters, so
  // the weights stay linear: C_c(t) = w_c g(t), g = 1 at the most normal view. A half-vector
  // lobe's C_F stays constant.
  bool varying = false;
  // The prior on varying shapes: each unit of squared offset of ln n or ln g from its value at the
  // most normal view costs this fraction of the constant fit's objective (FitOptions::varyingPrior).
  double varyingPrior = 0.01;
  double maxExponent = 1e4;  // cap on n
  // Channels the shape search looks at (evenly spread; all if fewer). 3 chose models that scored within
  // 0.03 of 6 on the spectral Cornell tables (better on two of three) in 65 to 85 % of the time.
  int searchChannels = 3;
  int maxEvaluations = 600;  // shape trials in the compass search
  // Shape trials of the compass search that frees a varying model's offsets (from the constant fit).
  // 600 scored the chosen candidates within 0.02 of 300 and 200 (docs/fitting.md) at twice the time;
  // 100 lost up to 0.23.
  int maxVaryingEvaluations = 300;
  // Warm start: the shapes (exponent, c_xy, axis) of the first lobes, as a fit of the same table
  // with fewer lobes returned them; the fit adds lobes greedily after these. The greedy steps are
  // the same either way, so a fit warm-started from the (K-1)-lobe fit equals the cold K-lobe fit.
  std::vector<Lobe> startLobes;
  // Colour profiles (ColorProfile::DifferenceAngle): the shapes are found without them, then every
  // weight column is multiplied by the cubic Bernstein polynomials in theta_d / 90 degrees and the
  // weights are solved again (the columns' non-negative coefficients are the profile's p_j times the
  // term's weight). The shapes are the same as without, so a profiled fit reuses their searches.
  bool colorProfile = false;
  // Compass searches other fits of the same table ran already (may be null; see ShapeSearches).
  std::shared_ptr<ShapeSearches> searches;
  // Gauss-Newton steps on the weights after the NNLS linearised at the data (each an NNLS of the
  // residual linearised at the current model). 0 leaves the weights the search ranked shapes by.
  int gaussNewtonSteps = kGaussNewtonSteps;
};

struct SharedFitOutcome {
  LobeModel model;         // elevation Constant (Varying with SharedFitConfig::varying), range from `range`,
                           // colour profiles with SharedFitConfig::colorProfile
  int evaluations = 0;     // shape trials
  double objective = 0.0;  // sum over channels and fitted rows of r_i^2
  std::size_t rows = 0;    // fitted rows (light and view above the horizon)
};

// Fits `table` (all channels); `range` supplies minCos / maxCos. Throws Error(InvalidInput) when
// no row has both directions above the horizon.
SharedFitOutcome fitSharedLobes(const MeasuredTable& table, const SharedFitConfig& config, const LobeModel& range);

// Non-negative least squares min |A x - b|^2, x >= 0, given G = A^T A and h = A^T b (Lawson &
// Hanson 1974, chapter 23, on the normal equations). Small problems (a few columns).
// The right-hand side may be a column of a matrix (no copy).
Eigen::VectorXd nonNegativeLeastSquares(const Eigen::MatrixXd& gram, const Eigen::Ref<const Eigen::VectorXd>& rhs);

}  // namespace brdfbake::detail
