#pragma once
/// @file
/// The execution context every computation of the library takes, as Filament's libs/ibl takes a
/// `JobSystem&`: the worker threads, the memory limits, where progress goes and whether the caller
/// has cancelled, in one object.
///
///   Context context({.threads = 2, .progress = [](const std::string& task, double f) { ... }});
///   MatcapResult made = makeMatcap(request, context);   // another thread may call context.cancel()
///
/// Copies share the progress sink and the cancellation flag: task() gives a copy that reports under
/// another task name, so one cancel() stops every part of a job. Long loops call checkCancelled()
/// (or report(), which checks too) often enough that a cancel takes effect within a fraction of a
/// second; the call then throws Cancelled, which unwinds like any error (outputs not yet committed
/// are removed, core/files.hpp). A Context is safe to use from several threads at once.

#include <brdfbake/core/progress.hpp>

#include <exception>
#include <functional>
#include <memory>
#include <string>

namespace brdfbake {

/// Most worker threads a context takes (docs/limits.md): far more than any machine has cores, far
/// fewer than would exhaust the thread library (TBB crashed on 70,000).
inline constexpr int kMaxThreads = 1024;

/// Largest image a computation allocates unless large images are allowed: 8192^2 texels (1 GiB of
/// float RGBA). The memory budget (memory_budget.hpp) applies to every size.
inline constexpr long long kMaxTexels = 8192LL * 8192LL;

/// What a computation throws once its Context is cancelled. Deliberately not a brdfbake::Error (nor
/// a std::runtime_error): no layer takes it for a failure to report and carry on from (a spec's
/// failed map, a fit's failed candidate); it leaves the job's call.
class Cancelled : public std::exception {
 public:
  const char* what() const noexcept override { return "cancelled"; }
};

class Context {
 public:
  struct Options {
    /// Worker threads, 0 = every core; at most kMaxThreads.
    int threads = 0;
    /// Allow images over kMaxTexels texels (the memory budget still applies).
    bool allowLarge = false;
    /// Where progress goes (empty: nowhere). See ProgressSink; a sink may also throw to cancel.
    ProgressSink progress;
  };

  /// Every core, no large images, no progress.
  Context();
  /// Throws Error(InvalidArgument) "threads must be in [0, 1024] (0 = every core), got N".
  explicit Context(Options options);

  /// The thread count asked for (0 = every core): what tbb::task_arena takes, through arenaThreads().
  int threads() const { return threads_; }
  /// The thread count for a tbb::task_arena: threads(), or tbb::task_arena::automatic (-1) for 0.
  int arenaThreads() const { return threads_ > 0 ? threads_ : -1; }
  bool allowLarge() const { return allowLarge_; }

  /// Throws Error(Resource) "[where: ]a W x H map needs N GiB ..." when a width x height float RGBA
  /// image exceeds kMaxTexels without allowLarge(), or the memory budget (requireWithinMemoryBudget).
  void requireImageSize(int width, int height, const std::string& where = {}) const;

  /// This context reporting its progress as `name` (the same threads, limits, sink and cancellation).
  Context task(std::string name) const;
  /// This context for a part of the current task that spans [from, to] of it: the part's fraction f is
  /// reported as from + (to - from) f (parts of parts compose).
  Context part(double from, double to) const;
  /// This context on `threads` threads (0 = every core; the same sink and cancellation), for work
  /// that runs inside another parallel loop (a fit of each held-out split).
  Context withThreads(int threads) const;
  /// This context with its reports going nowhere (cancellation is still checked), for parts whose
  /// progress would mislead (fits running side by side).
  Context withoutProgress() const;
  /// The task progress is reported under ("" unless task() named one).
  const std::string& taskName() const { return task_; }
  /// Reports `fraction` (in [0, 1]) of the current task to the sink, after checkCancelled(). Calls
  /// are serialised, so a sink needs no lock of its own, and a task's reports never go backwards: a
  /// fraction below the furthest the task (any of its parts) reached is sent as that furthest, so
  /// threads reporting out of order do not make a bar jump back.
  void report(double fraction) const;
  /// report() as a callback, for the computations that count their steps (ProgressCounter).
  std::function<void(double)> progress() const;

  /// Asks every computation using this context (or a copy) to stop. Safe from any thread; cheap.
  void cancel() const noexcept;
  bool cancelled() const noexcept;
  /// Throws Cancelled once cancel() was called.
  void checkCancelled() const;

  /// Throws Error(InvalidArgument) "<what> must be in [0, 1024] (0 = every core), got N" unless
  /// 0 <= threads <= kMaxThreads.
  static void requireThreadCount(int threads, const std::string& what = "threads");

 private:
  struct Shared;
  std::shared_ptr<Shared> shared_;
  int threads_ = 0;
  bool allowLarge_ = false;
  std::string task_;
  std::shared_ptr<double> reached_;    // the furthest fraction this task reported (guarded by Shared)
  double offset_ = 0.0, scale_ = 1.0;  // part(): fraction f of the part is offset_ + scale_ f of the task
  bool quiet_ = false;                 // withoutProgress()
};

}  // namespace brdfbake
