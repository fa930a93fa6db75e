#include "scene/scene.h"

#include <iostream>

#include "core/error.h"
#include "core/progress.h"
#include "scene/grid_medium.h"
#include "scene/homogeneous_medium.h"
#include "scene/lights.h"

namespace vpm {

namespace {

RenderSettings read_render(Params p) {
    RenderSettings r;
    r.width = int(p.integer("width", r.width, Range::closed(1, 65536)));
    r.height = int(p.integer("height", r.height, Range::closed(1, 65536)));
    r.spp = int(p.integer("spp", r.spp, Range::closed(1, 1 << 24)));
    r.seed = uint64_t(p.integer("seed", int64_t(r.seed), Range::at_least(0)));
    r.threads = int(p.integer("threads", r.threads, Range::closed(0, 4096)));
    r.output = p.string("output", r.output);
    r.integrator = p.choice("integrator", r.integrator, {"path", "photon_map"});
    r.max_depth = int(p.integer("max_depth", r.max_depth, Range::closed(-1, 1 << 20)));
    r.rr_depth = int(p.integer("rr_depth", r.rr_depth, Range::closed(1, 1 << 20)));
    r.exposure = p.real("exposure", r.exposure, Range::closed(-64, 64));
    // Film accumulators are 3 doubles per pixel next to the 3-float image; refuse what cannot fit.
    const double bytes = double(r.width) * double(r.height) * 3.0 * (8.0 + 4.0);
    if (bytes > 0.8 * double(physical_memory_bytes()))
        p.fail("width", "a " + std::to_string(r.width) + "x" + std::to_string(r.height) +
                            " image needs " + std::to_string(bytes / 1e9) + " GB, more than this machine's memory");
    p.finish();
    return r;
}

PhotonSettings read_photons(Params p) {
    PhotonSettings s;
    s.count = p.integer("count", s.count, Range::closed(1, int64_t(1) << 40));
    s.estimator = p.choice("estimator", s.estimator, {"classic", "corrected", "mse_optimal"});
    const int min_k = s.estimator == "classic" ? 1 : s.estimator == "corrected" ? 2 : 3;
    s.k = int(p.integer("k", s.k, Range::closed(1, 1 << 20)));
    if (s.k < min_k)
        p.fail("k", "the " + s.estimator + " estimator needs k >= " + std::to_string(min_k) +
                        (s.estimator == "corrected" ? " (it drops the k-th photon)" : ""));
    if (s.estimator == "corrected" && s.k == 2)
        std::cerr << "warning: " << p.where("k")
                  << ": corrected estimator with k = 2 is unbiased but has infinite variance\n";
    s.direct = p.choice("direct", s.direct, {"nee", "photon_map"});
    s.max_radius = p.real("max_radius", s.max_radius, Range::at_least(0.0));
    s.max_bounces = int(p.integer("max_bounces", s.max_bounces, Range::closed(1, 1 << 30)));
    s.memory_budget_fraction = p.real("memory_budget_fraction", s.memory_budget_fraction, {0.0, 1.0, true, false});
    s.final_gather = p.boolean("final_gather", s.final_gather);
    s.extinction = p.choice("extinction", s.extinction, {"point", "ball"});
    s.max_radius_mfp = p.real("max_radius_mfp", s.max_radius_mfp, Range::at_least(0.0));
    s.allocation = p.choice("allocation", s.allocation, {"importance", "power"});
    p.finish();
    return s;
}

}  // namespace

std::unique_ptr<Scene> Scene::load(const std::string& path, const std::vector<std::string>& overrides) {
    return build(load_config(path, overrides));
}

std::unique_ptr<Scene> Scene::build(std::shared_ptr<const ConfigDocument> doc) {
    auto scene = std::make_unique<Scene>();
    scene->source_file = doc->file;
    Params root(doc, &scene->resolved);
    scene->render = read_render(root.table("render"));
    scene->photons = read_photons(root.table("photons"));
    {
        Params cam = root.table("camera");
        scene->camera = Camera::from_params(cam, scene->render.width, scene->render.height);
    }
    for (Params& lp : root.tables("lights")) scene->lights.push_back(make_light(lp));
    if (scene->lights.empty()) root.fail("lights", "the scene has no [[lights]]; add at least one");

    for (Params& mp : root.tables("media")) {
        const std::string type = mp.choice("type", {"homogeneous", "grid"});
        if (type == "grid") {
            scene->media.push_back(make_grid_medium(mp));
            ++scene->openvdb_media_;
        } else {
            scene->media.push_back(make_homogeneous_medium(mp));
        }
        mp.finish();
        scene->bounds.extend(scene->media.back()->bounds());
        scene->build_log.push_back("medium: " + scene->media.back()->describe());
    }

    std::vector<Params> shapes = root.tables("shapes");
    if (!shapes.empty()) {
        scene->surfaces = Surfaces::create(shapes);
        scene->bounds.extend(scene->surfaces->bounds());
        scene->build_log.push_back("Embree: " + scene->surfaces->describe());
    } else {
        scene->build_log.push_back("Embree: not built (no shapes)");
    }
    scene->build_log.push_back(scene->openvdb_media_ ? "OpenVDB: " + std::to_string(scene->openvdb_media_) + " grid(s) loaded"
                                                     : "OpenVDB: not used (no grid media)");
    root.finish();

    for (auto& light : scene->lights) {
        light->set_scene_bounds(scene->bounds);
        scene->build_log.push_back("light: " + light->describe());
    }
    scene->build_log.push_back("camera: " + scene->camera.describe());
    return scene;
}

MediumEvent Scene::sample_medium(const Ray& ray, double tmax, Rng& rng) const {
    MediumEvent event;
    for (const auto& m : media) {
        const double t = m->sample_free_flight(ray, std::min(tmax, event.t), rng);
        if (t < event.t) {
            event.t = t;
            event.medium = m.get();
        }
    }
    return event;
}

double Scene::transmittance(const Ray& ray, double tmax, Rng& rng) const {
    if (surfaces && surfaces->occluded(ray, tmax)) return 0.0;
    double tr = 1.0;
    for (const auto& m : media) {
        tr *= m->transmittance(ray, tmax, rng);
        if (tr == 0.0) break;
    }
    return tr;
}

Rgb Scene::escaped_radiance(const Vec3& dir) const {
    Rgb l = Rgb::Zero();
    for (const auto& light : lights) l += light->escaped_radiance(dir);
    return l;
}

Rgb Scene::total_light_power() const {
    Rgb p = Rgb::Zero();
    for (const auto& light : lights) p += light->power();
    return p;
}

}  // namespace vpm
