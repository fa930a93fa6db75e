// Every file path that a config comment or a document names exists, so a move (the scene/ split,
// a renamed test) cannot leave a reader following a stale pointer. Paths are looked up from the
// repository root, the mentioning file's folder, lib/ (include paths such as "photon/estimate/kernels.h")
// configs/ (config comments name their siblings) and configs/sweeps/ (sweep examples name scenes
// relative to the sweep file); outputs (out/, build/, $VAR/...), extensions alone and the optional
// third-party files beside a checkout (../shared/..., absent in a plain clone) are skipped.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path kRoot = VPM_SOURCE_DIR;

// Files that a comment names but that a command writes at run time.
const std::set<std::string> kGenerated = {"dense_voxel.vdb"};

bool path_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '/' || c == '-' || c == '$'; }

bool has_checked_extension(const std::string& t) {
    for (const char* ext : {".cpp", ".h", ".toml", ".md", ".vdb", ".exr", ".py", ".sh", ".obj", ".ply", ".in"}) {
        const std::string e = ext;
        if (t.size() > e.size() && t.compare(t.size() - e.size(), e.size(), e) == 0) return true;
    }
    return false;
}

// The path-like words of a line, trailing sentence punctuation removed.
std::vector<std::string> path_words(const std::string& line) {
    std::vector<std::string> words;
    std::string w;
    for (size_t i = 0; i <= line.size(); ++i) {
        if (i < line.size() && path_char(line[i])) {
            w += line[i];
            continue;
        }
        while (!w.empty() && (w.back() == '.' || w.back() == '-')) w.pop_back();
        if (!w.empty() && has_checked_extension(w)) words.push_back(w);
        w.clear();
    }
    return words;
}

bool exists_somewhere(const std::string& word, const fs::path& mentioned_in) {
    for (const fs::path& base :
         {kRoot, mentioned_in.parent_path(), kRoot / "lib", kRoot / "configs", kRoot / "configs" / "sweeps"})
        if (fs::exists(base / word)) return true;
    return false;
}

std::vector<std::string> stale_paths(const fs::path& file, bool comments_only, bool bare_names) {
    std::vector<std::string> stale;
    std::ifstream in(file);
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        if (comments_only) {
            const size_t hash = line.find('#');
            if (hash == std::string::npos) continue;
            line = line.substr(hash);
        }
        for (const std::string& w : path_words(line)) {
            // /tmp/...: a session's scratch file named in a measurement's provenance, gone on a fresh machine.
            if (w.rfind("/tmp/", 0) == 0) continue;
            if (w[0] == '$' || (w[0] == '.' && w.rfind("../", 0) != 0) || w.rfind("../shared/", 0) == 0 || w.rfind("out/", 0) == 0 || w.rfind("build/", 0) == 0 || kGenerated.count(w)) continue;
            if (!bare_names && w.find('/') == std::string::npos) continue;   // prose names a file by its name
            if (!exists_somewhere(w, file))
                stale.push_back(fs::relative(file, kRoot).string() + ":" + std::to_string(n) + ": " + w);
        }
    }
    return stale;
}

}  // namespace

TEST(DocPaths, ConfigCommentsNameExistingFiles) {
    std::vector<std::string> stale;
    size_t configs = 0;
    for (const auto& e : fs::recursive_directory_iterator(kRoot / "configs")) {
        if (e.path().extension() != ".toml") continue;
        ++configs;
        for (const std::string& s : stale_paths(e.path(), true, true)) stale.push_back(s);
    }
    EXPECT_GT(configs, 10u);
    for (const std::string& s : stale) ADD_FAILURE() << "a config comment names a missing file: " << s;
}

TEST(DocPaths, DocumentsNameExistingFiles) {
    std::vector<fs::path> docs = {kRoot / "README.md", kRoot / "BENCHMARKS.md", kRoot / "STRESS.md"};
    for (const char* folder : {"docs", "media", "tests/data/vdb"})
        for (const auto& e : fs::recursive_directory_iterator(kRoot / folder))
            if (e.path().extension() == ".md") docs.push_back(e.path());
    for (const fs::path& d : docs) {
        ASSERT_TRUE(fs::exists(d)) << d;
        for (const std::string& s : stale_paths(d, false, false)) ADD_FAILURE() << "a document names a missing file: " << s;
    }
}

TEST(DocPaths, TheCheckFindsAStalePath) {
    const fs::path tmp = fs::temp_directory_path() / ("vpm_doc_paths_test_" + std::to_string(::getpid()) + ".md");
    std::ofstream(tmp) << "See lib/scene/params.h and lib/config/params.h.\n";
    const std::vector<std::string> stale = stale_paths(tmp, false, false);
    fs::remove(tmp);
    ASSERT_EQ(stale.size(), 1u);
    EXPECT_NE(stale[0].find("lib/scene/params.h"), std::string::npos) << stale[0];
}
