#pragma once
// Internal to fit/: the per-channel Ceres fit behind FitMethod::PerChannel (docs/fitting.md,
// "Per-channel fits with Ceres"): each channel its own mirror lobes, constant or varying with the
// view's elevation, fitted on the cube-root residual with Ceres, K = 1, 2, ... lobes grown greedily.
#include <brdfbake/fit/lobe_fit.hpp>
#include <brdfbake/measured/measured_table.hpp>

namespace brdfbake::detail {

// The elevation range of the fitted views (light and view above the horizon): the varying
// polynomials span exactly this range. Views within 1 degree of the horizon do not widen it.
LobeModel fittedRange(const MeasuredTable& table);

// The Ceres per-channel fit (FitMethod::PerChannel) of one explicit lobe count and elevation (the
// in-sample greedy sequence still grows K from 1). Throws Error(InvalidInput) when the usable
// samples cannot determine the model.
FitResult fitPerChannel(const MeasuredTable& table, const FitOptions& options);

}  // namespace brdfbake::detail
