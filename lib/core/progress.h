#pragma once
// Progress of long runs on stderr. On a terminal, a bar redrawn in place:
// "label [=====>    ] 45% 12.3 s, ETA 15.1 s" (nothing for runs shorter than a second). When
// stderr is a file or a pipe (a log), one line every 5 seconds instead,
// "label: 45% (450/1000), 12.3 s, ETA 15.1 s", and a last "label: 100%" line; the interval comes
// from the environment variable VPM_PROGRESS_SECONDS when set (0: a line at every advance).
// Silent when disabled. Thread-safe: workers call advance() from any thread.
// Counting milliseconds (a run against its time limit) the line reads "(1.2 s/2.0 s)" and the ETA
// is the time left.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace vpm {

class Progress {
public:
    enum class Unit { items, milliseconds };
    Progress(std::string label, uint64_t total, bool enabled = true, Unit unit = Unit::items);
    ~Progress();   // calls done()
    void advance(uint64_t amount = 1);
    void done();

private:
    void draw(bool final);
    void draw_bar(bool final);
    void draw_line(bool final);
    std::string label_;
    uint64_t total_;
    bool enabled_;
    Unit unit_;
    bool terminal_ = false;        // a bar on a terminal, else log lines
    int64_t first_ms_ = 0, every_ms_ = 0;
    std::atomic<uint64_t> count_{0};
    std::chrono::steady_clock::time_point start_;
    std::atomic<int64_t> last_draw_ms_{-1000000};
    std::mutex draw_mutex_;
    bool finished_ = false;
    bool drew_ = false;
};

// Wall-clock seconds since construction.
class Timer {
public:
    Timer() : start_(std::chrono::steady_clock::now()) {}
    double seconds() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }

private:
    std::chrono::steady_clock::time_point start_;
};

// Peak resident set size of this process so far, in bytes (getrusage).
uint64_t peak_rss_bytes();
// Physical memory of the machine, in bytes.
uint64_t physical_memory_bytes();
// The memory this process may use, in bytes: the physical memory, or less where the process's
// address-space limit (ulimit -v, RLIMIT_AS) or its cgroup's memory.max sets less. The memory
// guards compare their projections with this, so a run under a limit is refused, not killed.
uint64_t memory_limit_bytes();

}  // namespace vpm
