#include "analysis/sweep/sweep_csv.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "render/run/image_io.h"

namespace fs = std::filesystem;

namespace vpm {

int CsvTable::column(const std::string& name) const {
    for (size_t i = 0; i < header.size(); ++i)
        if (header[i] == name) return int(i);
    return -1;
}

std::string csv_line(const std::vector<std::string>& fields) {
    std::string s;
    for (size_t i = 0; i < fields.size(); ++i) {
        if (i) s += ',';
        const std::string& f = fields[i];
        if (f.find_first_of(",\"\n\r") == std::string::npos) {
            s += f;
        } else {
            s += '"';
            for (char c : f) s += c == '"' ? std::string("\"\"") : std::string(1, c);
            s += '"';
        }
    }
    return s + '\n';
}

std::vector<std::string> parse_csv_line(const std::string& line) {
    std::vector<std::string> out;
    std::string cur;
    bool quoted = false;
    for (size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') cur += '"', ++i;
            else if (c == '"') quoted = false;
            else cur += c;
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            out.push_back(cur);
            cur.clear();
        } else if (c != '\r') {
            cur += c;
        }
    }
    out.push_back(cur);
    return out;
}

namespace {

std::string read_all(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FileError(path.string() + ": cannot read");
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// Splits into complete lines (quoted newlines kept inside a record); `rest` gets a torn tail.
std::vector<std::string> records(const std::string& text, std::string& rest) {
    std::vector<std::string> out;
    std::string cur;
    bool quoted = false;
    for (char c : text) {
        if (c == '"') quoted = !quoted;
        if (c == '\n' && !quoted) {
            out.push_back(cur);
            cur.clear();
        } else {
            cur += c;
        }
    }
    rest = cur;
    return out;
}

}  // namespace

CsvTable read_csv(const fs::path& path) {
    const std::string text = read_all(path);
    std::string rest;
    const auto lines = records(text, rest);
    CsvTable t;
    t.torn_tail = !rest.empty();
    if (lines.empty()) throw FileError(path.string() + ": no header line");
    t.header = parse_csv_line(lines[0]);
    for (size_t i = 1; i < lines.size(); ++i) {
        if (lines[i].empty()) continue;
        auto f = parse_csv_line(lines[i]);
        if (f.size() != t.header.size())
            throw FileError(path.string() + ":" + std::to_string(i + 1) + ": " + std::to_string(f.size()) +
                            " fields, the header has " + std::to_string(t.header.size()) + " (corrupt row)");
        t.rows.push_back(std::move(f));
    }
    return t;
}

void prepare_csv(const fs::path& path, const std::vector<std::string>& header) {
    if (!fs::exists(path)) {
        write_text_atomic(path, csv_line(header));
        return;
    }
    const std::string text = read_all(path);
    const auto nl = text.find('\n');
    if (nl == std::string::npos || parse_csv_line(text.substr(0, nl)) != header)
        throw FileError(path.string() + ": its header does not match this sweep's columns (a different sweep "
                        "file or axes?); use another --out folder");
    if (!text.empty() && text.back() != '\n') {
        // The process died inside a row's write: drop the partial row (rewritten atomically).
        write_text_atomic(path, text.substr(0, text.rfind('\n') + 1));
    }
}

void append_csv_row(const fs::path& path, const std::vector<std::string>& fields) {
    const std::string line = csv_line(fields);
    const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
    if (fd < 0) throw FileError(path.string() + ": cannot open for appending: " + std::strerror(errno));
    const ssize_t n = ::write(fd, line.data(), line.size());
    const int err = errno;
    ::fsync(fd);
    ::close(fd);
    if (n != ssize_t(line.size()))
        throw FileError(path.string() + ": short write appending a row: " + std::strerror(n < 0 ? err : EIO));
}

}  // namespace vpm
