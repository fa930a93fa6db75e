#pragma once
// Reading TOML text safely. toml++ is a recursive parser and its tables are freed recursively,
// so a 40,000-level dotted header crashes it (stack overflow): every config, base config, sweep
// file and --set value passes through these checks (size, nesting) before toml++ sees it.
#include <cstddef>
#include <string>

#include <toml++/toml.h>

namespace vpm {

constexpr size_t kMaxConfigBytes = size_t(1) << 20;   // 1 MiB: configs are a few KB
constexpr int kMaxConfigNesting = 64;                  // tables + dotted key parts + brackets

// Reads a config-like file ("config file", "base config", "sweep file" as `what`). Throws
// FileError naming the path when it is missing, a folder, not a regular file, over
// kMaxConfigBytes, or unreadable.
std::string read_config_text(const std::string& path, const std::string& what);

// Throws ConfigError "<name>:<line>: ..." if any key path (header, dotted key, inline table)
// plus the arrays and inline tables around it is deeper than kMaxConfigNesting, or the text is
// over kMaxConfigBytes. A cheap scan that knows strings and comments; it never parses values.
void check_toml_shape(const std::string& text, const std::string& name);

// check_toml_shape, then toml::parse; syntax errors become ConfigError
// "<name>:<line>: TOML syntax error: <description>".
toml::table parse_toml_checked(const std::string& text, const std::string& name);

// A JSON config: a run's sidecar (OUT.json, whose "config" is the fully resolved config) or a
// plain JSON object with the same keys. Integers stay integers, numbers with a fraction or
// exponent are floats. Throws ConfigError naming `name`.
bool looks_like_json(const std::string& text);
toml::table config_from_json(const std::string& text, const std::string& name);
// "array", "number", ... when `text` is valid JSON, else "" (to explain a JSON config that is no object).
std::string json_value_kind(const std::string& text);

}  // namespace vpm
