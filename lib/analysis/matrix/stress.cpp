#include "analysis/matrix/stress.h"

#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>


#include "core/error.h"
#include "core/progress.h"
#include "photon/estimate/estimators.h"
#include "photon/map/photon_map.h"
#include "render/run/run.h"
#include "core/density_grid.h"
#include "io/vdb_io.h"
#include "render/photon_map/photon_map_stats.h"

namespace vpm {

namespace {

enum class Ref { none, analytic, path, compare };

struct CellSpec {
    std::string group, label, scene;
    std::vector<std::string> sets;
    Ref ref = Ref::none;
    double analytic = 0.0;
    std::string compare_to;              // "group/label" of an earlier cell (Ref::compare)
    bool full_only = false;              // too big for --quick
    std::string note;
    std::function<void(StressCell&)> custom;   // library-level cell (no scene file)

    CellSpec(std::string g, std::string l, std::string sc, std::vector<std::string> st, Ref r = Ref::none,
             double a = 0.0)
        : group(std::move(g)), label(std::move(l)), scene(std::move(sc)), sets(std::move(st)), ref(r), analytic(a) {}
};

std::string num(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

std::string coord(double v) {   // exact decimal for TOML overrides
    std::ostringstream s;
    s << std::setprecision(17) << v;
    const std::string t = s.str();
    return t.find_first_of(".e") == std::string::npos ? t + ".0" : t;
}

uint64_t nonfinite_count(const Image& img) {
    uint64_t n = 0;
    for (float v : img.rgb) n += !std::isfinite(v);
    return n;
}

// One voxel of density `peak` at the centre of a 64^3 block of density `background`.
void write_dense_voxel_vdb(const std::filesystem::path& path, float background = 1e-6f, float peak = 1e6f) {
    DensityGrid grid(Vec3i(0, 0, 0), Vec3i(63, 63, 63));
    for (int z = 0; z < 8; ++z)
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) grid.set_block_constant(Vec3i(x, y, z), background);
    grid.set_voxel(Vec3i(32, 32, 32), peak);
    grid.finalize();
    write_vdb_density(path.string(), "density", grid);
}

// All photons at one point: kNN radii are 0; the estimator must extend the ball or return 0,
// never Inf or NaN (estimators.h rule (c)).
void coincident_cell(StressCell& c, size_t n, size_t k, double offset) {
    std::vector<PhotonInput> photons(n, PhotonInput{Vec3(0.25, -0.5, 1.0), Vec3(0.0, 0.0, -1.0), Rgb::Constant(1.0 / double(n))});
    if (n > 1) photons.back().position = Vec3(0.25, -0.5, 1.5);   // one photon farther away, to extend to
    const PhotonMap map(photons);
    GatherBuffers buf;
    EstimatorStats stats;
    const Timer t;
    double sum = 0.0;
    uint64_t queries = 0;
    for (int i = -2; i <= 2; ++i) {
        const Vec3 x = Vec3(0.25, -0.5, 1.0) + Vec3(0.0, 0.0, offset * i);
        for (const Estimator& e : Estimator::all()) {
            if (k < e.min_k()) continue;
            const Estimate<Rgb> est = estimate_in_scattering(map, x, Vec3(0, 0, 1), 0.5, e, k, kInfinity, buf, &stats);
            for (int ch = 0; ch < 3; ++ch) {
                c.nonfinite_samples += !std::isfinite(est.value[ch]);
                sum += est.value[ch];
            }
            ++queries;
        }
    }
    c.seconds = t.seconds();
    c.value = queries ? sum / double(3 * queries) : 0.0;
    c.note = std::to_string(n) + " photons, queries at the point and +-" + num(offset) + "; " + stats.to_string();
}

std::vector<CellSpec> specs(bool quick) {
    std::vector<CellSpec> v;
    auto furnace = [&](std::string group, std::string label, std::vector<std::string> sets, std::string note = "") {
        CellSpec s{group, label, "furnace.toml", std::move(sets), Ref::analytic, 0.5};
        s.note = std::move(note);
        v.push_back(s);
        return &v.back();
    };
    auto sphere = [&](std::string group, std::string label, std::vector<std::string> sets, std::string note = "") {
        CellSpec s{group, label, "sphere.toml", std::move(sets), Ref::path};
        s.note = std::move(note);
        v.push_back(s);
        return &v.back();
    };
    // sigma_t_scale: optical radius of the furnace sphere 2e-6 .. 2e6.
    for (double s : {1e-6, 1e-3, 1.0, 1e3, 1e6})
        furnace("sigma_t_scale", num(s), {"media.0.sigma_t_scale=" + num(s)},
                s >= 1e3 ? "albedo 1: photons random-walk until max_bounces = 100 (cap bias, reported)" : "");
    // albedo, on the sphere scene against the path tracer.
    for (double a : {0.0, 0.5, 0.99, 0.999, 1.0}) sphere("albedo", num(a), {"media.0.albedo=" + num(a)});
    // Henyey-Greenstein g: the furnace radiance does not depend on g.
    for (double g : {-0.999, -0.9, 0.0, 0.9, 0.999}) furnace("g", num(g), {"media.0.g=" + num(g)});
    // k from the smallest allowed (2: every estimator needs k >= 2); the last cell asks for more than are stored.
    for (int k : {2, 3, 8, 1024})
        furnace("k", std::to_string(k), {"photons.k=" + std::to_string(k)},
                k == 2 ? "corrected k = 2: unbiased, infinite variance" : "");
    furnace("k", "> stored", {"photons.count=50", "photons.k=100000"}, "50 photons emitted, k = 100000: fewer than k stored, camera paths continue");
    // Photon counts (max_bounces 100, sigma 0.5 so the map stays ~1.5 photons per emitted one).
    for (int64_t n : {int64_t(1), int64_t(10), int64_t(1000), int64_t(100000), int64_t(1000000), int64_t(10000000)}) {
        CellSpec* s = furnace("photons", num(double(n)), {"photons.count=" + std::to_string(n), "media.0.sigma_t_scale=0.5"});
        s->full_only = n > 1000;
    }
    // All photons coincident (library level: PhotonMap + estimate_in_scattering).
    for (size_t k : {size_t(2), size_t(8), size_t(1024)}) {
        CellSpec s{"coincident", "k=" + std::to_string(k), "-", {}};
        s.custom = [k](StressCell& c) { coincident_cell(c, 5000, k, 1e-9); };
        v.push_back(s);
    }
    // Translated by 1e6 units: same image as untranslated within noise (same seed, so ~ rounding).
    furnace("translated", "furnace 0", {});
    {
        const std::string t = "1000000.0";
        CellSpec* s = furnace("translated", "furnace +1e6",
                              {"camera.position=[" + t + ", 0.0, 0.0]", "camera.look_at=[" + t + ", 0.0, -1.0]",
                               "media.0.center=[" + t + ", 0.0, 0.0]"});
        s->ref = Ref::compare;
        s->compare_to = "translated/furnace 0";
    }
    sphere("translated", "sphere 0", {});
    {
        const std::string t = "1000000.0";
        CellSpec* s = sphere("translated", "sphere +1e6",
                             {"camera.position=[" + t + ", 0.3, 4.0]", "camera.look_at=[" + t + ", 0.0, 0.0]",
                              "lights.0.position=[" + coord(std::stod(t) - 1.5) + ", 2.5, 1.5]", "media.0.center=[" + t + ", 0.0, 0.0]",
                              "shapes.0.center=[" + t + ", -1.0, 0.0]"},
                             "Embree floor, point light and sphere all moved");
        s->ref = Ref::compare;
        s->compare_to = "translated/sphere 0";
        sphere("translated", "sphere 0, path tracer", {"render.integrator=\"path\""})->ref = Ref::none;
        std::vector<std::string> sets = s->sets;
        sets.push_back("render.integrator=\"path\"");
        CellSpec* p = sphere("translated", "sphere +1e6, path tracer", sets, "reference integrator, same scene");
        p->ref = Ref::compare;
        p->compare_to = "translated/sphere 0, path tracer";
    }
    // Lights inside dense media and on their boundary.
    sphere("light", "inside, sigma 100", {"lights.0.position=[0.0, 0.0, 0.0]", "media.0.sigma_t_scale=100.0", "media.0.albedo=0.99"},
           "no affordable reference: light leaves by diffusion (optical radius 100), which the path tracer's NEE "
           "(transmittance e^-100) and roulette-limited walks do not sample")
        ->ref = Ref::none;
    sphere("light", "on boundary", {"lights.0.position=[0.0, 1.0, 0.0]"});
    sphere("light", "on boundary, sigma 1e4", {"lights.0.position=[0.0, 1.0, 0.0]", "media.0.sigma_t_scale=10000.0"});
    // Pathological media: albedo 1, huge sigma. Photons stop at the cap; paths by roulette.
    sphere("pathological", "albedo 1, sigma 1e6, photon map", {"media.0.albedo=1.0", "media.0.sigma_t_scale=1000000.0"},
           "photon paths truncated at max_bounces = 100");
    {
        CellSpec* s = sphere("pathological", "albedo 1, sigma 1e6, path tracer",
                             {"media.0.albedo=1.0", "media.0.sigma_t_scale=1000000.0", "render.integrator=\"path\""},
                             "reference integrator: Russian roulette (q <= 0.95) bounds the walk");
        s->ref = Ref::none;
    }
    // One extremely dense voxel in near-vacuum (OpenVDB grid written by the tool).
    {
        CellSpec s{"dense voxel", "1e6 in 1e-6", "dense_voxel.toml", {}, Ref::path};
        s.note = "64^3 grid; local majorants and the closed-form optical depth keep the tracking cost bounded";
        v.push_back(s);
    }
    // Grid media at stiff densities, each with both integrators: the default plume at
    // sigma_t_scale 4e2 .. 1e8, the dense voxel 1e9 in 1e-3, box.vdb at 1e15, the plume's medium
    // alone scaled by 1e6. @OUT@ is run_stress's output folder (where the VDB is written).
    {
        auto grid = [&](const std::string& label, const std::string& scene, const std::vector<std::string>& sets,
                        const std::string& note) {
            for (const bool path : {false, true}) {
                std::vector<std::string> s = sets;
                if (path) s.push_back("render.integrator=\"path\"");
                CellSpec c{"dense grid", label + (path ? ", path tracer" : ", photon map"), scene, s};
                c.note = note;
                v.push_back(c);
            }
        };
        for (const char* s : {"4e2", "1e4", "1e6", "1e8"})
            grid(std::string("plume ") + s, "plume.toml", {std::string("media.0.sigma_t_scale=") + s}, "");
        grid("1e9 in 1e-3", "dense_voxel.toml", {"media.0.file=\"@OUT@/dense_voxel_1e9.vdb\""},
             "64^3 grid of 1e-3 with one voxel of 1e9");
        grid("box.vdb 1e15", "plume.toml", {"media.0.file=\"../../media/box.vdb\"", "media.0.sigma_t_scale=1e15"}, "");
        grid("plume scaled 1e6", "plume.toml", {"media.0.transform.scale=1e6"}, "camera inside the scaled plume");
    }
    // Rays grazing the medium bounds: the camera in the plane of the box's top face / the grid's face.
    sphere("grazing", "sphere tangent", {"camera.position=[0.0, 1.0, 4.0]", "camera.look_at=[0.0, 1.0, 0.0]"},
           "the centre row of camera rays is tangent to the sphere at y = 1");
    {
        CellSpec s{"grazing", "grid face", "dense_voxel.toml",
                   {"camera.position=[0.0, -1.0, 3.5]", "camera.look_at=[0.0, -1.0, 0.0]"},
                   Ref::path};
        s.note = "camera rays in the plane of the grid's lower face";
        v.push_back(s);
    }
    (void)quick;
    return v;
}

}  // namespace

bool StressReport::all_ok() const {
    for (const auto& c : cells)
        if (!c.ok()) return false;
    return true;
}

std::vector<std::string> stress_cell_keys(bool quick) {
    std::vector<std::string> keys;
    for (const CellSpec& spec : specs(quick))
        if (!(quick && spec.full_only)) keys.push_back(spec.group + "/" + spec.label);
    return keys;
}

StressReport run_stress(const StressOptions& o) {
    StressReport report;
    report.quick = o.quick;
    const Timer total;
    std::filesystem::create_directories(o.out);
    const std::filesystem::path vdb = std::filesystem::absolute(o.out) / "dense_voxel.vdb";
    write_dense_voxel_vdb(vdb);
    write_dense_voxel_vdb(std::filesystem::absolute(o.out) / "dense_voxel_1e9.vdb", 1e-3f, 1e9f);
    std::map<std::string, Image> images;

    for (const CellSpec& spec : specs(o.quick)) {
        const std::string key = spec.group + "/" + spec.label;
        if (o.quick && spec.full_only) continue;
        if (o.filter && !o.filter(key)) continue;
        StressCell c;
        c.group = spec.group;
        c.label = spec.label;
        c.scene = spec.scene;
        c.note = spec.note;
        if (spec.custom) {
            spec.custom(c);
        } else {
            std::vector<std::string> sets;
            if (o.quick) sets = {"render.width=8", "render.height=8", "render.spp=1", "photons.count=2000"};
            if (spec.scene == "dense_voxel.toml") sets.push_back("media.0.file=\"" + vdb.generic_string() + "\"");
            for (std::string s : spec.sets) {   // the cell's own keys come last and win
                if (const auto at = s.find("@OUT@"); at != std::string::npos)
                    s.replace(at, 5, std::filesystem::absolute(o.out).generic_string());
                sets.push_back(s);
            }
            const std::string file = (o.configs / spec.scene).string();
            const RunConfig config = RunConfig::load(file, sets);
            RunOptions ro;
            ro.progress = false;
            const Timer t;
            RunResult r = run(config, ro);
            c.seconds = t.seconds();
            c.nonfinite_pixels = nonfinite_count(r.image);
            c.nonfinite_samples = r.stats.render.nonfinite_samples;
            c.value = r.image.mean();
            if (const auto& p = PhotonMapStats::of(r.stats).photons) {
                c.photon_pass = true;
                c.energy_imbalance = p->energy.relative_imbalance();
                c.emitted = p->emitted;
                c.stored = p->stored;
                c.truncated_paths = p->truncated_paths;
                const double em = p->energy.emitted.sum();
                c.truncated_energy = em > 0 ? p->energy.truncated.sum() / em : 0.0;
            }
            if (spec.ref == Ref::analytic) {
                c.has_reference = true;
                c.reference_kind = "analytic " + num(spec.analytic);
                c.reference = spec.analytic;
            } else if (spec.ref == Ref::path && !o.quick) {
                // The unbiased path tracer on the same scene, 16x more samples per pixel.
                std::vector<std::string> rs = sets;
                rs.push_back("render.integrator=\"path\"");
                rs.push_back("render.spp=" + std::to_string(16 * config.render.spp));
                RunResult ref = run(RunConfig::load(file, rs), ro);
                c.has_reference = true;
                c.reference_kind = "path tracer";
                c.reference = ref.image.mean();
                c.nonfinite_pixels += nonfinite_count(ref.image);
                c.nonfinite_samples += ref.stats.render.nonfinite_samples;
            } else if (spec.ref == Ref::compare) {
                auto it = images.find(spec.compare_to);
                if (it != images.end() && it->second.rgb.size() == r.image.rgb.size()) {
                    double diff = 0.0, base = 0.0;
                    uint64_t differing = 0;
                    for (size_t i = 0; i < r.image.rgb.size(); ++i) {
                        const double a = r.image.rgb[i], b = it->second.rgb[i];
                        diff += std::abs(a - b);
                        base += std::abs(b);
                        differing += std::abs(a - b) > 1e-4 * std::max(std::abs(b), 1e-3);
                    }
                    c.note += (c.note.empty() ? "" : "; ") + std::to_string(differing) + " of " +
                              std::to_string(r.image.rgb.size()) + " pixel channels differ by > 1e-4";
                    c.has_reference = true;
                    c.reference_kind = "untranslated (mean |diff| / mean)";
                    c.reference = it->second.mean();
                    c.rel_error = base > 0 ? diff / base : diff;
                }
            }
            if (c.has_reference && spec.ref != Ref::compare)
                c.rel_error = c.reference != 0.0 ? (c.value - c.reference) / c.reference : c.value;
            images[key] = std::move(r.image);
        }
        if (o.log)
            *o.log << "stress: " << key << ": nonfinite " << c.nonfinite_pixels << "/" << c.nonfinite_samples
                   << ", imbalance " << c.energy_imbalance << ", truncated " << c.truncated_paths << ", "
                   << c.seconds << " s" << (c.has_reference ? ", rel err " + num(c.rel_error) : "") << "\n";
        report.cells.push_back(std::move(c));
    }
    report.seconds = total.seconds();
    return report;
}

std::string StressReport::to_markdown(const std::string& command, const std::string& machine) const {
    std::ostringstream s;
    s << "# vpm stress matrix\n\n"
         "Generated by `"
      << command << "` (" << (quick ? "quick subset" : "full matrix") << ", " << std::fixed << std::setprecision(1)
      << seconds << " s on " << machine
      << "). Do not edit by hand.\n\n"
         "One axis at a time around the base scenes in `configs/stress/` (furnace.toml: white furnace, "
         "analytic radiance 0.5; sphere.toml: homogeneous sphere over an Embree floor, reference = unbiased "
         "path tracer at 16x the spp; dense_voxel.toml: one voxel of density 1e6 in a 64^3 grid of 1e-6; plume.toml: the default plume "
         "scene with the photon map, for the dense-grid cells), "
         "plus special cells. Columns: non-finite pixels / non-finite samples left out by the render loop "
         "(both must be 0); energy = |emitted - absorbed - escaped - truncated| / emitted of the photon pass "
         "(must be <= 1e-6); truncated = photon paths cut by photons.max_bounces and the fraction of the "
         "emitted power they carried; rel. error = (image mean - reference) / reference (for translated cells: "
         "mean |pixel difference| / mean pixel against the untranslated image). Errors include the photon "
         "map's own bias (boundary bias of the kNN ball, cap bias where paths are truncated) and noise: "
         "they are measurements, not pass/fail criteria.\n\n";
    s << "| axis | value | scene | NaN/Inf px / samples | energy imbalance | photons emitted / stored | truncated paths (power) | time s | image mean | reference | rel. error | ok | note |\n";
    s << "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    auto g = [](double v, int p = 3) {
        std::ostringstream o;
        o << std::setprecision(p) << v;
        return o.str();
    };
    for (const auto& c : cells) {
        s << "| " << c.group << " | " << c.label << " | " << c.scene << " | " << c.nonfinite_pixels << " / "
          << c.nonfinite_samples << " | " << (c.photon_pass ? g(c.energy_imbalance, 2) : "-") << " | "
          << (c.photon_pass ? std::to_string(c.emitted) + " / " + std::to_string(c.stored) : "-") << " | "
          << (c.photon_pass ? std::to_string(c.truncated_paths) + " (" + g(c.truncated_energy, 3) + ")" : "-")
          << " | " << g(c.seconds, 3) << " | " << g(c.value, 4) << " | "
          << (c.has_reference ? g(c.reference, 4) + " (" + c.reference_kind + ")" : "-") << " | "
          << (c.has_reference ? g(c.rel_error, 3) : "-") << " | " << (c.ok() ? "yes" : "**NO**") << " | " << c.note
          << " |\n";
    }
    s << "\nAll cells ok: " << (all_ok() ? "yes" : "**NO**") << "\n";
    return s.str();
}

}  // namespace vpm
