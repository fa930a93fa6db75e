#include "native_call.h"

#include <chrono>
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include <pybind11/pybind11.h>
#include <string>

#include "core/error.h"
#include "core/thread_limit.h"
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

namespace py = pybind11;

namespace vpm::python {

void check_threads(int threads) {
    if (threads < 0 || threads > kMaxThreads)
        throw Error("threads: expected 0 (all cores) to " + std::to_string(kMaxThreads) + ", got " + std::to_string(threads));
}

void call_native(const std::function<void(const std::atomic<bool>& interrupted)>& work, int threads) {
    check_threads(threads);
    std::optional<tbb::global_control> limit;
    if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, size_t(threads));
    tbb::task_group_context context;
    std::atomic<bool> interrupted{false};
    std::exception_ptr failure;
    std::unique_ptr<py::error_already_set> signal;   // the exception a signal handler raised
    std::mutex mutex;
    std::condition_variable finished_cv;
    bool finished = false;
    {
        py::gil_scoped_release release;
        std::thread helper([&] {
            try {
                // One task in `context`: nested parallel loops bind to it and see its cancellation.
                tbb::parallel_for(0, 1, [&](int) { work(interrupted); }, context);
            } catch (...) {
                failure = std::current_exception();
            }
            std::lock_guard<std::mutex> lock(mutex);
            finished = true;
            finished_cv.notify_one();
        });
        std::unique_lock<std::mutex> lock(mutex);
        while (!finished) {
            finished_cv.wait_for(lock, std::chrono::milliseconds(50));
            if (finished || signal) continue;   // after the first signal: wait for the work to wind down
            lock.unlock();
            {
                py::gil_scoped_acquire acquire;
                if (PyErr_CheckSignals() != 0) {
                    signal = std::make_unique<py::error_already_set>();
                    interrupted = true;
                    context.cancel_group_execution();
                }
            }
            lock.lock();
        }
        lock.unlock();
        helper.join();
    }
    if (signal) throw *signal;
    if (failure) std::rethrow_exception(failure);
}

}  // namespace vpm::python
