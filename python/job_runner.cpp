#include "job_runner.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace brdfbake::python {

namespace {

// What the job's threads tell the calling thread, and the calling thread's answers: `cancelled`, and
// `delivered`, how many reports it has passed on.
struct JobChannel {
  std::mutex mutex;
  std::condition_variable wake;                         // the calling thread waits on it
  std::condition_variable delivered;                    // a task's last report waits on it
  std::vector<std::pair<std::string, double>> reports;  // the latest fraction of each task not yet passed on
  std::uint64_t reported = 0;                           // reports queued so far
  std::uint64_t passedOn = 0;                           // of which the calling thread has handled
  bool done = false;
  bool waitForLast = false;  // a Python callback takes the reports: a task's last one waits for it
  std::exception_ptr failure;
  std::atomic<bool> cancelled{false};

  // Between reports the calling thread passes on the latest every 50 ms. A task's last report
  // (fraction 1) wakes it and, with a callback, waits until the callback has seen it, so that a callback
  // raising there still stops the job before the task's output is written.
  void report(const std::string& task, double fraction) {
    if (cancelled.load()) throw Cancelled{};
    const bool last = fraction >= 1.0;
    std::unique_lock lock(mutex);
    const auto same = std::find_if(reports.begin(), reports.end(), [&](const auto& r) { return r.first == task; });
    if (same != reports.end())
      same->second = fraction;
    else
      reports.emplace_back(task, fraction);
    const std::uint64_t mine = ++reported;
    if (!last) return;
    wake.notify_one();
    if (!waitForLast) return;
    delivered.wait(lock, [&] { return passedOn >= mine || cancelled.load(); });
    if (cancelled.load()) throw Cancelled{};
  }
};

constexpr auto kPollInterval = std::chrono::milliseconds(50);

}  // namespace

void runJob(const std::function<void(const Context&)>& job, const py::object& progress, int threads, bool allowLarge) {
  auto channel = std::make_shared<JobChannel>();
  channel->waitForLast = !progress.is_none();
  const ProgressSink sink = [channel](const std::string& task, double fraction) { channel->report(task, fraction); };
  const Context context({.threads = threads, .allowLarge = allowLarge, .progress = sink});
  std::thread worker([&job, &context, channel] {
    try {
      job(context);
    } catch (...) {
      channel->failure = std::current_exception();
    }
    {
      const std::lock_guard lock(channel->mutex);
      channel->done = true;
    }
    channel->wake.notify_one();
  });

  std::exception_ptr cancelling;  // the Python exception that cancelled the job
  for (bool done = false; !done;) {
    std::vector<std::pair<std::string, double>> reports;
    std::uint64_t handled = 0;
    {
      const py::gil_scoped_release release;
      std::unique_lock lock(channel->mutex);
      channel->wake.wait_for(lock, kPollInterval, [&] {
        return channel->done || std::any_of(channel->reports.begin(), channel->reports.end(),
                                            [](const auto& r) { return r.second >= 1.0; });
      });
      reports.swap(channel->reports);
      handled = channel->reported;
      done = channel->done;
    }
    if (!cancelling) {
      try {
        if (!progress.is_none()) {
          for (const auto& [task, fraction] : reports) progress(task, fraction);
        }
        if (!done && PyErr_CheckSignals() != 0) throw py::error_already_set();
      } catch (...) {
        cancelling = std::current_exception();
        channel->cancelled = true;
        context.cancel();
      }
    }
    {
      const std::lock_guard lock(channel->mutex);
      channel->passedOn = handled;
    }
    channel->delivered.notify_all();
  }
  {
    const py::gil_scoped_release release;
    worker.join();
  }
  if (cancelling) std::rethrow_exception(cancelling);
  if (channel->failure) {
    try {
      std::rethrow_exception(channel->failure);
    } catch (const Cancelled&) {
      // Only the calling thread cancels, and then `cancelling` is set; unreachable otherwise.
      throw std::runtime_error("brdfbake: a job was cancelled without a reason");
    }
  }
}

}  // namespace brdfbake::python
