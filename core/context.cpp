#include <brdfbake/core/context.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/memory_budget.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>

namespace brdfbake {

struct Context::Shared {
  ProgressSink sink;
  std::mutex reporting;
  std::atomic<bool> cancelled{false};
};

Context::Context() : shared_(std::make_shared<Shared>()), reached_(std::make_shared<double>(0.0)) {}

Context::Context(Options options) : shared_(std::make_shared<Shared>()), reached_(std::make_shared<double>(0.0)) {
  requireThreadCount(options.threads);
  threads_ = options.threads;
  allowLarge_ = options.allowLarge;
  shared_->sink = std::move(options.progress);
}

void Context::requireThreadCount(int threads, const std::string& what) {
  require(threads >= 0 && threads <= kMaxThreads, what + " must be in [0, " + std::to_string(kMaxThreads) +
                                                      "] (0 = every core), got " + std::to_string(threads));
}

void Context::requireImageSize(int width, int height, const std::string& where) const {
  const double bytes = 16.0 * static_cast<double>(width) * static_cast<double>(height);
  const std::string size =
      (where.empty() ? "" : where + ": ") + "a " + std::to_string(width) + " x " + std::to_string(height) + " map";
  if (static_cast<long long>(width) * height > kMaxTexels && !allowLarge_) {
    throw Error(Error::Kind::Resource, size + " needs " + formatBytes(bytes) +
                                           " of float RGBA, more than the limit of " +
                                           formatBytes(16.0 * static_cast<double>(kMaxTexels)) +
                                           "; lower the resolution or allow large maps (--allow-large)");
  }
  requireWithinMemoryBudget(bytes, size);
}

Context Context::task(std::string name) const {
  Context copy = *this;
  copy.task_ = std::move(name);
  copy.reached_ = std::make_shared<double>(0.0);
  copy.offset_ = 0.0, copy.scale_ = 1.0;
  return copy;
}

Context Context::withThreads(int threads) const {
  requireThreadCount(threads);
  Context copy = *this;
  copy.threads_ = threads;
  return copy;
}

Context Context::withoutProgress() const {
  Context copy = *this;
  copy.quiet_ = true;
  return copy;
}

Context Context::part(double from, double to) const {
  Context copy = *this;
  copy.offset_ = offset_ + scale_ * from;
  copy.scale_ = scale_ * (to - from);
  return copy;
}

void Context::report(double fraction) const {
  checkCancelled();
  if (!shared_->sink || quiet_) return;
  const std::lock_guard lock(shared_->reporting);
  const double f = std::clamp(std::isfinite(fraction) ? fraction : 0.0, 0.0, 1.0);
  *reached_ = std::max(*reached_, std::clamp(offset_ + scale_ * f, 0.0, 1.0));
  shared_->sink(task_, *reached_);
}

std::function<void(double)> Context::progress() const {
  return [copy = *this](double fraction) { copy.report(fraction); };
}

void Context::cancel() const noexcept { shared_->cancelled.store(true, std::memory_order_relaxed); }

bool Context::cancelled() const noexcept { return shared_->cancelled.load(std::memory_order_relaxed); }

void Context::checkCancelled() const {
  if (cancelled()) throw Cancelled();
}

}  // namespace brdfbake
