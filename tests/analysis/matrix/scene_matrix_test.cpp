// The scene matrix's quick subset (issue 20) at fixed work: every figure present and finite,
// references cached by scene hash and reused by a second run, and the cell scaled by 1e3
// reproducing its unscaled cell's figures (same seed, same work: only rounding may differ).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>

#include "analysis/sweep/row_hash.h"
#include "analysis/matrix/scene_matrix.h"
#include "core/error.h"
#include "render/run/run_config.h"

namespace fs = std::filesystem;
using namespace vpm;

namespace {

MatrixOptions quick_options(const fs::path& out) {
    MatrixOptions o;
    o.quick = true;
    o.budget = 0.0;   // fixed work (one pass of 16 spp): figures independent of the clock
    o.passes = 1;
    o.reference_seconds = 0.4;
    o.size = 16;
    o.media = fs::path(VPM_SOURCE_DIR) / "media";
    o.out = out;
    o.sets = {"photons.count=4000"};
    return o;
}

struct QuickRun {
    fs::path out;
    MatrixReport first, again;
};

const QuickRun& quick_run() {
    static const QuickRun r = [] {
        QuickRun q;
        q.out = fs::temp_directory_path() / ("vpm_matrix_quick_" + std::to_string(getpid()));
        q.first = run_scene_matrix(quick_options(q.out));
        MatrixOptions o = quick_options(q.out);
        o.filter = [](const MatrixCell& c) { return c.shape == "sphere"; };
        q.again = run_scene_matrix(o);
        fs::remove_all(q.out);
        return q;
    }();
    return r;
}

const MatrixRow* find(const MatrixReport& r, const std::string& id) {
    for (const auto& row : r.rows)
        if (row.cell.id() == id) return &row;
    return nullptr;
}

}  // namespace

TEST(SceneMatrixQuick, TableIsCompleteAndFinite) {
    const MatrixReport& r = quick_run().first;
    ASSERT_EQ(r.rows.size(), matrix_cells(true).size());
    for (const auto& row : r.rows) {
        ASSERT_EQ(row.methods.size(), matrix_methods().size()) << row.cell.id();
        EXPECT_GT(row.sigma_t_scale, 0.0);
        EXPECT_GE(row.reference_noise, 0.0);
        for (size_t i = 0; i < row.methods.size(); ++i) {
            const auto& m = row.methods[i];
            EXPECT_EQ(m.nonfinite_pixels, 0u) << row.cell.id() << " " << m.label;
            EXPECT_EQ(m.passes, 1) << row.cell.id() << " " << m.label;
            EXPECT_TRUE(std::isfinite(m.rel_rmse) && m.rel_rmse > 0.0) << row.cell.id() << " " << m.label;
            EXPECT_TRUE(std::isfinite(m.cost()) && m.seconds > 0.0) << row.cell.id() << " " << m.label;
            if (i > 0) {
                EXPECT_TRUE(std::isfinite(row.ratio(i))) << row.cell.id() << " " << m.label;
            }
        }
    }
    const std::string md = r.to_markdown("test", "test"), csv = r.to_csv();
    const std::regex nonfinite("\\b(nan|inf)\\b", std::regex::icase);   // not "luminance"
    EXPECT_FALSE(std::regex_search(md, nonfinite)) << md;
    EXPECT_FALSE(std::regex_search(csv, nonfinite)) << csv;
}

TEST(SceneMatrixQuick, ReferencesAreCachedByUnscaledSceneAndReused) {
    const QuickRun& q = quick_run();
    // Four cells, one of them the scaled copy of another: three references rendered.
    EXPECT_EQ(q.first.references_rendered, 3);
    EXPECT_EQ(q.first.references_reused, 0);
    const MatrixRow* a = find(q.first, "box-tau1-a0.9-g0-point-s1");
    const MatrixRow* b = find(q.first, "box-tau1-a0.9-g0-point-s1000");
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->reference, b->reference);
    // The second run (the sphere cell only) reads its reference from the cache.
    ASSERT_EQ(q.again.rows.size(), 1u);
    EXPECT_EQ(q.again.references_rendered, 0);
    EXPECT_EQ(q.again.references_reused, 1);
    EXPECT_TRUE(q.again.rows[0].reference_reused);
    EXPECT_EQ(q.again.rows[0].reference, find(q.first, q.again.rows[0].cell.id())->reference);
}

TEST(SceneMatrixQuick, ScaledCellReproducesItsUnscaledFigures) {
    const MatrixReport& r = quick_run().first;
    const MatrixRow* a = find(r, "box-tau1-a0.9-g0-point-s1");
    const MatrixRow* b = find(r, "box-tau1-a0.9-g0-point-s1000");
    ASSERT_TRUE(a && b);
    EXPECT_DOUBLE_EQ(a->sigma_t_scale, b->sigma_t_scale);
    for (size_t i = 0; i < a->methods.size(); ++i) {
        // Same seeds and work against the same reference: equal errors up to rounding, which may
        // flip a few random decisions (a few pixels' worth of the error, far below a 5% change).
        EXPECT_NEAR(b->methods[i].rel_rmse, a->methods[i].rel_rmse, 0.05 * a->methods[i].rel_rmse) << a->methods[i].label;
    }
}

TEST(SceneMatrix, ScaledSceneScalesLengthsAndExtinction) {
    MatrixCell c{"g", "sphere", 10, 0.9, 0.0, "spot", 1e3};
    const std::string t = matrix_scene_toml(c, 5.0, "/media", 64);
    EXPECT_NE(t.find("radius = 1000.0"), std::string::npos) << t;
    EXPECT_NE(t.find("sigma_t_scale = 0.005"), std::string::npos) << t;
    EXPECT_NE(t.find("intensity = 2e+07"), std::string::npos) << t;
    MatrixCell bad = c;
    bad.light = "laser";
    EXPECT_THROW(matrix_scene_toml(bad, 5.0, "/media", 64), std::exception);
}

// The reference cache's key follows the media file's content, not the checkout's folder: the same
// cell written in two folders holding copies of blob.vdb hashes alike; other content does not.
TEST(SceneMatrix, SceneHashFollowsMediaContentNotTheirFolder) {
    const fs::path root = fs::temp_directory_path() / ("vpm_matrix_hash_" + std::to_string(getpid()));
    const fs::path src = fs::path(VPM_SOURCE_DIR) / "media" / "blob.vdb";
    MatrixCell c{"g", "blob", 1, 0.9, 0.0, "point", 1.0};
    auto hash_in = [&](const std::string& folder) {
        const fs::path media = root / folder / "media";
        const fs::path scene = root / folder / "cell.toml";
        std::ofstream(scene) << matrix_scene_toml(c, 2.0, media, 8);
        return scene_hash(RunConfig::load(scene.string(), {"render.integrator=\"path\""}).resolved);
    };
    for (const char* f : {"a", "b", "c"}) {
        fs::create_directories(root / f / "media");
        // c: another grid under the same name
        fs::copy_file(*f == 'c' ? src.parent_path() / "plume.vdb" : src, root / f / "media" / "blob.vdb",
                      fs::copy_options::overwrite_existing);
    }
    const std::string a = hash_in("a"), b = hash_in("b"), changed = hash_in("c");
    EXPECT_EQ(a, b);
    EXPECT_NE(a, changed);
    fs::remove_all(root);
}

// `vpm bench matrix --set` reaches the compared runs only, so it may not change what the cached
// references were rendered for.
TEST(SceneMatrix, MethodSetsAreLimitedToPhotonKeysAndTheSeed) {
    EXPECT_NO_THROW(vpm::check_matrix_method_set("photons.store_probability=\"auto\""));
    EXPECT_NO_THROW(vpm::check_matrix_method_set("render.seed=2"));
    EXPECT_THROW(vpm::check_matrix_method_set("media.albedo=0.5"), vpm::Error);
    EXPECT_THROW(vpm::check_matrix_method_set("render.time_limit=1"), vpm::Error);
    EXPECT_THROW(vpm::check_matrix_method_set("photons.k"), vpm::Error);
    EXPECT_THROW(vpm::check_matrix_method_set("=3"), vpm::Error);
}
