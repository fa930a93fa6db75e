#pragma once
// Atomic replacement of output files. A StagedFile is written under a temporary name beside its
// destination ("<dest>.tmp-<pid>-<n>") and renamed over it by commit(); until then the
// destination is untouched, and the temporary is removed on destruction, on failure and (once
// remove_temporaries_on_signals() is installed) on SIGINT, SIGTERM and SIGHUP.
//
// Destinations follow the rule of `cp`: a symlink is written through (its final target is
// replaced, the link stays); an existing destination must be a regular file (a device, FIFO,
// socket or folder is refused with FileError naming what it is), and its folder must exist.
#include <filesystem>
#include <string>
#include <vector>

namespace vpm {

class StagedFile {
public:
    // Checks the destination (check_output_file) and picks the temporary name; creates nothing.
    explicit StagedFile(const std::filesystem::path& destination);
    StagedFile(StagedFile&& other) noexcept;
    StagedFile& operator=(StagedFile&&) = delete;
    StagedFile(const StagedFile&) = delete;
    StagedFile& operator=(const StagedFile&) = delete;
    ~StagedFile();   // removes the temporary unless committed

    const std::filesystem::path& temp() const { return temp_; }
    // The path as given, and the file that commit() replaces (symlinks followed).
    const std::filesystem::path& path() const { return path_; }
    const std::filesystem::path& target() const { return target_; }

    // Removes the temporary and throws FileError "<path>: <reason>".
    [[noreturn]] void abort(const std::string& reason);
    // Renames the temporary over the target. Throws FileError (temporary removed).
    void commit();

private:
    std::filesystem::path path_, target_, temp_;
    int slot_ = -1;   // entry in the signal-cleanup table
    bool done_ = false;
};

// Renames every file while holding an exclusive advisory lock (flock) on each target's folder,
// so that concurrent runs writing the same outputs each replace the whole set: afterwards the
// files all come from one run. Readers that need a consistent set take the same lock.
void commit_together(std::vector<StagedFile>& files);

// The file `path` resolves to (symlinks followed, also dangling ones). Throws FileError for a
// symlink loop.
std::filesystem::path resolve_output_target(const std::filesystem::path& path);

// Throws FileError unless `path` can be replaced by a regular file: names a file, its folder
// exists and is a folder, and it is absent or a regular file (after following symlinks).
void check_output_file(const std::filesystem::path& path);

// Creates `folder` (and parents) and proves it writable by creating and removing a probe file.
// Throws FileError naming the folder and why. Call before long work that ends in writing there.
void prepare_output_folder(const std::filesystem::path& folder);

// Installs SIGINT/SIGTERM/SIGHUP handlers that remove live temporaries, then re-raise the signal
// with its default action (so the exit status still says which signal ended the process).
void remove_temporaries_on_signals();

}  // namespace vpm
