// Temporary-then-rename writes, the advisory lock that keeps one run's files together, and the
// signal handler that removes temporaries when a run is interrupted.
#include "render/run/staged_file.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <set>
#include <system_error>

#include "core/error.h"

namespace fs = std::filesystem;

namespace vpm {
namespace {

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

// The longest ".tmp-<pid>-<n>" a StagedFile appends: 5 + a 10-digit pid + 1 + a 20-digit counter.
constexpr size_t kTemporarySuffixBytes = 36;

[[noreturn]] void fail(const fs::path& path, const std::string& reason) {
    throw FileError(path.string() + ": " + reason);
}

const char* kind_of(fs::file_type t) {
    switch (t) {
        case fs::file_type::directory: return "a folder";
        case fs::file_type::character: return "a character device";
        case fs::file_type::block: return "a block device";
        case fs::file_type::fifo: return "a FIFO";
        case fs::file_type::socket: return "a socket";
        default: return "not a regular file";
    }
}

// Live temporaries, for the signal handler: a fixed table (no allocation, no locks) whose
// entries are claimed with a compare-and-swap. state: 0 free, 1 being filled, 2 live.
constexpr int kSlots = 64;
constexpr size_t kMaxPath = 4096;
struct Slot {
    std::atomic<int> state{0};
    char path[kMaxPath];
};
Slot g_slots[kSlots];

int register_temporary(const fs::path& p) {
    const std::string& s = p.native();
    if (s.size() >= kMaxPath) return -1;
    for (int i = 0; i < kSlots; ++i) {
        int expected = 0;
        if (!g_slots[i].state.compare_exchange_strong(expected, 1)) continue;
        std::memcpy(g_slots[i].path, s.c_str(), s.size() + 1);
        g_slots[i].state.store(2);
        return i;
    }
    return -1;   // table full: still removed on failure and destruction, only not on a signal
}

void unregister_temporary(int slot) {
    if (slot >= 0) g_slots[slot].state.store(0);
}

extern "C" void remove_temporaries_and_reraise(int sig) {
    for (auto& slot : g_slots)
        if (slot.state.load() == 2) ::unlink(slot.path);   // async-signal-safe
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

// Closes the folder descriptors (and so drops their locks) however commit_together ends.
struct FolderLocks {
    std::vector<int> fds;
    ~FolderLocks() {
        for (int fd : fds) ::close(fd);
    }
};

}  // namespace

fs::path resolve_output_target(const fs::path& path) {
    fs::path p = path;
    for (int i = 0; i < 40; ++i) {
        std::error_code ec;
        if (!fs::is_symlink(fs::symlink_status(p, ec))) return p;
        const fs::path link = fs::read_symlink(p, ec);
        if (ec) fail(path, "cannot write: cannot read symbolic link " + quoted(p) + ": " + ec.message());
        p = link.is_absolute() ? link : p.parent_path() / link;
    }
    fail(path, "cannot write: too many levels of symbolic links");
}

void check_output_file(const fs::path& path) {
    if (path.empty()) throw FileError("(empty path): cannot write: no file name given");
    if (!path.has_filename() || path.filename() == "." || path.filename() == "..")
        fail(path, "cannot write: the path names a folder, not a file");
    const fs::path target = resolve_output_target(path);
    const std::string via = target == path ? std::string() : " (symbolic link to " + quoted(target) + ")";
    const fs::path parent = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::error_code ec;
    const fs::file_status folder = fs::status(parent, ec);
    if (!fs::exists(folder)) fail(path, "cannot write" + via + ": folder " + quoted(parent) + " does not exist");
    if (!fs::is_directory(folder)) fail(path, "cannot write" + via + ": " + quoted(parent) + " is not a folder");
    const fs::file_status st = fs::symlink_status(target, ec);
    if (fs::exists(st) && !fs::is_regular_file(st))
        fail(path, std::string("cannot write") + via + ": it is " + kind_of(st.type()) +
                       "; vpm only replaces regular files");
    // The temporary (".tmp-<pid>-<n>" after the name) must fit the folder's name limit too, or
    // the write would fail only at the end.
    const long name_max = ::pathconf(parent.c_str(), _PC_NAME_MAX);
    const size_t name = target.filename().string().size();
    if (name_max > 0 && name + kTemporarySuffixBytes > size_t(name_max))
        fail(path, "cannot write" + via + ": the file name is " + std::to_string(name) + " bytes; this folder allows " +
                       std::to_string(name_max) + " and vpm writes through a temporary name " +
                       std::to_string(kTemporarySuffixBytes) + " bytes longer, so at most " +
                       std::to_string(size_t(name_max) - kTemporarySuffixBytes) + " bytes");
}

void prepare_output_folder(const fs::path& folder_in) {
    const fs::path folder = folder_in.empty() ? fs::path(".") : folder_in;
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (!fs::is_directory(folder)) {
        const std::string why = ec ? ec.message() : std::string("it exists and is not a folder");
        fail(folder, "cannot create output folder: " + why);
    }
    static std::atomic<unsigned long> counter{0};
    const fs::path probe =
        folder / (".vpm-write-probe-" + std::to_string(long(::getpid())) + "-" + std::to_string(counter++));
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0) {
        const int err = errno;
        fail(folder, std::string("cannot write in output folder: ") + std::strerror(err));
    }
    ::close(fd);
    ::unlink(probe.c_str());
}

StagedFile::StagedFile(const fs::path& destination) : path_(destination) {
    check_output_file(destination);
    target_ = resolve_output_target(destination);
    static std::atomic<unsigned long> counter{0};
    temp_ = target_;
    temp_ += ".tmp-" + std::to_string(long(::getpid())) + "-" + std::to_string(counter++);
    slot_ = register_temporary(temp_);
}

StagedFile::StagedFile(StagedFile&& other) noexcept
    : path_(std::move(other.path_)), target_(std::move(other.target_)), temp_(std::move(other.temp_)),
      slot_(other.slot_), done_(other.done_) {
    other.slot_ = -1;
    other.done_ = true;
}

StagedFile::~StagedFile() {
    if (done_) return;
    std::error_code ec;
    fs::remove(temp_, ec);
    unregister_temporary(slot_);
}

void StagedFile::abort(const std::string& reason) {
    std::error_code ec;
    fs::remove(temp_, ec);
    unregister_temporary(slot_);
    slot_ = -1;
    done_ = true;
    fail(path_, reason);
}

void StagedFile::commit() {
    if (done_) fail(path_, "internal: staged file committed twice");
    if (std::rename(temp_.c_str(), target_.c_str()) != 0) {
        const int err = errno;
        abort(std::string("cannot write: rename from temporary file failed: ") + std::strerror(err));
    }
    unregister_temporary(slot_);
    slot_ = -1;
    done_ = true;
}

void commit_together(std::vector<StagedFile>& files) {
    // One lock per folder, taken in a fixed (sorted) order so two runs never wait on each other.
    std::set<std::string> folders;
    for (const auto& f : files) {
        const fs::path parent = f.target().parent_path().empty() ? fs::path(".") : f.target().parent_path();
        folders.insert(fs::absolute(parent).lexically_normal().string());
    }
    FolderLocks locks;
    for (const auto& folder : folders) {
        const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        if (fd < 0) {
            const int err = errno;
            fail(folder, std::string("cannot lock output folder: ") + std::strerror(err));
        }
        locks.fds.push_back(fd);
        while (::flock(fd, LOCK_EX) != 0) {
            if (errno == EINTR) continue;
            const int err = errno;
            fail(folder, std::string("cannot lock output folder: ") + std::strerror(err));
        }
    }
    for (auto& f : files) f.commit();
}

void remove_temporaries_on_signals() {
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
        struct sigaction old {};
        if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;   // e.g. nohup
        struct sigaction sa {};
        sa.sa_handler = remove_temporaries_and_reraise;
        sigemptyset(&sa.sa_mask);
        ::sigaction(sig, &sa, nullptr);
    }
}

}  // namespace vpm
