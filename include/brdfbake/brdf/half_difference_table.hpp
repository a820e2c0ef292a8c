#pragma once
/// @file
/// A smooth table of ln f over Rusinkiewicz 1998's half and difference angles: a term of a lobe model
/// (LobeModel::halfDifference, brdf/lobes.hpp) that `brdfbake fit` chooses where no lobe family follows a
/// table (docs/fitting.md, "Half-difference tables").
///
/// theta_h is the angle between the half-vector h = (l + v) / |l + v| and the normal, theta_d the
/// angle between the light and h (cos theta_d = l.h). One channel of the term is
///
///     f(l, v) = exp( sum_{k,j} a_kj hat_k(x) B_j(s) )     [1/sr],
///
///     x = sqrt(theta_h / 90 degrees) (K - 1),   s = theta_d / 90 degrees,
///
/// hat_k the piecewise-linear hat of knot k = 0..K-1 (1 at x = k, 0 at x = k -+ 1), B_j the Bernstein
/// polynomials binom(D, j) s^j (1 - s)^(D - j), j = 0..D. The square root puts the knots close
/// together near the highlight (K = 12: the first knot 0.74 degrees from it) and far apart where f
/// is smooth. Hats and Bernstein polynomials are each non-negative and sum to 1, so ln f lies
/// between the smallest and the largest a_kj: bounded coefficients bound f. The term depends on
/// theta_h and theta_d alone: isotropic, and reciprocal (both angles are symmetric in l and v).

#include <brdfbake/core/math.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace brdfbake {

/// Largest Bernstein degree D a table may have.
inline constexpr int kMaxTableDegree = 12;
/// Bound on |a_kj| LobeModel::validate accepts (e^50 = 5e21 1/sr: finite in every product a map takes).
inline constexpr double kMaxTableLogValue = 50.0;

/// The shape of a model's table: K knots in theta_h and degree D in theta_d; K = 0 means no table.
struct HalfDifferenceTableShape {
  int halfAngleKnots = 0;    ///< K, 2..64 (0: none)
  int differenceDegree = 0;  ///< D, 0..kMaxTableDegree
  bool empty() const { return halfAngleKnots == 0; }
  /// Coefficients per channel, K (D + 1), index k (D + 1) + j.
  int coefficientCount() const { return halfAngleKnots * (differenceDegree + 1); }
  /// Throws Error(InvalidArgument) for sizes outside the ranges above.
  void validate() const;
};

/// The basis functions at one pair of angles: two hats (knot and knot + 1) and D + 1 Bernstein
/// weights; every other hat is 0 there.
struct HalfDifferenceBasis {
  int knot = 0;           ///< the lower of the two hats that may be non-zero
  double lowerHat = 1.0;  ///< hat_knot(x)
  double upperHat = 0.0;  ///< hat_{knot+1}(x)
  int degree = 0;         ///< D
  double bernstein[kMaxTableDegree + 1] = {};

  /// At theta_h and theta_d (radians, clamped to [0, pi / 2]).
  static HalfDifferenceBasis at(const HalfDifferenceTableShape& shape, double thetaH, double thetaD);
  /// sum_{k,j} a_kj hat_k B_j for one channel's coefficients (HalfDifferenceTableShape::coefficientCount of them).
  double logValue(const std::vector<double>& coefficients) const;
  /// Calls add(index, basis value) for each of the 2 (D + 1) basis functions that may be non-zero.
  template <class Add>
  void forEachTerm(Add add) const {
    const int stride = degree + 1;
    for (int j = 0; j <= degree; ++j) {
      add(knot * stride + j, lowerHat * bernstein[j]);
      add((knot + 1) * stride + j, upperHat * bernstein[j]);
    }
  }
};

}  // namespace brdfbake
