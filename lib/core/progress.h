#pragma once
// A progress bar on stderr for long runs: "label [=====>    ] 45% 12.3 s, ETA 15.1 s".
// Silent when disabled, when stderr is not a terminal, or for runs shorter than a second.
// Thread-safe: workers call advance() from any thread.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace vpm {

class Progress {
public:
    Progress(std::string label, uint64_t total, bool enabled = true);
    ~Progress();   // calls done()
    void advance(uint64_t amount = 1);
    void done();

private:
    void draw(bool final);
    std::string label_;
    uint64_t total_;
    bool enabled_;
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

}  // namespace vpm
