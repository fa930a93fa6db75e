// The config reference's table of tables (docs/config.md) and docs/kernels.md list exactly the registered names of every registry
// (lights, media, integrators, estimators, kernels): adding an entry without documenting it, or
// removing one and leaving its documentation, fails here; `vpm render --help` lists them from the
// registries themselves.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "photon/estimate/estimators.h"
#include "photon/estimate/kernels.h"
#include "photon/estimate/walk_estimate.h"
#include "render/integrator_registry.h"
#include "render/photon_map/gathers/gather_registry.h"
#include "render/photon_map/gathers/photon_beams_gather.h"
#include "scene/lights/light_registry.h"
#include "scene/materials/material_registry.h"
#include "scene/media/medium_registry.h"
#include "support/vpm_process.h"

using namespace vpm;

namespace {

std::string read(const std::string& relative) {
    std::ifstream in(std::string(VPM_SOURCE_DIR) + "/" + relative);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// The row of `table` (e.g. "`[[lights]]`") in docs/config.md's table of tables.
std::string config_reference_row(const std::string& table) {
    std::istringstream in(read("docs/config.md"));
    for (std::string line; std::getline(in, line);)
        if (line.rfind("| " + table + " |", 0) == 0) return line;
    return "";
}

// The values a row lists for `key`: the quoted words `"x"` after "`key` = " outside parentheses
// (which hold each value's own keys), up to the next key (", `k"), a ';' or the end of the cell.
std::set<std::string> listed_values(const std::string& row, const std::string& key) {
    std::set<std::string> values;
    const std::string start = "`" + key + "` = ";
    size_t i = row.find(start);
    if (i == std::string::npos) return values;
    int depth = 0;
    for (i += start.size(); i < row.size(); ++i) {
        const char c = row[i];
        if (c == '(') ++depth;
        if (c == ')') --depth;
        if (depth > 0) continue;
        if (c == ';' || (c == '|' && row[i - 1] != '\\')) break;
        if (c == ',' && row.compare(i, 3, ", `") == 0 && i + 3 < row.size() && row[i + 3] != '"') break;
        if (c == '"') {
            const size_t end = row.find('"', i + 1);
            values.insert(row.substr(i + 1, end - i - 1));
            i = end;
        }
    }
    return values;
}

std::set<std::string> as_set(const std::vector<std::string>& v) { return {v.begin(), v.end()}; }

}  // namespace

TEST(RegistryDocs, ConfigReferenceListsEveryRegistryExactly) {
    EXPECT_EQ(listed_values(config_reference_row("`[[lights]]`"), "type"), as_set(light_names()));
    EXPECT_EQ(listed_values(config_reference_row("`[[media]]`"), "type"), as_set(medium_names()));
    EXPECT_EQ(listed_values(config_reference_row("`[[shapes]]`"), "material"), as_set(material_names()));
    EXPECT_EQ(listed_values(config_reference_row("`[render]`"), "integrator"), as_set(integrator_names()));
    EXPECT_EQ(listed_values(config_reference_row("`[photons]`"), "estimator"), as_set(Estimator::names()));
    EXPECT_EQ(listed_values(config_reference_row("`[photons]`"), "kernel"), as_set(Kernel::names()));
    EXPECT_EQ(listed_values(config_reference_row("`[photons]`"), "gather"), as_set(gather_names()));
    EXPECT_EQ(listed_values(config_reference_row("`[photons]`"), "neighbours"), as_set(neighbourhood_names()));
}

TEST(RegistryDocs, KernelDocumentListsEveryKernelExactly) {
    std::istringstream in(read("docs/kernels.md"));
    std::set<std::string> table_rows, comment;
    bool in_table = false;
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("| kernel | K(t)", 0) == 0) {
            in_table = true;
            continue;
        }
        if (in_table && line.rfind("| ", 0) == 0 && line.rfind("|--", 0) != 0)
            table_rows.insert(line.substr(2, line.find(" |", 2) - 2));
        else if (in_table && line.rfind("|--", 0) != 0)
            in_table = false;
        // The config example's comment listing the choices: kernel = "..."  # constant (default) | cone | ...
        const size_t hash = line.find('#');
        if (line.find("kernel = \"") != std::string::npos && hash != std::string::npos &&
            line.find("(default) |", hash) != std::string::npos) {
            std::istringstream names(line.substr(hash + 1));
            for (std::string w; names >> w;)
                if (w != "|" && w != "(default)") comment.insert(w);
        }
    }
    EXPECT_EQ(table_rows, as_set(Kernel::names()));
    EXPECT_EQ(comment, as_set(Kernel::names()));
}

TEST(RegistryDocs, TheRowParserReadsWhatItShould) {
    const std::string row = "| `[x]` | `type` = `\"a\"` (`k` = `\"inner\"`), `\"b\"` (`j`); both: `g`, `kind` = `\"c\"` \\| "
                            "`\"d\"`, `m` (1) |";
    EXPECT_EQ(listed_values(row, "type"), (std::set<std::string>{"a", "b"}));
    EXPECT_EQ(listed_values(row, "kind"), (std::set<std::string>{"c", "d"}));
    EXPECT_TRUE(listed_values(row, "none").empty());
}

TEST(RegistryDocs, RenderHelpListsEveryRegisteredName) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("vpm_registry_docs_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    const vpm::test::Outcome o = vpm::test::run_vpm("render --help", dir);
    std::filesystem::remove_all(dir);
    ASSERT_EQ(o.code, 0) << o.err;
    for (const auto& names : {light_names(), medium_names(), material_names(), integrator_names(), Estimator::names(), Kernel::names(),
                              beam_widths_names()})
        for (const std::string& n : names) EXPECT_NE(o.out.find(n), std::string::npos) << n << "\n" << o.out;
}
