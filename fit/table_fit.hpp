#pragma once
// Internal to fit/: the half-difference table (brdf/half_difference_table.hpp) fitted to a measured
// table, LobeKindChoice::HalfDifference (docs/fitting.md, "Half-difference tables").
#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/measured/measured_table.hpp>

namespace brdfbake::detail {

// The table's shape: 12 knots in sqrt(theta_h / 90 degrees), degree 6 in theta_d / 90 degrees.
inline constexpr HalfDifferenceTableShape kFittedTableShape{12, 6};
// The weight of the smoothness penalty, as a fraction of the mean diagonal of the normal equations.
inline constexpr double kTableSmoothing = 1e-2;
// Measured values below this (1/sr; zero and negative ones of the RGB files) are fitted as this.
inline constexpr double kTableFloor = 1e-6;
// How far (in ln f) a table's coefficients may leave the range of the values it was fitted to.
inline constexpr double kTableRangeMargin = 1.0;

// Every channel's coefficients minimise, over the rows with light and view above the horizon,
//   sum_i (ln f_model(i) - ln max(f_i, kTableFloor))^2 + kTableSmoothing s |P a|^2,
// P the second differences of the coefficients along theta_h (between knots k, k + 1, k + 2) and
// along theta_d (degrees j, j + 1, j + 2), s the mean diagonal of the first sum's normal equations;
// linear least squares, one Cholesky factorisation for every channel. The penalty fills knots no
// row reaches and keeps the table smooth between the table's elevations. Each channel's coefficients
// are then clamped to the range of its fitted ln max(f_i, kTableFloor) widened by kTableRangeMargin
// (ln f is a weighted mean of them, so the table stays within a factor e of the values it was fitted
// to: unclamped, its extrapolation to grazing mirror directions, beyond the last measured elevation,
// reached 250 times Mystique's largest sample), and to kMaxTableLogValue. The model has no diffuse
// term and no lobes. Throws Error(InvalidArgument) when fewer rows than coefficients per channel are
// usable (canFitHalfDifferenceTable).
LobeModel fitHalfDifferenceTable(const MeasuredTable& table);

// Rows of `table` with light and view above the horizon: what every fit can use.
std::size_t usableRows(const MeasuredTable& table);

// Whether `table` has as many usable rows as a half-difference table has coefficients per channel.
bool canFitHalfDifferenceTable(const MeasuredTable& table);

}  // namespace brdfbake::detail
