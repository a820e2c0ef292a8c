#include <brdfbake/bake/auto_config.hpp>
#include <brdfbake/core/error.hpp>

#include <sstream>

namespace brdfbake {

long long MapConfiguration::cost() const {
  if (radialProfile) return static_cast<long long>(resolution) * samplesPerTexel;
  const auto map = makeParameterization(parameterization, resolution);
  return static_cast<long long>(map->width()) * map->height() * samplesPerTexel;
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

AutoResult chooseConfiguration(const MapFunction& function, const AutoOptions& options) {
  options.validate();
  std::vector<MapConfiguration> candidates;
  for (auto kind : options.parameterizations)
    for (int resolution : options.resolutions)
      for (int spt : options.samplesPerTexel) candidates.push_back({kind, resolution, spt});
  const std::optional<Vec3> axis = options.allowRadialProfile ? function.symmetryAxis() : std::nullopt;
  if (axis) {
    for (int resolution : options.resolutions)
      for (int spt : options.samplesPerTexel) candidates.push_back({ParameterizationKind::Sphere, resolution, spt, true});
  }
  // Cheapest first; ties go to fewer samples (sharper texels), then the order given.
  std::stable_sort(candidates.begin(), candidates.end(), [](const MapConfiguration& a, const MapConfiguration& b) {
    return a.cost() != b.cost() ? a.cost() < b.cost() : a.samplesPerTexel < b.samplesPerTexel;
  });
  const ErrorProbes probes(function, options.error);
  AutoResult result;
  double best = std::numeric_limits<double>::infinity();
  MapConfiguration bestConfiguration;
  double totalCost = 0.0, doneCost = 0.0;
  for (const auto& candidate : candidates) totalCost += static_cast<double>(candidate.cost());
  for (const auto& candidate : candidates) {
    BakeOptions bakeOptions = options.bake;
    const double cost = static_cast<double>(candidate.cost());
    bakeOptions.progress = [&options, doneCost, cost, totalCost](double fraction) {
      if (options.progress) options.progress((doneCost + fraction * cost) / totalCost);
    };
    doneCost += cost;
    if (candidate.radialProfile) {
      RadialProfile profile = bakeRadialProfile(function, *axis, candidate.resolution, candidate.samplesPerTexel, bakeOptions);
      const double error = autoErrorMeasure(measureProfileError(profile, probes, options.error.visibleSphere), candidate, *axis);
      ++result.tried;
      if (error <= options.maxError) {
        result.chosen = candidate;
        result.error = error;
        result.image = profile.toImage();
        result.radialProfile = std::move(profile);
        return result;
      }
      result.rejected.emplace_back(candidate, error);
      if (error < best) best = error, bestConfiguration = candidate;
      continue;
    }
    const auto map = makeParameterization(candidate.parameterization, candidate.resolution);
    bakeOptions.samplesPerTexel = candidate.samplesPerTexel;
    Image image = bake(*map, function, bakeOptions);
    const double error = autoErrorMeasure(measureMapError(image, *map, probes, options.error.visibleSphere), candidate.parameterization);
    ++result.tried;
    if (error <= options.maxError) {
      result.chosen = candidate;
      result.error = error;
      result.image = std::move(image);
      return result;
    }
    result.rejected.emplace_back(candidate, error);
    if (error < best) best = error, bestConfiguration = candidate;
  }
  std::ostringstream message;
  message << "no configuration meets max_error " << options.maxError << ": the best, " << bestConfiguration.describe()
          << ", reaches " << best << "; allow larger resolutions or a larger max_error";
  throw Error(Error::Kind::InvalidInput, message.str());
}

}  // namespace brdfbake
