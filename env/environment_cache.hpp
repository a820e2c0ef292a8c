#pragma once
// What an Environment keeps of the work computations do on its radiance (EnvironmentPreparation,
// env/environment.hpp): the split into bright texels and the rest with the rest's mip pyramid, per
// split setting. Private to env/.
#include <brdfbake/env/environment.hpp>

#include <map>
#include <memory>
#include <mutex>
#include <utility>

#include "under_environment_internal.hpp"

namespace brdfbake::detail {

// The environment split into explicit lights and the rest, and the rest's pyramid.
struct PreparedSplit {
  PreparedSplit(EnvironmentSplit s) : split(std::move(s)), rest(split.rest) {}
  EnvironmentSplit split;
  LatLongPyramid rest;
};

struct EnvironmentCache {
  // splitEnvironment(environment, factor, maxTexels) and its rest's pyramid, made once per setting.
  std::shared_ptr<const PreparedSplit> split(const Environment& environment, double factor, int maxTexels);

 private:
  std::mutex mutex_;
  std::map<std::pair<double, int>, std::shared_ptr<const PreparedSplit>> splits_;
};

}  // namespace brdfbake::detail
