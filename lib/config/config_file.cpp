#include "config/config_file.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

#include <functional>
#include <set>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace fs = std::filesystem;

namespace vpm {

std::string read_config_text(const std::string& path, const std::string& what) {
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (!fs::exists(st)) throw FileError(path + ": cannot open " + what + ": no such file");
    if (fs::is_directory(st)) throw FileError(path + ": cannot read " + what + ": it is a folder, not a file");
    if (!fs::is_regular_file(st)) throw FileError(path + ": cannot read " + what + ": not a regular file");
    const auto size = fs::file_size(path, ec);
    if (!ec && size > kMaxConfigBytes)
        throw FileError(path + ": " + what + " is " + std::to_string(size) + " bytes; the limit is " +
                        std::to_string(kMaxConfigBytes) + " (1 MiB)");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FileError(path + ": cannot open " + what);
    std::stringstream text;
    text << in.rdbuf();
    if (in.bad()) throw FileError(path + ": cannot read " + what);
    // A config is text: an image or a grid given by mistake is named as what it is, not parsed.
    const std::string bytes = text.str();
    const bool exr = bytes.compare(0, 4, "\x76\x2f\x31\x01") == 0;
    if (exr || bytes.find('\0') != std::string::npos)
        throw FileError(path + ": cannot read " + what + ": it is " + (exr ? "an OpenEXR image" : "a binary file") +
                        ", not text; a config is TOML, or JSON such as a run's sidecar (the .json beside its image)");
    return bytes;
}

void check_toml_shape(const std::string& text, const std::string& name) {
    if (text.size() > kMaxConfigBytes)
        throw ConfigError(name + ": " + std::to_string(text.size()) + " bytes; the limit is " +
                          std::to_string(kMaxConfigBytes) + " (1 MiB)");
    size_t line = 1;
    auto too_deep = [&](size_t depth) {
        if (depth > size_t(kMaxConfigNesting))
            throw ConfigError(name + ":" + std::to_string(line) + ": nesting deeper than " +
                              std::to_string(kMaxConfigNesting) +
                              " levels (table headers, dotted keys, arrays and inline tables); a scene needs a handful");
    };
    std::vector<char> brackets;   // open '[' and '{' of values
    bool at_key = true;           // reading a key (line start, inside an inline table)
    bool line_start = true;       // only blanks so far on this line
    size_t key_parts = 1;
    const size_t n = text.size();
    for (size_t i = 0; i < n; ++i) {
        const char c = text[i];
        if (c == '\n') {
            ++line;
            line_start = true;
            if (brackets.empty()) {
                at_key = true;
                key_parts = 1;
            }
            continue;
        }
        if (c == ' ' || c == '\t' || c == '\r') continue;
        const bool first = line_start;
        line_start = false;
        if (c == '#') {   // comment to the end of the line
            while (i + 1 < n && text[i + 1] != '\n') ++i;
            continue;
        }
        if (c == '"' || c == '\'') {   // strings, also """ and ''' multi-line ones
            const bool triple = i + 2 < n && text[i + 1] == c && text[i + 2] == c;
            i += triple ? 3 : 1;
            for (; i < n; ++i) {
                if (text[i] == '\n') ++line;
                if (c == '"' && text[i] == '\\') { ++i; if (i < n && text[i] == '\n') ++line; continue; }
                if (text[i] != c) continue;
                if (!triple) break;
                if (i + 2 < n && text[i + 1] == c && text[i + 2] == c) { i += 2; break; }
            }
            continue;
        }
        if (first && brackets.empty() && c == '[') {   // [table] or [[array.of.tables]]
            size_t depth = i + 1 < n && text[i + 1] == '[' ? 2 : 1;
            for (++i; i < n && text[i] != ']' && text[i] != '\n'; ++i) {
                if (text[i] == '.') ++depth;
                if (text[i] == '"' || text[i] == '\'') {   // quoted key part
                    const char q = text[i];
                    for (++i; i < n && text[i] != q && text[i] != '\n'; ++i)
                        if (q == '"' && text[i] == '\\') ++i;
                }
            }
            too_deep(depth);
            while (i + 1 < n && text[i + 1] == ']') ++i;
            continue;
        }
        if (at_key) {
            if (c == '.') too_deep(brackets.size() + ++key_parts);
            else if (c == '=') { at_key = false; key_parts = 1; }
            else if (c == '}' && !brackets.empty()) { brackets.pop_back(); at_key = false; }   // {}
            continue;
        }
        if (c == '[' || c == '{') {
            brackets.push_back(c);
            too_deep(brackets.size());
            if (c == '{') { at_key = true; key_parts = 1; }
        } else if ((c == ']' || c == '}') && !brackets.empty()) {
            brackets.pop_back();
        } else if (c == ',' && !brackets.empty() && brackets.back() == '{') {
            at_key = true;
            key_parts = 1;
        }
    }
}

toml::table parse_toml_checked(const std::string& text, const std::string& name) {
    check_toml_shape(text, name);
    try {
        return toml::parse(text, name);
    } catch (const toml::parse_error& e) {
        throw ConfigError(name + ":" + std::to_string(e.source().begin.line) + ": TOML syntax error: " +
                          std::string(e.description()));
    }
}

}  // namespace vpm

namespace vpm {

namespace {

// `path`: the dotted key of the value, for messages ("render.seed", "shapes.0.radius").
toml::array json_array_to_toml(const nlohmann::json& j, const std::string& name, const std::string& path, int depth);

toml::table json_object_to_toml(const nlohmann::json& j, const std::string& name, const std::string& path, int depth);

void check_json_depth(int depth, const std::string& name) {
    if (depth > kMaxConfigNesting)
        throw ConfigError(name + ": nesting deeper than " + std::to_string(kMaxConfigNesting) + " levels");
}

template <class Insert>
void json_value_to_toml(const nlohmann::json& v, const std::string& name, const std::string& path, int depth,
                        Insert&& insert) {
    switch (v.type()) {
        case nlohmann::json::value_t::object: insert(json_object_to_toml(v, name, path + ".", depth + 1)); break;
        case nlohmann::json::value_t::array: insert(json_array_to_toml(v, name, path + ".", depth + 1)); break;
        case nlohmann::json::value_t::string: insert(v.get<std::string>()); break;
        case nlohmann::json::value_t::boolean: insert(v.get<bool>()); break;
        case nlohmann::json::value_t::number_integer: insert(v.get<int64_t>()); break;
        case nlohmann::json::value_t::number_unsigned:
            // Configs hold 64-bit signed integers (TOML's): a larger one must not wrap to a negative.
            if (v.get<uint64_t>() > uint64_t(INT64_MAX))
                throw ConfigError(name + ": " + path + ": integer " + std::to_string(v.get<uint64_t>()) +
                                  " is out of range; integers are 64-bit signed, at most 9223372036854775807 (2^63 - 1)");
            insert(int64_t(v.get<uint64_t>()));
            break;
        case nlohmann::json::value_t::number_float: insert(v.get<double>()); break;
        default: throw ConfigError(name + ": " + path + ": a null or binary value has no TOML equivalent");
    }
}

toml::array json_array_to_toml(const nlohmann::json& j, const std::string& name, const std::string& path, int depth) {
    check_json_depth(depth, name);
    toml::array a;
    size_t i = 0;
    for (const auto& v : j)
        json_value_to_toml(v, name, path + std::to_string(i++), depth, [&](auto&& x) { a.push_back(std::move(x)); });
    return a;
}

toml::table json_object_to_toml(const nlohmann::json& j, const std::string& name, const std::string& path, int depth) {
    check_json_depth(depth, name);
    toml::table t;
    for (const auto& item : j.items()) {   // not a structured binding: C++17 lambdas cannot capture one
        const std::string& key = item.key();
        json_value_to_toml(item.value(), name, path + key, depth, [&](auto&& x) { t.insert_or_assign(key, std::move(x)); });
    }
    return t;
}

}  // namespace

bool looks_like_json(const std::string& text) {
    const size_t i = text.find_first_not_of(" \t\r\n");
    return i != std::string::npos && text[i] == '{';
}

namespace {

// nlohmann keeps the last of two equal keys in an object; a config must not silently lose one, so
// the parser callback tracks the keys of every open object (path for the message).
struct DuplicateKeyCheck {
    struct Frame {
        bool object = false;
        std::set<std::string> keys;
        std::string key;   // the member being read
    };
    const std::string* name;
    std::vector<Frame> open;
    bool operator()(int /*depth*/, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        using E = nlohmann::json::parse_event_t;
        if (event == E::object_start || event == E::array_start) open.push_back({event == E::object_start, {}, {}});
        else if ((event == E::object_end || event == E::array_end) && !open.empty()) open.pop_back();
        else if (event == E::key && !open.empty()) {
            Frame& f = open.back();
            const std::string key = parsed.get<std::string>();
            if (!f.keys.insert(key).second) {
                std::string path;
                for (size_t i = 0; i + 1 < open.size(); ++i)
                    if (open[i].object) path += open[i].key + ".";
                throw ConfigError(*name + ": duplicate JSON key \"" + path + key + "\" (JSON objects keep only one value per key; remove one)");
            }
            f.key = key;
        }
        return true;
    }
};

}  // namespace

namespace {

// Removes the value at a dotted path ("render.spp", "media.0.g") from `root`, if it is there.
void remove_value(toml::table& root, const std::string& key) {
    toml::node* cur = &root;
    size_t start = 0;
    for (size_t dot; (dot = key.find('.', start)) != std::string::npos; start = dot + 1) {
        const std::string part = key.substr(start, dot - start);
        toml::node* next = nullptr;
        if (toml::table* t = cur->as_table()) {
            next = t->get(part);
        } else if (toml::array* a = cur->as_array(); a && !part.empty() && part.size() < 10 &&
                                                      part.find_first_not_of("0123456789") == std::string::npos) {
            next = a->get(std::stoul(part));
        }
        if (!next) return;
        cur = next;
    }
    if (toml::table* t = cur->as_table()) t->erase(key.substr(start));
}

}  // namespace

std::string json_value_kind(const std::string& text) {
    nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    return j.is_discarded() ? std::string() : std::string(j.type_name());
}

toml::table config_from_json(const std::string& text, const std::string& name) {
    nlohmann::json j;
    try {
        DuplicateKeyCheck check{&name, {}};
        j = nlohmann::json::parse(text, std::ref(check));
    } catch (const nlohmann::json::exception& e) {   // syntax errors, and numbers out of range (found by fuzzing)
        throw ConfigError(name + ": JSON syntax error: " + e.what());
    }
    if (!j.is_object()) throw ConfigError(name + ": expected a JSON object");
    if (j.contains("config")) {   // a run sidecar: its resolved config
        if (!j["config"].is_object()) throw ConfigError(name + ": config: expected an object");
        toml::table config = json_object_to_toml(j["config"], name, "", 0);
        // The values the run's document left unset go again, so that nothing is pinned that the run left to the plan (its
        // automatic choices are made again, as in the run).
        if (j.contains("config_defaults")) {
            const nlohmann::json& d = j["config_defaults"];
            if (!d.is_array()) throw ConfigError(name + ": config_defaults: expected an array of dotted keys");
            for (const nlohmann::json& key : d) {
                if (!key.is_string()) throw ConfigError(name + ": config_defaults: expected dotted keys (strings), got " + key.dump());
                remove_value(config, key.get<std::string>());
            }
        }
        return config;
    }
    return json_object_to_toml(j, name, "", 0);
}

}  // namespace vpm
