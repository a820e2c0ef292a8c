#pragma once
/// @file
/// Timing and progress reporting shared by every long computation.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <mutex>
#include <string>
#include <utility>

namespace brdfbake {

/// Seconds elapsed since `start` on the steady clock.
inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Progress of a job as the library reports it to a front end (the CLI, a Python callback):
/// `task` names the step ("maps[0] phong_eye.exr", "fit garnet_red.astm"), `fraction` is the part of
/// it done, in [0, 1]; each task ends with 1. Calls are serialised within a task but may come from
/// worker threads. A sink may throw to cancel the job: the exception leaves the job's call, and the
/// unfinished step leaves no output behind (its temporaries are removed).
using ProgressSink = std::function<void(const std::string& task, double fraction)>;

/// The fraction callback of one task of `sink` (the form BakeOptions::progress and the other
/// computations take); empty when `sink` is.
inline std::function<void(double)> progressFor(const ProgressSink& sink, const std::string& task) {
  if (!sink) return {};
  return [sink, task](double fraction) { sink(task, fraction); };
}

/// Counts steps done out of `total` from any thread and reports the fraction done to a callback
/// (Context::progress(), which also checks for cancellation, so a loop that counts its steps stops
/// within a step of a cancel). Reports are serialised; a step that finds another report in progress
/// skips its own, except the last step, which always reports 1.
class ProgressCounter {
 public:
  ProgressCounter(std::function<void(double)> callback, std::size_t total)
      : callback_(std::move(callback)), total_(std::max<std::size_t>(total, 1)) {}

  void step() {
    const std::size_t done = ++done_;
    if (!callback_) return;
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock() && done < total_) return;
    if (!lock.owns_lock()) lock.lock();
    callback_(std::min(1.0, static_cast<double>(done) / static_cast<double>(total_)));
  }

 private:
  std::function<void(double)> callback_;
  std::size_t total_;
  std::atomic<std::size_t> done_{0};
  std::mutex mutex_;
};

}  // namespace brdfbake
