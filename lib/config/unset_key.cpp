#include "config/unset_key.h"

#include <cctype>

#include "core/error.h"

namespace vpm {

void unset_key(ConfigDocument& doc, const std::string& key) {
    const std::string where = "--unset " + key;
    std::vector<std::string> parts;
    for (size_t start = 0;;) {
        const size_t dot = key.find('.', start);
        parts.push_back(key.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
        if (dot == std::string::npos) break;
        start = dot + 1;
    }
    for (const auto& p : parts)
        if (p.empty()) throw ConfigError(where + ": empty part in the key (two dots, or a dot at an end)");
    auto is_index = [](const std::string& p) {
        if (p.empty() || p.size() > 9) return false;
        for (char c : p)
            if (!std::isdigit(static_cast<unsigned char>(c))) return false;
        return true;
    };
    auto not_set = [&] { return ConfigError(where + ": " + doc.file + " does not set it, so there is nothing to unset"); };
    toml::node* cur = &doc.root;
    for (size_t i = 0; i + 1 < parts.size(); ++i) {
        toml::node* next = nullptr;
        if (auto* t = cur->as_table()) next = t->get(parts[i]);
        else if (auto* a = cur->as_array(); a && is_index(parts[i])) next = a->get(std::stoul(parts[i]));
        if (!next) throw not_set();
        cur = next;
    }
    auto* table = cur->as_table();
    toml::node* value = table ? table->get(parts.back()) : nullptr;
    if (!value) throw not_set();
    if (value->is_table() || value->is_array_of_tables())
        throw ConfigError(where + ": is a whole table in " + doc.file + "; unset its keys one by one");
    table->erase(parts.back());
    doc.overridden.erase(key);
}

}  // namespace vpm
