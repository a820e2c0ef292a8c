#pragma once
/// @file
/// What every long-running job (baking, prefiltering) takes besides its own settings.

#include <functional>
#include <string>

namespace brdfbake {

/// Most worker threads any job takes (docs/limits.md): far more than any machine has cores, far
/// fewer than would exhaust the thread library (TBB crashed on 70,000).
inline constexpr int kMaxThreads = 1024;

/// Throws Error(InvalidArgument) "<what> must be in [0, 1024] (0 = every core), got N" unless
/// 0 <= threads <= kMaxThreads. Every option struct with a thread count calls it in validate().
void requireThreadCount(int threads, const std::string& what = "threads");

struct RunOptions {
  /// Worker threads, at most kMaxThreads; 0 uses every core.
  int threads = 0;
  /// Largest image the job allocates without `allowLarge`, in texels (default 8192^2 = 1 GiB of
  /// float RGBA).
  long long maxTexels = 8192LL * 8192LL;
  bool allowLarge = false;
  /// Called with the fraction done (0..1), serialised, from worker threads. May be empty.
  std::function<void(double)> progress;

  /// Throws Error(InvalidArgument) unless 0 <= threads <= kMaxThreads and maxTexels > 0.
  void validateRun() const;
  /// Throws Error(Resource) naming the size in GiB when a width x height float RGBA image exceeds
  /// maxTexels and large images are not allowed.
  void requireImageSize(int width, int height) const;
};

}  // namespace brdfbake
