#pragma once
// One shape for every registry of things users choose by name: lights, media, integrators,
// estimators and kernels. A registry is a static table of entries, each with a `const char*
// name`, in the order lists are shown; the table lives in the registry's .cpp, which declares
// each entry's factory beside its line, so adding an entry is its own file plus one line there.
// These helpers give every registry the same name list and lookup, so config errors, `--help`
// texts and the documentation checks (tests/tools/registry_docs_test.cpp) read the same names.
#include <iterator>
#include <string>
#include <vector>

namespace vpm {

// `Table` is any range of entries (a std::vector or a C array).
template <class Table>
std::vector<std::string> registry_names(const Table& entries) {
    std::vector<std::string> names;
    for (const auto& e : entries) names.emplace_back(e.name);
    return names;
}

// The entry called `name`, or nullptr.
template <class Table>
auto registry_find(const Table& entries, const std::string& name) -> decltype(&*std::begin(entries)) {
    for (const auto& e : entries)
        if (name == e.name) return &e;
    return nullptr;
}

// "a, b, c": the allowed values in error messages.
inline std::string registry_list(const std::vector<std::string>& names) {
    std::string s;
    for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
    return s;
}

}  // namespace vpm
