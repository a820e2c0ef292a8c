#pragma once
// Internal to fit/: the per-channel Ceres fit behind FitMethod::PerChannel (docs/fitting.md,
// "Per-channel fits with Ceres"): each channel its own mirror lobes, constant or varying with the
// view's elevation, fitted on the cube-root residual with Ceres, K = 1, 2, ... lobes grown greedily;
// on spectral tables most wavelengths start from a neighbouring wavelength's fit.
#include <brdfbake/fit/lobe_fit.hpp>
#include <brdfbake/measured/measured_table.hpp>

#include <memory>

namespace brdfbake::detail {

// The elevation range of the fitted views (light and view above the horizon): the varying
// polynomials span exactly this range. Views within 1 degree of the horizon do not widen it.
LobeModel fittedRange(const MeasuredTable& table);

// The Ceres per-channel fit (FitMethod::PerChannel) of one explicit lobe count and elevation (the
// in-sample greedy sequence still grows K from 1). Throws Error(InvalidInput) when the usable
// samples cannot determine the model.
FitResult fitPerChannel(const MeasuredTable& table, const FitOptions& options, const Context& context);

// The per-channel fits of one table, kept and grown on demand: K = 1, 2, ... lobes of each
// elevation, each K starting from K - 1 (and a varying K from the constant K), exactly as
// fitPerChannel fits them. Candidates scored one after another on a held-out split reuse the
// sequence instead of refitting it. Keeps a reference to `table`.
class PerChannelFits {
 public:
  PerChannelFits(const MeasuredTable& table, const FitOptions& options, const Context& context);
  ~PerChannelFits();
  PerChannelFits(const PerChannelFits&) = delete;
  PerChannelFits& operator=(const PerChannelFits&) = delete;

  // The model of `lobes` lobes of `elevation`, what fitPerChannel returns with those fixed.
  // Throws Error(InvalidInput or InvalidArgument) when the samples cannot determine it.
  LobeModel model(int lobes, LobeElevation elevation);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace brdfbake::detail
