#pragma once
/// @file
/// What every long-running job (baking, prefiltering) takes besides its own settings.

#include <functional>

namespace brdfbake {

struct RunOptions {
  /// Worker threads; 0 uses every core.
  int threads = 0;
  /// Largest image the job allocates without `allowLarge`, in texels (default 8192^2 = 1 GiB of
  /// float RGBA).
  long long maxTexels = 8192LL * 8192LL;
  bool allowLarge = false;
  /// Called with the fraction done (0..1), serialised, from worker threads. May be empty.
  std::function<void(double)> progress;

  /// Throws Error(InvalidArgument) unless threads >= 0 and maxTexels > 0.
  void validateRun() const;
  /// Throws Error(Resource) naming the size in GiB when a width x height float RGBA image exceeds
  /// maxTexels and large images are not allowed.
  void requireImageSize(int width, int height) const;
};

}  // namespace brdfbake
