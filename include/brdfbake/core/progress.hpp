#pragma once
/// @file
/// Timing and progress reporting shared by every long computation.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <mutex>

namespace brdfbake {

/// Seconds elapsed since `start` on the steady clock.
inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Counts steps done out of `total` from any thread and reports the fraction done to a callback.
/// Reports are serialised; a step that finds another report in progress skips its own, except the
/// last step, which always reports 1.
class ProgressCounter {
 public:
  ProgressCounter(const std::function<void(double)>& callback, std::size_t total)
      : callback_(callback), total_(std::max<std::size_t>(total, 1)) {}

  void step() {
    const std::size_t done = ++done_;
    if (!callback_) return;
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock() && done < total_) return;
    if (!lock.owns_lock()) lock.lock();
    callback_(std::min(1.0, static_cast<double>(done) / static_cast<double>(total_)));
  }

 private:
  const std::function<void(double)>& callback_;
  std::size_t total_;
  std::atomic<std::size_t> done_{0};
  std::mutex mutex_;
};

}  // namespace brdfbake
