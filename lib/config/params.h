#pragma once
// A parameter dictionary over one TOML table (after pbrt-v4's ParameterDictionary).
//
// Objects read their parameters through it; every read is recorded, with the value actually used
// (defaults included) copied into a "resolved" table. Afterwards finish() reports the first key
// nobody read as an unknown-key error with its line. So unknown-key errors fall out of the
// objects' own reads, not from a hand-maintained list, and the resolved config round-trips.
//
// Key paths are dotted, with array indices as numbers: "media.0.sigma_t_scale". The same paths
// are accepted by `vpm render --set`.
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "core/math.h"

namespace vpm {

// A loaded config file: its parsed root, where it came from, and which paths --set overrode.
struct ConfigDocument {
    std::string file;                      // as given by the user, used in messages
    std::filesystem::path base_dir;        // relative paths inside the file resolve from here
    toml::table root;
    std::set<std::string> overridden;      // dotted paths set on the command line
};

// Reads `path` and applies "dotted.key=value" overrides (values parsed as TOML, bare words as
// strings). Throws ConfigError naming the file and line (syntax) or the override (bad path).
std::shared_ptr<ConfigDocument> load_config(const std::string& path,
                                            const std::vector<std::string>& overrides = {});
// Same, from text in memory; `name` stands for the file in messages.
std::shared_ptr<ConfigDocument> parse_config(const std::string& text, const std::string& name,
                                             const std::filesystem::path& base_dir,
                                             const std::vector<std::string>& overrides = {});

// Closed or open interval used to validate numbers; prints itself for error messages.
struct Range {
    double lo = -kInfinity, hi = kInfinity;
    bool lo_open = false, hi_open = false;
    static Range any() { return {}; }
    static Range at_least(double v) { return {v, kInfinity, false, false}; }
    static Range positive() { return {0.0, kInfinity, true, false}; }
    static Range closed(double a, double b) { return {a, b, false, false}; }
    static Range open(double a, double b) { return {a, b, true, true}; }
    bool contains(double v) const;
    std::string to_string() const;
};

class Params {
public:
    // The root of a document; `resolved` receives every value used.
    Params(std::shared_ptr<const ConfigDocument> doc, toml::table* resolved);

    bool has(const std::string& key) const;

    double real(const std::string& key, double fallback, Range range = Range::any());
    double real(const std::string& key, Range range = Range::any());   // required
    int64_t integer(const std::string& key, int64_t fallback, Range range = Range::any());
    int64_t integer(const std::string& key, Range range = Range::any());
    bool boolean(const std::string& key, bool fallback);
    std::string string(const std::string& key, const std::string& fallback);
    std::string string(const std::string& key);
    // One of `allowed`; the error lists them.
    std::string choice(const std::string& key, const std::string& fallback,
                       const std::vector<std::string>& allowed);
    std::string choice(const std::string& key, const std::vector<std::string>& allowed);
    // The same, mapped to a typed value: `allowed` pairs each accepted name with its value.
    template <class T>
    T choice(const std::string& key, const T& fallback, const std::vector<std::pair<std::string, T>>& allowed) {
        std::string fallback_name;
        std::vector<std::string> names;
        for (const auto& [name, value] : allowed) {
            names.push_back(name);
            if (value == fallback) fallback_name = name;
        }
        const std::string chosen = choice(key, fallback_name, names);
        for (const auto& [name, value] : allowed)
            if (name == chosen) return value;
        return fallback;
    }
    // A number (grey) or a 3-array; every component in `range`.
    Rgb rgb(const std::string& key, const Rgb& fallback, Range range = Range::any());
    Rgb rgb(const std::string& key, Range range = Range::any());
    Vec3 vec3(const std::string& key, const Vec3& fallback);
    Vec3 vec3(const std::string& key);
    std::vector<double> reals(const std::string& key, const std::vector<double>& fallback,
                              Range range = Range::any());
    // An array of strings.
    std::vector<std::string> strings(const std::string& key, const std::vector<std::string>& fallback);
    // The raw value of `key`, marked as read, for callers that interpret TOML values themselves
    // (sweep axes); null when absent.
    const toml::node* node(const std::string& key);
    // The keys present in this table, in the order they appear in the file.
    std::vector<std::string> keys() const;
    // Line of `key` in its file; 0 when absent or set on the command line.
    int line(const std::string& key) const;
    // A file path, resolved against the config file's folder; must exist when must_exist.
    std::filesystem::path path(const std::string& key, bool must_exist = true);

    // Sub-table (empty one when absent) and array of tables (empty when absent).
    Params table(const std::string& key);
    std::vector<Params> tables(const std::string& key);

    // Throws ConfigError for the first key present in the table that no read consumed.
    void finish() const;

    // Throws ConfigError "<file>:<line>: <path>: <message>" for `key` of this table.
    [[noreturn]] void fail(const std::string& key, const std::string& message) const;
    // Dotted path of `key` in this table ("media.0.g").
    std::string path_of(const std::string& key) const;
    // "file:line" (or "--set key") of `key`, for messages and warnings.
    std::string where(const std::string& key) const;
    const std::string& file() const { return doc_->file; }
    const std::string& prefix() const { return prefix_; }

private:
    Params(std::shared_ptr<const ConfigDocument> doc, const toml::table* table, toml::table* resolved,
           std::string prefix);
    const toml::node* lookup(const std::string& key) const;   // marks the key used
    double number_at(const toml::node& node, const std::string& what) const;

    std::shared_ptr<const ConfigDocument> doc_;
    const toml::table* table_ = nullptr;   // never null; an empty table for absent sub-tables
    toml::table* resolved_ = nullptr;
    std::string prefix_;                   // "" at the root, else "media.0."
    mutable std::set<std::string> used_;
    std::shared_ptr<toml::table> empty_;   // owns the empty table when this one is absent
};

// The resolved table as TOML text.
std::string to_toml_string(const toml::table& table);

}  // namespace vpm
