#include "config/params.h"

#include <fstream>
#include <sstream>

#include "core/error.h"
#include "config/config_file.h"

namespace vpm {

namespace fs = std::filesystem;

namespace {

std::string format_number(double v) {
    std::ostringstream s;
    s.precision(12);
    s << v;
    return s.str();
}

std::string type_name(const toml::node& n) {
    switch (n.type()) {
        case toml::node_type::table: return "a table";
        case toml::node_type::array: return "an array";
        case toml::node_type::string: return "a string";
        case toml::node_type::integer: return "an integer";
        case toml::node_type::floating_point: return "a number";
        case toml::node_type::boolean: return "a boolean";
        default: return "a date/time";
    }
}

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> parts;
    std::string cur;
    for (char c : s) {
        if (c == sep) { parts.push_back(cur); cur.clear(); }
        else cur += c;
    }
    parts.push_back(cur);
    return parts;
}

bool is_index(const std::string& s) {
    return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos;
}

// "-1", "3": meant as an array index (even if not a valid one).
bool looks_like_index(const std::string& s) {
    return is_index(s) || (s.size() > 1 && s[0] == '-' && is_index(s.substr(1)));
}

std::string join_parts(const std::vector<std::string>& parts, size_t n) {
    std::string s;
    for (size_t j = 0; j < n; ++j) s += (j ? "." : "") + parts[j];
    return s;
}

// Throws unless `p` is an index into an array of `n` entries, naming the valid range.
void check_index(const std::string& where, const std::string& p, const std::string& array, size_t n) {
    const std::string range = n ? " (0 to " + std::to_string(n - 1) + ")" : std::string();
    if (!is_index(p))
        throw ConfigError(where + ": '" + p + "' is not an index of '" + array + "', which has " + std::to_string(n) +
                          " entries" + range);
    if (p.size() > 18 || std::stoull(p) >= n)
        throw ConfigError(where + ": index " + p + " is past the end of '" + array + "', which has " +
                          std::to_string(n) + " entries" + range);
}

// An integer literal (decimal, optional sign and underscores) that TOML's 64-bit integers cannot hold.
bool out_of_range_integer(const std::string& value) {
    const size_t b = value.find_first_not_of(" \t"), e = value.find_last_not_of(" \t");
    if (b == std::string::npos) return false;
    std::string digits;
    for (size_t i = b; i <= e; ++i) {
        const char c = value[i];
        if ((c == '+' || c == '-') && i == b) continue;
        if (c == '_') continue;
        if (c < '0' || c > '9') return false;
        digits += c;
    }
    if (digits.empty()) return false;
    digits.erase(0, std::min(digits.find_first_not_of('0'), digits.size() - 1));
    const std::string limit = value[b] == '-' ? "9223372036854775808" : "9223372036854775807";
    return digits.size() > limit.size() || (digits.size() == limit.size() && digits > limit);
}

// Parses the right-hand side of --set as one TOML value; a bare word that is not TOML is a string.
toml::table parse_override_value(const std::string& value, const std::string& where) {
    if (out_of_range_integer(value))
        throw ConfigError(where + ": integer out of range; integers are 64-bit signed, from -9223372036854775808 to "
                                  "9223372036854775807 (2^63 - 1)");
    check_toml_shape("v = " + value, where);
    toml::table t;
    try {
        t = toml::parse("v = " + value);
    } catch (const toml::parse_error&) {
        if (value.find_first_of("\r\n") != std::string::npos)
            throw ConfigError(where + ": the value spans lines and is no TOML value; give one value per --set "
                                      "(a string with a line break must be quoted: \"a\\nb\")");
        t.insert("v", value);
        return t;
    }
    // "16\nrender.height = 4" parses as two keys: everything after the first value would be lost.
    if (t.size() != 1)
        throw ConfigError(where + ": more than one value (a line break ends the first and starts a key); give "
                                  "one value per --set, e.g. --set render.width=16 --set render.height=4");
    return t;
}

void apply_override(ConfigDocument& doc, const std::string& assignment) {
    const auto eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0)
        throw ConfigError("--set " + assignment + ": expected KEY=VALUE, e.g. media.0.sigma_t_scale=10");
    const std::string key = assignment.substr(0, eq);
    // Messages stay one line: a line break in the value is shown as \n.
    std::string shown;
    for (char c : assignment) shown += c == '\n' ? std::string("\\n") : c == '\r' ? std::string("\\r") : std::string(1, c);
    const std::string where = "--set " + shown;
    const auto parts = split(key, '.');
    if (parts.size() > size_t(kMaxConfigNesting))
        throw ConfigError(where + ": the key has " + std::to_string(parts.size()) + " parts; the limit is " +
                          std::to_string(kMaxConfigNesting));
    for (const auto& p : parts)
        if (p.empty()) throw ConfigError(where + ": empty part in the key (two dots, or a dot at an end)");
    // What stands in the way, named by where it came from: an earlier --set, or the config file.
    auto origin = [&](const std::string& path) {
        return doc.overridden.count(path) ? std::string("set by --set " + path) : "in " + doc.file;
    };
    toml::node* cur = &doc.root;
    for (size_t i = 0; i + 1 < parts.size(); ++i) {
        const std::string& p = parts[i];
        const std::string here = join_parts(parts, i + 1);
        toml::node* next = nullptr;
        if (auto* t = cur->as_table()) {
            next = t->get(p);
            if (!next) {
                // A missing table is created (--set camera.fov=30 without [camera]); a missing array is not.
                if (looks_like_index(parts[i + 1]))
                    throw ConfigError(where + ": '" + here + "' has no entries (there is no [[" + here +
                                      "]]); --set changes existing array entries, it cannot add them");
                next = &t->insert(p, toml::table{}).first->second;
                doc.overridden.insert(here);
            }
        } else if (auto* a = cur->as_array()) {
            const std::string parent = join_parts(parts, i);
            check_index(where, p, parent, a->size());
            next = a->get(std::stoul(p));
        }
        if (!next || (!next->is_table() && !next->is_array()))
            throw ConfigError(where + ": '" + here + "' is a single value (" + origin(here) +
                              "), not a table or array, so it has no '" + parts[i + 1] + "'");
        cur = next;
    }
    toml::table parsed = parse_override_value(assignment.substr(eq + 1), where);
    toml::node* value = parsed.get("v");
    const std::string& last = parts.back();
    if (auto* t = cur->as_table()) {
        // A table given whole would drop every key of the table it replaces that it leaves out.
        if (const toml::node* old = t->get(last); old && old->is_table() && value->is_table())
            throw ConfigError(where + ": '" + key + "' is a table (" + origin(key) +
                              "); a table value would replace all of its keys, not only the ones given. Set the keys "
                              "one by one: --set " + key + ".KEY=VALUE");
        t->insert_or_assign(last, std::move(*value));
    } else if (auto* a = cur->as_array(); a && is_index(last) && std::stoull(last.substr(0, 18)) < a->size()) {
        a->replace(a->cbegin() + static_cast<std::ptrdiff_t>(std::stoul(last)), std::move(*value));
    } else {
        check_index(where, last, join_parts(parts, parts.size() - 1), cur->as_array() ? cur->as_array()->size() : 0);
        throw ConfigError(where + ": cannot set '" + last + "' here");
    }
    doc.overridden.insert(key);
}

// Copies `over` into `base`: tables merge key by key, everything else (values, arrays, arrays of
// tables) replaces what the base had.
void merge_into(toml::table& base, const toml::table& over) {
    for (const auto& [key, node] : over) {
        toml::node* existing = base.get(key);
        if (existing && existing->is_table() && node.is_table()) merge_into(*existing->as_table(), *node.as_table());
        else base.insert_or_assign(key, node);
    }
}

// A config may start from another: `base = "default.toml"` (relative to the including file).
// The including file's keys win. Paths inside each file resolve relative to that file.
void apply_base(ConfigDocument& doc, int depth) {
    const toml::node* base = doc.root.get("base");
    if (!base) return;
    const auto name = base->value_exact<std::string>();
    const std::string where = doc.file + ":" + std::to_string(base->source().begin.line) + ": base: ";
    if (!name) throw ConfigError(where + "expected a config file path string");
    if (depth > 8) throw ConfigError(where + "more than 8 nested base configs (a cycle?)");
    fs::path path(*name);
    if (path.is_relative()) path = doc.base_dir / path;
    if (!fs::exists(path)) throw ConfigError(where + "cannot open " + path.string() + ": no such file");
    std::string text;
    try {
        text = read_config_text(path.string(), "base config");
    } catch (const FileError& e) {
        throw ConfigError(where + e.what());
    }
    ConfigDocument parent;
    parent.file = path.lexically_normal().string();
    parent.base_dir = path.parent_path();
    parent.root = parse_toml_checked(text, parent.file);
    apply_base(parent, depth + 1);
    doc.root.erase("base");
    merge_into(parent.root, doc.root);
    doc.root = std::move(parent.root);
}

}  // namespace

std::shared_ptr<ConfigDocument> parse_config(const std::string& text, const std::string& name,
                                             const fs::path& base_dir,
                                             const std::vector<std::string>& overrides) {
    auto doc = std::make_shared<ConfigDocument>();
    doc->file = name;
    doc->base_dir = base_dir;
    // A run's JSON sidecar loads as the config it records; anything else is TOML.
    if (looks_like_json(text)) {
        doc->root = config_from_json(text, name);
    } else {
        try {
            doc->root = parse_toml_checked(text, name);
        } catch (const ConfigError&) {
            // Valid JSON that is no object (an array, say) is no TOML either: say what it is.
            const std::string kind = json_value_kind(text);
            if (!kind.empty()) throw ConfigError(name + ": a JSON config must be an object { ... }, got a JSON " + kind);
            throw;
        }
    }
    apply_base(*doc, 0);
    for (const auto& o : overrides) apply_override(*doc, o);
    return doc;
}

std::shared_ptr<ConfigDocument> load_config(const std::string& path, const std::vector<std::string>& overrides) {
    const std::string text = read_config_text(path, "config file");
    const fs::path base = fs::absolute(fs::path(path)).parent_path();
    return parse_config(text, path, base, overrides);
}

bool Range::contains(double v) const {
    if (std::isnan(v)) return false;
    if (lo_open ? !(v > lo) : !(v >= lo)) return false;
    if (hi_open ? !(v < hi) : !(v <= hi)) return false;
    return true;
}

std::string Range::to_string() const {
    const bool has_lo = lo > -kInfinity, has_hi = hi < kInfinity;
    if (!has_lo && !has_hi) return "any finite number";
    if (has_lo && !has_hi) return std::string(lo_open ? "> " : ">= ") + format_number(lo);
    if (!has_lo) return std::string(hi_open ? "< " : "<= ") + format_number(hi);
    return std::string(lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) + (hi_open ? ")" : "]");
}

Params::Params(std::shared_ptr<const ConfigDocument> doc, toml::table* resolved)
    : doc_(std::move(doc)), table_(&doc_->root), resolved_(resolved) {}

Params::Params(std::shared_ptr<const ConfigDocument> doc, const toml::table* table, toml::table* resolved,
               std::string prefix)
    : doc_(std::move(doc)), table_(table), resolved_(resolved), prefix_(std::move(prefix)) {
    if (!table_) {
        empty_ = std::make_shared<toml::table>();
        table_ = empty_.get();
    }
}

std::string Params::path_of(const std::string& key) const { return prefix_ + key; }

std::string Params::where(const std::string& key) const {
    const std::string full = path_of(key);
    // Set on the command line, itself or within a table or array given there (--set 'shapes=[...]').
    for (size_t end = full.size(); end != std::string::npos && end > 0; end = full.rfind('.', end - 1)) {
        const std::string path = full.substr(0, end);
        if (doc_->overridden.count(path)) return "--set " + path;
    }
    const toml::node* n = table_->get(key);
    const auto& src = n ? n->source() : table_->source();
    const std::string file = src.path ? *src.path : doc_->file;   // keys from a base config name it
    if (src.begin.line > 0) return file + ":" + std::to_string(src.begin.line);
    return file;
}

void Params::fail(const std::string& key, const std::string& message) const {
    throw ConfigError(where(key) + ": " + path_of(key) + ": " + message);
}

bool Params::has(const std::string& key) const { return table_->get(key) != nullptr; }

const toml::node* Params::lookup(const std::string& key) const {
    used_.insert(key);
    return table_->get(key);
}

double Params::number_at(const toml::node& node, const std::string& key) const {
    if (auto v = node.value_exact<double>()) return *v;
    if (auto v = node.value_exact<int64_t>()) return static_cast<double>(*v);
    fail(key, "expected a number, got " + type_name(node));
}

double Params::real(const std::string& key, double fallback, Range range) {
    const toml::node* n = lookup(key);
    const double v = n ? number_at(*n, key) : fallback;
    if (n && (!std::isfinite(v) || !range.contains(v)))
        fail(key, "value " + format_number(v) + " is out of range; allowed: " + range.to_string());
    resolved_->insert_or_assign(key, v);
    return v;
}

double Params::real(const std::string& key, Range range) {
    if (!has(key)) fail(key, "required number is missing; allowed: " + range.to_string());
    return real(key, 0.0, range);
}

int64_t Params::integer(const std::string& key, int64_t fallback, Range range) {
    const toml::node* n = lookup(key);
    int64_t v = fallback;
    if (n) {
        if (auto i = n->value_exact<int64_t>()) v = *i;
        else fail(key, "expected an integer, got " + type_name(*n));
        if (!range.contains(static_cast<double>(v)))
            fail(key, "value " + std::to_string(v) + " is out of range; allowed: " + range.to_string());
    }
    resolved_->insert_or_assign(key, v);
    return v;
}

int64_t Params::integer(const std::string& key, Range range) {
    if (!has(key)) fail(key, "required integer is missing; allowed: " + range.to_string());
    return integer(key, 0, range);
}

bool Params::boolean(const std::string& key, bool fallback) {
    const toml::node* n = lookup(key);
    bool v = fallback;
    if (n) {
        if (auto b = n->value_exact<bool>()) v = *b;
        else fail(key, "expected true or false, got " + type_name(*n));
    }
    resolved_->insert_or_assign(key, v);
    return v;
}

std::string Params::string(const std::string& key, const std::string& fallback) {
    const toml::node* n = lookup(key);
    std::string v = fallback;
    if (n) {
        if (auto s = n->value_exact<std::string>()) v = *s;
        else fail(key, "expected a string, got " + type_name(*n));
    }
    resolved_->insert_or_assign(key, v);
    return v;
}

std::string Params::string(const std::string& key) {
    if (!has(key)) fail(key, "required string is missing");
    return string(key, "");
}

std::string Params::choice(const std::string& key, const std::string& fallback,
                           const std::vector<std::string>& allowed) {
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + ("\"" + a + "\"");
    if (const toml::node* n = lookup(key); n && !n->is_string())
        fail(key, "expected a string, got " + type_name(*n) + "; allowed: " + list);
    const std::string v = string(key, fallback);
    for (const auto& a : allowed)
        if (a == v) return v;
    fail(key, "unknown value \"" + v + "\"; allowed: " + list);
}

std::string Params::choice(const std::string& key, const std::vector<std::string>& allowed) {
    if (!has(key)) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + ("\"" + a + "\"");
        fail(key, "required key is missing; allowed: " + list);
    }
    return choice(key, "", allowed);
}

Rgb Params::rgb(const std::string& key, const Rgb& fallback, Range range) {
    const toml::node* n = lookup(key);
    Rgb v = fallback;
    if (n) {
        if (const auto* a = n->as_array()) {
            if (a->size() != 3) fail(key, "expected a number or [r, g, b], got an array of " + std::to_string(a->size()));
            for (int c = 0; c < 3; ++c) v[c] = number_at(*a->get(static_cast<size_t>(c)), key);
        } else {
            v = Rgb::Constant(number_at(*n, key));
        }
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(v[c]) || !range.contains(v[c]))
                fail(key, "component " + format_number(v[c]) + " is out of range; allowed: " + range.to_string());
    }
    resolved_->insert_or_assign(key, toml::array{v[0], v[1], v[2]});
    return v;
}

Rgb Params::rgb(const std::string& key, Range range) {
    if (!has(key)) fail(key, "required colour is missing (a number or [r, g, b])");
    return rgb(key, Rgb::Zero(), range);
}

Vec3 Params::vec3(const std::string& key, const Vec3& fallback) {
    const toml::node* n = lookup(key);
    Vec3 v = fallback;
    if (n) {
        const auto* a = n->as_array();
        if (!a || a->size() != 3) fail(key, "expected [x, y, z], got " + type_name(*n));
        for (int c = 0; c < 3; ++c) {
            v[c] = number_at(*a->get(static_cast<size_t>(c)), key);
            if (!std::isfinite(v[c])) fail(key, "components must be finite");
        }
    }
    resolved_->insert_or_assign(key, toml::array{v[0], v[1], v[2]});
    return v;
}

Vec3 Params::vec3(const std::string& key) {
    if (!has(key)) fail(key, "required vector [x, y, z] is missing");
    return vec3(key, Vec3::Zero());
}

std::vector<double> Params::reals(const std::string& key, const std::vector<double>& fallback, Range range) {
    const toml::node* n = lookup(key);
    std::vector<double> v = fallback;
    if (n) {
        const auto* a = n->as_array();
        if (!a) fail(key, "expected an array of numbers, got " + type_name(*n));
        v.clear();
        for (const auto& e : *a) {
            const double x = number_at(e, key);
            if (!std::isfinite(x) || !range.contains(x))
                fail(key, "element " + format_number(x) + " is out of range; allowed: " + range.to_string());
            v.push_back(x);
        }
    }
    toml::array out;
    for (double x : v) out.push_back(x);
    resolved_->insert_or_assign(key, std::move(out));
    return v;
}

std::vector<std::string> Params::strings(const std::string& key, const std::vector<std::string>& fallback) {
    const toml::node* n = lookup(key);
    if (!n) return fallback;
    const auto* a = n->as_array();
    if (!a) fail(key, "expected an array of strings, got " + type_name(*n));
    std::vector<std::string> v;
    toml::array out;
    for (const auto& e : *a) {
        const auto s = e.value_exact<std::string>();
        if (!s) fail(key, "expected strings, got " + type_name(e));
        v.push_back(*s);
        out.push_back(*s);
    }
    resolved_->insert_or_assign(key, std::move(out));
    return v;
}

const toml::node* Params::node(const std::string& key) {
    const toml::node* n = lookup(key);
    if (n) resolved_->insert_or_assign(key, *n);
    return n;
}

std::vector<std::string> Params::keys() const {
    std::vector<std::pair<int, std::string>> lines;
    for (const auto& [k, v] : *table_) lines.emplace_back(int(v.source().begin.line), std::string(k.str()));
    std::stable_sort(lines.begin(), lines.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::string> out;
    for (auto& l : lines) out.push_back(std::move(l.second));
    return out;
}

int Params::line(const std::string& key) const {
    if (doc_->overridden.count(path_of(key))) return 0;
    const toml::node* n = table_->get(key);
    return n ? int(n->source().begin.line) : 0;
}

fs::path Params::path(const std::string& key, bool must_exist) {
    const toml::node* n = lookup(key);
    if (!n) fail(key, "required file path is missing");
    const auto s = n->value_exact<std::string>();
    if (!s) fail(key, "expected a file path string, got " + type_name(*n));
    fs::path p(*s);
    // Relative to the file the key was written in (a base config may live elsewhere).
    const auto& src = n->source();
    const fs::path dir = src.path && *src.path != doc_->file ? fs::path(*src.path).parent_path() : doc_->base_dir;
    if (p.is_relative()) p = dir / p;
    p = p.lexically_normal();
    if (must_exist && !fs::exists(p)) fail(key, "file not found: " + p.string());
    if (must_exist && fs::is_directory(p)) fail(key, p.string() + " is a folder, not a file");
    resolved_->insert_or_assign(key, p.string());
    return p;
}

Params Params::table(const std::string& key) {
    const toml::node* n = lookup(key);
    if (n && !n->is_table()) fail(key, "expected a table, got " + type_name(*n));
    auto* out = resolved_->insert_or_assign(key, toml::table{}).first->second.as_table();
    return Params(doc_, n ? n->as_table() : nullptr, out, path_of(key) + ".");
}

std::vector<Params> Params::tables(const std::string& key) {
    const toml::node* n = lookup(key);
    std::vector<Params> result;
    if (!n) return result;
    const auto* a = n->as_array();
    if (!a) fail(key, "expected an array of tables ([[" + path_of(key) + "]]), got " + type_name(*n));
    auto* out = resolved_->insert_or_assign(key, toml::array{}).first->second.as_array();
    for (size_t i = 0; i < a->size(); ++i) {
        const auto* t = a->get(i)->as_table();
        if (!t) {
            // Named by where the entry came from: a --set (of the entry or the whole array) or its line.
            const std::string entry = key + "." + std::to_string(i);
            std::string at = where(entry);
            const auto& src = a->get(i)->source();
            if (at.rfind("--set ", 0) != 0 && src.begin.line > 0)
                at = (src.path ? *src.path : doc_->file) + ":" + std::to_string(src.begin.line);
            throw ConfigError(at + ": " + path_of(entry) + ": expected a table (an entry of [[" + path_of(key) + "]]), got " +
                              type_name(*a->get(i)));
        }
        out->push_back(toml::table{});
    }
    for (size_t i = 0; i < a->size(); ++i)
        result.push_back(Params(doc_, a->get(i)->as_table(), out->get(i)->as_table(),
                                path_of(key) + "." + std::to_string(i) + "."));
    return result;
}

void Params::finish() const {
    for (const auto& [k, node] : *table_) {
        const std::string key(k.str());
        if (used_.count(key)) continue;
        // The keys this table's reader asked for are exactly the ones it knows.
        std::string known;
        for (const std::string& u : used_) known += (known.empty() ? "" : ", ") + u;
        fail(key, "unknown key" + (known.empty() ? std::string() : "; known here: " + known));
    }
}

std::string to_toml_string(const toml::table& table) {
    std::ostringstream s;
    s << toml::toml_formatter(table);
    return s.str();
}

}  // namespace vpm
