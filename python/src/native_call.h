#pragma once
// Native work called from Python: the GIL is released while it runs, and Ctrl-C stops it.
//
// The work runs on a helper thread inside one TBB task_group_context; the calling (Python) thread
// waits and runs Python's signal handlers every 50 ms. When a handler raises (Ctrl-C:
// KeyboardInterrupt), the context is cancelled, so every parallel loop of the work (render rows,
// photon batches, study trials) returns at once; the flag handed to the work turns true so that
// loops between passes or sweep runs can stop too. The partial result is discarded and the
// Python exception is raised once the helper thread has returned: nothing is written, no
// half-built object reaches Python (the tool's guarantee: an interrupted run leaves no output).
#include <atomic>
#include <functional>

namespace vpm::python {

// Throws vpm::Error unless 0 <= threads <= kMaxThreads (the tool's --threads range).
void check_threads(int threads);

// Runs work(interrupted) as described above. Exceptions thrown by the work propagate unchanged.
// `threads` > 0 limits TBB's workers for the call (tbb::global_control, like `--threads`);
// outside check_threads' range it throws before any work.
void call_native(const std::function<void(const std::atomic<bool>& interrupted)>& work, int threads = 0);

}  // namespace vpm::python
