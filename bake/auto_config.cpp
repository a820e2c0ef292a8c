#include <brdfbake/bake/auto_config.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/memory_budget.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>

namespace brdfbake {

long long MapConfiguration::cost() const { return texels() * samplesPerTexel; }

long long MapConfiguration::texels() const {
  if (radialProfile) return resolution;
  const auto map = makeParameterization(parameterization, resolution);
  return static_cast<long long>(map->width()) * map->height();
}

std::string MapConfiguration::describe() const {
  std::ostringstream out;
  if (radialProfile) {
    out << "profile " << resolution << " texels, " << samplesPerTexel << " samples/texel";
    return out.str();
  }
  out << toString(parameterization) << " " << resolution << "^2, " << samplesPerTexel << " samples/texel";
  return out.str();
}

void AutoOptions::validate() const {
  require((!parameterizations.empty() || allowRadialProfile) && !resolutions.empty() && !samplesPerTexel.empty(),
          "auto selection needs at least one candidate of each kind");
  require(maxError > 0.0 && maxError < 1.0, "max_error must be in (0, 1), got " + std::to_string(maxError));
  for (int r : resolutions) require(r >= 1, "candidate resolutions must be >= 1");
  for (int s : samplesPerTexel) require(s >= 1, "candidate samples per texel must be >= 1");
}

double autoErrorMeasure(const ErrorStats& stats, ParameterizationKind kind) {
  return stats.bound(kind == ParameterizationKind::Sphere);
}

double autoErrorMeasure(const ErrorStats& stats, const MapConfiguration& configuration, const Vec3& profileAxis) {
  if (!configuration.radialProfile) return autoErrorMeasure(stats, configuration.parameterization);
  return stats.bound((profileAxis - Vec3::UnitZ()).norm() < 1e-12);
}

namespace {

// Share of the progress bar the search (estimates) takes; the bakes share the rest.
constexpr double kSearchShare = 0.3;
// A search whose best estimate is within this factor of the bound bakes that configuration before
// giving up: a bake's texels differ slightly from the estimate's (bakeTexel).
constexpr double kConfirmFactor = 2.0;
// Where the first family's search starts when no resolution is known to meet the bound: small
// enough to cost little, large enough that the error is past the lobe-narrower-than-a-texel regime
// for the lobes most scenes have (so the N^-2 extrapolation from it is close).
constexpr int kFirstProbeResolution = 32;

// A family of candidates: one parameterization (or the profile) and one sample count, over the
// allowed resolutions (ascending).
struct Family {
  ParameterizationKind kind = ParameterizationKind::Sphere;
  bool profile = false;
  int samplesPerTexel = 1;
  int order = 0;  // position in AutoOptions::parameterizations; profiles after them
  std::vector<int> resolutions;

  MapConfiguration at(int resolution) const { return {kind, resolution, samplesPerTexel, profile}; }
};

// Today's candidate order, which decides ties: cost, then fewer samples, then the order of the
// options' parameterizations (profiles last), then resolution.
using Key = std::tuple<long long, int, int, int>;
Key keyOf(const MapConfiguration& c, int order) { return {c.cost(), c.samplesPerTexel, order, c.resolution}; }

class Search {
 public:
  Search(const MapFunction& function, const AutoOptions& options, const Context& context)
      : function_(function),
        options_(options),
        context_(context),
        axis_(options.allowRadialProfile ? function.symmetryAxis() : std::nullopt),
        probes_(function, options.error) {
    makeFamilies();
  }

  AutoResult run() {
    report(0.0);
    for (const Family& family : families_) searchFamily(family);
    if (!best_) return confirmOrThrow();
    return bakeAndVerify(*best_, bestFamily_);
  }

 private:
  struct Estimate {
    MapConfiguration configuration;
    int order = 0;
    double error = 0.0;
  };

  bool withinBudget(const MapConfiguration& c) const {
    const long long texels = c.texels();
    const bool fits = (texels <= kMaxTexels || context_.allowLarge()) &&
                      16.0 * static_cast<double>(texels) <= static_cast<double>(memoryBudgetBytes());
    return fits;
  }

  void makeFamilies() {
    std::vector<int> resolutions = options_.resolutions, samples = options_.samplesPerTexel;
    std::sort(resolutions.begin(), resolutions.end());
    resolutions.erase(std::unique(resolutions.begin(), resolutions.end()), resolutions.end());
    std::sort(samples.begin(), samples.end());
    samples.erase(std::unique(samples.begin(), samples.end()), samples.end());
    const int kinds = static_cast<int>(options_.parameterizations.size());
    // Fewest samples first (they usually win), and in each the profile first: it is cheapest, so
    // the bound it sets leaves the maps fewer resolutions to estimate.
    for (int spt : samples) {
      std::vector<Family> batch;
      if (axis_) batch.push_back({ParameterizationKind::Sphere, true, spt, kinds, {}});
      for (int k = 0; k < kinds; ++k)
        batch.push_back({options_.parameterizations[static_cast<std::size_t>(k)], false, spt, k, {}});
      for (Family& family : batch) {
        for (int n : resolutions) {
          if (withinBudget(family.at(n))) {
            family.resolutions.push_back(n);
          } else {
            overBudget_ = true;
          }
        }
        if (!family.resolutions.empty()) families_.push_back(std::move(family));
      }
    }
    if (families_.empty()) {
      throw Error(Error::Kind::Resource,
                  "every auto candidate exceeds the memory budget (" +
                      formatBytes(16.0 * static_cast<double>(kMaxTexels)) +
                      " of float RGBA per map); allow smaller resolutions or large maps (--allow-large)");
    }
  }

  void report(double fraction) {
    progress_ = std::max(progress_, fraction);
    context_.report(progress_);
  }

  // The error of a configuration from the texels the probes read (estimateMapError), cached.
  double estimate(const Family& family, int resolution) {
    const MapConfiguration c = family.at(resolution);
    for (const Estimate& e : estimates_)
      if (e.order == family.order && e.configuration.resolution == resolution &&
          e.configuration.samplesPerTexel == c.samplesPerTexel)
        return e.error;
    const bool visible = options_.error.visibleSphere;
    double error;
    if (c.radialProfile) {
      error = autoErrorMeasure(
          estimateProfileError(function_, *axis_, resolution, c.samplesPerTexel, probes_, visible, context_), c,
          *axis_);
    } else {
      const auto map = makeParameterization(c.parameterization, resolution);
      error = autoErrorMeasure(estimateMapError(*map, function_, c.samplesPerTexel, probes_, visible, context_),
                               c.parameterization);
    }
    estimates_.push_back({c, family.order, error});
    report(kSearchShare * static_cast<double>(estimates_.size()) / (estimates_.size() + 4.0));
    return error;
  }

  // The next resolution to estimate: the smallest whose error the power law through the last two
  // estimates (or error ~ N^-2 from one) puts at or below the bound, kept inside (lo, hi).
  int predictIndex(const std::vector<int>& n, int lo, int hi,
                   const std::vector<std::pair<int, double>>& history) const {
    const auto [lastN, lastError] = history.back();
    double exponent = 2.0;  // bilinear reconstruction is second order (docs/accuracy.md)
    if (history.size() >= 2) {
      const auto [prevN, prevError] = history[history.size() - 2];
      const double measured = std::log(prevError / lastError) / std::log(static_cast<double>(lastN) / prevN);
      if (std::isfinite(measured)) exponent = std::clamp(measured, 0.5, 4.0);
    }
    const double target = lastError > 0.0 ? lastN * std::pow(lastError / options_.maxError, 1.0 / exponent) : 0.0;
    for (int i = lo + 1; i < hi; ++i)
      if (n[static_cast<std::size_t>(i)] >= target * (1.0 - 1e-9)) return i;
    return hi - 1;
  }

  // The smallest resolution of the family that meets the bound and beats the best so far, if any,
  // assuming the error falls as the resolution grows: bracketed between a resolution known to miss
  // (lo) and one known to meet it (hi), each estimate placed by the power law, until they are
  // neighbours; so the chosen resolution's next smaller one was estimated and missed.
  void searchFamily(const Family& family) {
    std::vector<int> n;
    for (int r : family.resolutions)
      if (!best_ || keyOf(family.at(r), family.order) < keyOf(*best_, bestFamily_.order)) n.push_back(r);
    if (n.empty()) return;
    const int count = static_cast<int>(n.size());
    int lo = -1, hi = count;
    int i = count - 1;  // with a best known, whether the largest cheaper resolution meets it decides
    if (!best_) {
      i = 0;
      while (i + 1 < count && n[static_cast<std::size_t>(i)] < kFirstProbeResolution) ++i;
    }
    std::vector<std::pair<int, double>> history;
    for (;;) {
      const double error = estimate(family, n[static_cast<std::size_t>(i)]);
      history.emplace_back(n[static_cast<std::size_t>(i)], error);
      (error <= options_.maxError ? hi : lo) = i;
      if (hi == lo + 1) break;
      i = predictIndex(n, lo, hi, history);
    }
    if (hi == count) return;
    best_ = family.at(n[static_cast<std::size_t>(hi)]);
    bestFamily_ = family;
  }

  struct Baked {
    double error = 0.0;
    Image image;
    std::optional<RadialProfile> profile;
  };

  Baked bakeOne(const MapConfiguration& c, AutoResult& result) {
    const double start = progress_, share = 0.9 * (1.0 - progress_);
    BakeOptions bakeOptions = options_.bake;
    bakeOptions.samplesPerTexel = c.samplesPerTexel;
    const Context bakeContext = context_.part(start, start + share);
    ++result.bakes;
    Baked baked;
    if (c.radialProfile) {
      RadialProfile profile = bakeRadialProfile(function_, *axis_, c.resolution, c.samplesPerTexel, bakeContext);
      baked.error = autoErrorMeasure(measureProfileError(profile, probes_, options_.error.visibleSphere), c, *axis_);
      baked.image = profile.toImage();
      baked.profile = std::move(profile);
    } else {
      const auto map = makeParameterization(c.parameterization, c.resolution);
      baked.image = bake(*map, function_, bakeOptions, bakeContext);
      baked.error = autoErrorMeasure(measureMapError(baked.image, *map, probes_, options_.error.visibleSphere),
                                     c.parameterization);
    }
    report(start + share);
    return baked;
  }

  // Bakes the chosen configuration and measures it; if the bake misses the bound (its texels
  // differ from the estimate's), steps up to the family's next resolution.
  AutoResult bakeAndVerify(MapConfiguration chosen, const Family& family) {
    AutoResult result;
    auto next = std::find(family.resolutions.begin(), family.resolutions.end(), chosen.resolution);
    std::vector<std::pair<MapConfiguration, double>> bakedMisses;
    for (;;) {
      Baked baked = bakeOne(chosen, result);
      if (baked.error <= options_.maxError) {
        result.chosen = chosen;
        result.error = baked.error;
        result.image = std::move(baked.image);
        result.radialProfile = std::move(baked.profile);
        break;
      }
      bakedMisses.emplace_back(chosen, baked.error);
      if (++next == family.resolutions.end()) throwNoneMeets(chosen, baked.error, "measured");
      chosen = family.at(*next);
    }
    report(1.0);
    // What was rejected on the way, cheapest first.
    std::vector<std::pair<Key, std::pair<MapConfiguration, double>>> rejected;
    const Key chosenKey = keyOf(chosen, family.order);
    for (const Estimate& e : estimates_)
      if (e.error > options_.maxError && keyOf(e.configuration, e.order) < chosenKey)
        rejected.push_back({keyOf(e.configuration, e.order), {e.configuration, e.error}});
    for (const auto& miss : bakedMisses) rejected.push_back({keyOf(miss.first, family.order), miss});
    std::stable_sort(rejected.begin(), rejected.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto& r : rejected) result.rejected.push_back(r.second);
    result.estimated = static_cast<int>(estimates_.size());
    return result;
  }

  // No candidate meets the bound by estimate. Close to it, the best is baked (a bake's texels
  // differ slightly from the estimate's) and kept if it meets the bound; otherwise the error says
  // what the best reaches and what it would take.
  AutoResult confirmOrThrow() {
    const Estimate* best = nullptr;
    for (const Estimate& e : estimates_)
      if (!best || e.error < best->error) best = &e;
    if (best->error > kConfirmFactor * options_.maxError) throwNoneMeets(best->configuration, best->error, "estimated");
    for (const Family& family : families_)
      if (family.order == best->order && family.samplesPerTexel == best->configuration.samplesPerTexel) {
        // The family's largest resolution: nothing above it to step up to.
        if (family.resolutions.back() == best->configuration.resolution)
          return bakeAndVerify(best->configuration, family);
      }
    throwNoneMeets(best->configuration, best->error, "estimated");
  }

  [[noreturn]] void throwNoneMeets(const MapConfiguration& c, double error, const char* how) const {
    std::ostringstream message;
    message << "no configuration meets max_error " << options_.maxError << ": the best, " << c.describe()
            << ", reaches " << error << " (" << how << ")";
    // The resolution the N^-2 law of bilinear lookups puts it at (docs/accuracy.md).
    if (error > 0.0 && !c.radialProfile) {
      const double needed = c.resolution * std::sqrt(error / options_.maxError);
      message << "; at error ~ N^-2 that takes about " << toString(c.parameterization) << " "
              << static_cast<long long>(std::ceil(needed)) << "^2";
    }
    if (overBudget_) message << "; larger candidates exceed the memory budget (--allow-large)";
    message << "; allow larger resolutions or a larger max_error";
    throw Error(Error::Kind::InvalidInput, message.str());
  }

  const MapFunction& function_;
  const AutoOptions& options_;
  const Context& context_;
  const std::optional<Vec3> axis_;
  const ErrorProbes probes_;
  std::vector<Family> families_;
  bool overBudget_ = false;
  std::vector<Estimate> estimates_;
  std::optional<MapConfiguration> best_;
  Family bestFamily_;
  double progress_ = 0.0;
};

}  // namespace

AutoResult chooseConfiguration(const MapFunction& function, const AutoOptions& options, const Context& context) {
  options.validate();
  Search search(function, options, context);
  return search.run();
}

}  // namespace brdfbake
