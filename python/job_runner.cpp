#include "job_runner.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace brdfbake::python {

namespace {

// What the job's threads tell the calling thread, and the calling thread's answer (cancelled).
struct JobChannel {
  std::mutex mutex;
  std::condition_variable wake;
  std::vector<std::pair<std::string, double>> reports;  // the latest fraction of each task not yet passed on
  bool done = false;
  std::exception_ptr failure;
  std::atomic<bool> cancelled{false};

  void report(const std::string& task, double fraction) {
    if (cancelled.load()) throw JobCancelled{};
    {
      const std::lock_guard lock(mutex);
      const auto same = std::find_if(reports.begin(), reports.end(), [&](const auto& r) { return r.first == task; });
      if (same != reports.end())
        same->second = fraction;
      else
        reports.emplace_back(task, fraction);
    }
    wake.notify_one();
  }
};

constexpr auto kPollInterval = std::chrono::milliseconds(50);

}  // namespace

void runJob(const std::function<void(const ProgressSink&)>& job, const py::object& progress) {
  auto channel = std::make_shared<JobChannel>();
  const ProgressSink sink = [channel](const std::string& task, double fraction) { channel->report(task, fraction); };
  std::thread worker([&job, &sink, channel] {
    try {
      job(sink);
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
    {
      const py::gil_scoped_release release;
      std::unique_lock lock(channel->mutex);
      channel->wake.wait_for(lock, kPollInterval, [&] { return channel->done || !channel->reports.empty(); });
      reports.swap(channel->reports);
      done = channel->done;
    }
    if (cancelling) continue;
    try {
      if (!progress.is_none()) {
        for (const auto& [task, fraction] : reports) progress(task, fraction);
      }
      if (!done && PyErr_CheckSignals() != 0) throw py::error_already_set();
    } catch (...) {
      cancelling = std::current_exception();
      channel->cancelled = true;
    }
  }
  {
    const py::gil_scoped_release release;
    worker.join();
  }
  if (cancelling) std::rethrow_exception(cancelling);
  if (channel->failure) {
    try {
      std::rethrow_exception(channel->failure);
    } catch (const JobCancelled&) {
      // Only the calling thread cancels, and then `cancelling` is set; unreachable otherwise.
      throw std::runtime_error("brdfbake: a job was cancelled without a reason");
    }
  }
}

}  // namespace brdfbake::python
