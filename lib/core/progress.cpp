#include "core/progress.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace vpm {
namespace {

constexpr int64_t kQuietMs = 1000;      // nothing is drawn during the first second
constexpr int64_t kRedrawMs = 100;      // at most ~10 redraws a second
constexpr int kBarWidth = 30;
constexpr int64_t kLogLineMs = 5000;    // a log line every 5 s when stderr is not a terminal

// VPM_PROGRESS_SECONDS, or the default.
int64_t log_interval_ms() {
    const char* env = std::getenv("VPM_PROGRESS_SECONDS");
    if (!env || !*env) return kLogLineMs;
    char* end = nullptr;
    const double s = std::strtod(env, &end);
    if (*end != '\0' || !(s >= 0.0) || s > 1e6) return kLogLineMs;
    return int64_t(s * 1000.0);
}

std::string format_seconds(double s) {
    char buf[32];
    if (s < 60.0) {
        std::snprintf(buf, sizeof(buf), "%.1f s", s);
    } else if (s < 3600.0) {
        std::snprintf(buf, sizeof(buf), "%dm%02ds", int(s / 60.0), int(s) % 60);
    } else {
        std::snprintf(buf, sizeof(buf), "%dh%02dm", int(s / 3600.0), (int(s) / 60) % 60);
    }
    return buf;
}

}  // namespace

Progress::Progress(std::string label, uint64_t total, bool enabled, Unit unit)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled && total > 0),
      unit_(unit),
      terminal_(::isatty(2) == 1),
      start_(std::chrono::steady_clock::now()) {
    if (terminal_) {
        first_ms_ = kQuietMs;
        every_ms_ = kRedrawMs;
    } else if (enabled_) {
        first_ms_ = every_ms_ = log_interval_ms();
    }
    last_draw_ms_ = -every_ms_ - 1;
}

Progress::~Progress() { done(); }

void Progress::advance(uint64_t amount) {
    count_.fetch_add(amount, std::memory_order_relaxed);
    if (!enabled_) return;
    const int64_t now_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                               std::chrono::steady_clock::now() - start_)
                               .count();
    if (now_ms < first_ms_) return;
    int64_t last = last_draw_ms_.load(std::memory_order_relaxed);
    if (now_ms - last < every_ms_) return;
    // Only one thread wins the right to draw this frame; the others return at once.
    if (!last_draw_ms_.compare_exchange_strong(last, now_ms, std::memory_order_relaxed)) return;
    std::unique_lock<std::mutex> lock(draw_mutex_, std::try_to_lock);
    if (!lock.owns_lock() || finished_) return;
    draw(false);
}

void Progress::done() {
    std::lock_guard<std::mutex> lock(draw_mutex_);
    if (finished_) return;
    finished_ = true;
    if (enabled_ && drew_) draw(true);   // a run that never drew stays silent
}

// Called with draw_mutex_ held.
void Progress::draw(bool final) {
    if (terminal_) draw_bar(final);
    else draw_line(final);
    drew_ = true;
}

void Progress::draw_line(bool final) {
    const uint64_t count = std::min(count_.load(std::memory_order_relaxed), total_);
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    char head[96];
    if (unit_ == Unit::milliseconds)
        std::snprintf(head, sizeof(head), ": %d%% (%.1f s/%.1f s), ", int(100.0 * double(count) / double(total_)),
                      double(count) / 1000.0, double(total_) / 1000.0);
    else
        std::snprintf(head, sizeof(head), ": %d%% (%llu/%llu), ", int(100.0 * double(count) / double(total_)),
                      (unsigned long long)count, (unsigned long long)total_);
    std::string line = label_ + head + format_seconds(elapsed);
    if (!final) line += ", ETA " + (count > 0 ? format_seconds(elapsed * double(total_ - count) / double(count)) : "?");
    line += "\n";
    std::fwrite(line.data(), 1, line.size(), stderr);   // one write: lines from threads never mix
    std::fflush(stderr);
}

void Progress::draw_bar(bool final) {
    const uint64_t count = std::min(count_.load(std::memory_order_relaxed), total_);
    const double fraction = total_ > 0 ? double(count) / double(total_) : 1.0;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();

    std::string bar(kBarWidth, ' ');
    const int filled = int(fraction * kBarWidth);
    for (int i = 0; i < filled && i < kBarWidth; ++i) bar[size_t(i)] = '=';
    if (filled < kBarWidth) bar[size_t(filled)] = '>';

    std::string line = "\r" + label_ + " [" + bar + "] ";
    char pct[16];
    std::snprintf(pct, sizeof(pct), "%3d%% ", int(fraction * 100.0));
    line += pct;
    line += format_seconds(elapsed);
    if (!final) {
        line += ", ETA ";
        line += count > 0 ? format_seconds(elapsed * double(total_ - count) / double(count)) : "?";
    }
    line += "\x1b[K";   // clear the rest of the line (stderr is a terminal here)
    if (final) line += "\n";
    std::fwrite(line.data(), 1, line.size(), stderr);
    std::fflush(stderr);
}

uint64_t peak_rss_bytes() {
    struct rusage usage {};
    if (::getrusage(RUSAGE_SELF, &usage) != 0) return 0;
    return uint64_t(usage.ru_maxrss) * 1024u;   // Linux reports kilobytes
}

uint64_t physical_memory_bytes() {
    const long pages = ::sysconf(_SC_PHYS_PAGES);
    const long page_size = ::sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || page_size <= 0) return 0;
    return uint64_t(pages) * uint64_t(page_size);
}

uint64_t memory_limit_bytes() {
    uint64_t limit = physical_memory_bytes();
    if (limit == 0) limit = UINT64_MAX;
    struct rlimit r {};
    if (::getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY) limit = std::min<uint64_t>(limit, uint64_t(r.rlim_cur));
    // cgroup v2: "max" or a byte count.
    std::ifstream cgroup("/sys/fs/cgroup/memory.max");
    std::string text;
    if (cgroup >> text && text != "max") {
        char* end = nullptr;
        const unsigned long long bytes = std::strtoull(text.c_str(), &end, 10);
        if (end && *end == '\0' && bytes > 0) limit = std::min<uint64_t>(limit, uint64_t(bytes));
    }
    return limit == UINT64_MAX ? 0 : limit;
}

}  // namespace vpm
