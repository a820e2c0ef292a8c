#include "environment_cache.hpp"

namespace brdfbake {

EnvironmentPreparation::EnvironmentPreparation() : cache_(std::make_unique<detail::EnvironmentCache>()) {}
EnvironmentPreparation::~EnvironmentPreparation() = default;
EnvironmentPreparation::EnvironmentPreparation(const EnvironmentPreparation&) : EnvironmentPreparation() {}
EnvironmentPreparation& EnvironmentPreparation::operator=(const EnvironmentPreparation&) {
  cache_ = std::make_unique<detail::EnvironmentCache>();
  return *this;
}
EnvironmentPreparation::EnvironmentPreparation(EnvironmentPreparation&& other) noexcept
    : cache_(std::exchange(other.cache_, std::make_unique<detail::EnvironmentCache>())) {}
EnvironmentPreparation& EnvironmentPreparation::operator=(EnvironmentPreparation&& other) noexcept {
  std::swap(cache_, other.cache_);
  return *this;
}

namespace detail {

std::shared_ptr<const PreparedSplit> EnvironmentCache::split(const Environment& environment, double factor,
                                                             int maxTexels) {
  const std::pair<double, int> key{factor, maxTexels};
  {
    const std::lock_guard lock(mutex_);
    if (const auto found = splits_.find(key); found != splits_.end()) return found->second;
  }
  // Made outside the lock (it takes time; two threads may both make it, and one is kept).
  auto made = std::make_shared<const PreparedSplit>(splitEnvironment(environment, factor, maxTexels));
  const std::lock_guard lock(mutex_);
  return splits_.try_emplace(key, std::move(made)).first->second;
}

}  // namespace detail
}  // namespace brdfbake
