#pragma once
// The sweep's CSV files: one row per finished run, appended and flushed as each run ends, so a
// killed sweep loses at most the run in flight. Each row goes out in a single write(2) on an
// O_APPEND descriptor followed by fsync; a reader treats a last line without its newline as torn
// (the process died inside the write) and ignores it, and resume truncates it away before
// appending. Fields are quoted (RFC 4180) when they hold a comma, quote or newline.
#include <filesystem>
#include <string>
#include <vector>

namespace vpm {

struct CsvTable {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    bool torn_tail = false;   // a last line without newline was ignored
    int column(const std::string& name) const;   // -1 if absent
};

std::string csv_line(const std::vector<std::string>& fields);   // with the trailing '\n'
std::vector<std::string> parse_csv_line(const std::string& line);

// Reads a CSV (header + rows). Throws FileError if it cannot be read, or if a complete row has a
// different number of fields than the header (corruption is reported, not skipped).
CsvTable read_csv(const std::filesystem::path& path);

// Opens `path` for appending rows with `header`: creates it (header only, atomically) when absent;
// otherwise checks the header matches (FileError if not) and cuts a torn last line.
void prepare_csv(const std::filesystem::path& path, const std::vector<std::string>& header);
// One row in one write(2) + fsync. Throws FileError.
void append_csv_row(const std::filesystem::path& path, const std::vector<std::string>& fields);

}  // namespace vpm
