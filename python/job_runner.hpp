#pragma once
// Running a job of the run layer from Python: without the GIL, with progress, and stoppable by
// Ctrl-C.
//
// The job runs on a thread of its own while the calling (Python) thread waits for it without the
// GIL. Every 50 ms, and at once when a task reports its end (fraction 1), the calling thread takes the
// GIL, passes the latest fraction of each task to the progress callback and runs Python's signal
// handlers (PyErr_CheckSignals, which acts on the main thread only: the job's worker threads could
// not). A task's last report waits until the callback has seen it, so a callback may stop the job
// there, before the task's output is written. When a handler raises (Ctrl-C: KeyboardInterrupt) or
// the callback does, the job's Context is cancelled: its next check throws Cancelled (computations
// check often: a cancel takes effect within a fraction of a second), which unwinds it like any error
// (the unfinished output's temporaries are removed, core/files.hpp), and the Python exception is
// raised once it has stopped. Whatever finished before stays: the maps of a spec already written, for
// instance.
#include <brdfbake/core/context.hpp>

#include <pybind11/pybind11.h>

#include <functional>

namespace brdfbake::python {

namespace py = pybind11;

/// Runs job(context) on a Context of `threads` (0 = every core; checked: Error naming "threads") and
/// `allowLarge`, its progress passed to `progress` (a Python callable (task: str, fraction: float)
/// or None), as described above. Call with the GIL held. Rethrows what the job throws
/// (brdfbake::Error becomes brdfbake.Error), or raises the Python exception that cancelled it.
void runJob(const std::function<void(const Context&)>& job, const py::object& progress, int threads = 0,
            bool allowLarge = false);

}  // namespace brdfbake::python
