#include "scene/scene.h"

#include <algorithm>

#include "scene/camera_region.h"
#include "scene/emission_guides.h"
#include "scene/interior_medium.h"
#include "scene/lights/light_registry.h"
#include "scene/media/optical_depth_profile.h"
#include "scene/media/medium_registry.h"

namespace vpm {

namespace {

bool finite_or_empty(const Bounds3& b) { return b.empty() || (b.lo.allFinite() && b.hi.allFinite()); }

std::string format_bounds(const Bounds3& b) {
    return "[" + format_rgb(b.lo.array()) + " .. " + format_rgb(b.hi.array()) + "]";
}

// Lights at infinity aim part of their photons at what the camera sees (scene/camera_region.h);
// the region is only traced for a scene that has such a light.
void focus_lights_at_infinity(Scene& scene) {
    bool any = false;
    for (const auto& light : scene.lights) any = any || light->at_infinity();
    if (!any) return;
    const Bounds3 region = camera_seen_region(scene);
    for (size_t i = 0; i < scene.lights.size(); ++i)
        if (scene.lights[i]->at_infinity() && scene.lights[i]->set_emission_focus(region))
            scene.build_log.push_back("light " + std::to_string(i) + ": half of its photons aimed at the region the camera sees, " +
                                      format_bounds(region) + " (scene/lights/emission_bounds.h)");
}

// Each shape's `interior_medium` (-1 where unset), read before Surfaces::create finishes the tables:
// an index of a [[media]] table, named by one shape at most.
std::vector<int> read_interior_media(std::vector<Params>& shapes, size_t media) {
    std::vector<int> interior(shapes.size(), -1);
    for (size_t i = 0; i < shapes.size(); ++i) {
        Params& p = shapes[i];
        if (!p.has("interior_medium")) continue;
        const int64_t n = p.integer("interior_medium");
        if (n < 0 || uint64_t(n) >= media)
            p.fail("interior_medium", "value " + std::to_string(n) + " is not a [[media]] table of this scene; allowed: " +
                                          (media == 0 ? std::string("none (the scene has no [[media]])")
                                                      : "0 to " + std::to_string(media - 1) + " (the 0-based index of a [[media]] table)"));
        for (size_t j = 0; j < i; ++j)
            if (interior[j] == int(n))
                p.fail("interior_medium", "[[media]] table " + std::to_string(n) + " is already the interior medium of shape " +
                                              std::to_string(j) + " (" + shapes[j].where("interior_medium") +
                                              "); a medium can be inside one shape only");
        interior[i] = int(n);
    }
    return interior;
}

// Replaces each interior medium by the same medium confined to its shape, which must be a closed
// dielectric (its inside is a region, scene/dielectric_regions.h).
void confine_interior_media(Scene& scene, const std::vector<Params>& shapes, const std::vector<int>& interior) {
    bool any = false;
    for (size_t i = 0; i < shapes.size(); ++i) {
        if (interior[i] < 0) continue;
        const auto& dielectrics = scene.surfaces->dielectric_shapes();
        int shape = -1;
        for (size_t d = 0; d < dielectrics.size(); ++d)
            if (dielectrics[d].table == i) shape = int(d);
        if (shape < 0)
            shapes[i].fail("interior_medium", "needs a closed glass shape: material = \"dielectric\" on a box, sphere or closed mesh");
        auto& medium = scene.media[size_t(interior[i])];
        medium = std::make_unique<InteriorMedium>(std::move(medium), *scene.surfaces, shape);
        scene.build_log.push_back("medium " + std::to_string(interior[i]) + ": " + medium->describe());
        any = true;
    }
    if (!any) return;
    // What the media fill is now their shapes' inside.
    scene.bounds = scene.surfaces->bounds();
    for (const auto& m : scene.media) scene.bounds.extend(m->bounds());
}

}  // namespace

void check_medium_contract(const Medium& medium, const Params& table) {
    const Bounds3 b = medium.bounds();
    if (!finite_or_empty(b))
        table.fail("type", "the medium's bounds " + format_bounds(b) +
                               " are not a finite box; lights at infinity emit over the scene bounds and point "
                               "lights aim at them, so a medium must bound the region where its density is "
                               "non-zero (scene/media/medium_registry.h)");
}

void check_light_contract(const Light& light, const Params& table, const std::string& why) {
    // The key the user can change: the light's emission, else its type.
    std::string key = "type";
    for (const char* k : {"radiance", "irradiance", "intensity", "file"})
        if (table.has(k)) {
            key = k;
            break;
        }
    require_finite_power(table, key, light, why);
    const Rgb power = light.power();
    if ((power.array() < 0.0).any())
        table.fail(key, "the light's total power " + format_rgb(power) + " is negative");
    if (!finite_or_empty(light.bounds()))
        table.fail("type", "the area light's bounds " + format_bounds(light.bounds()) + " are not a finite box");
}

std::unique_ptr<Scene> Scene::build(Params& root, int width, int height) {
    auto scene = std::make_unique<Scene>();
    {
        Params cam = root.table("camera");
        scene->camera = Camera::from_params(cam, width, height);
    }
    std::vector<Params> light_tables = root.tables("lights");
    for (Params& lp : light_tables) scene->lights.push_back(make_light(lp));
    if (scene->lights.empty()) root.fail("lights", "the scene has no [[lights]]; add at least one");

    for (Params& mp : root.tables("media")) {
        const MediumType* type = nullptr;
        scene->media.push_back(make_medium(mp, &type));
        check_medium_contract(*scene->media.back(), mp);
        if (type->uses_openvdb) ++scene->openvdb_media_;
        scene->bounds.extend(scene->media.back()->bounds());
        scene->build_log.push_back("medium: " + scene->media.back()->describe());
    }

    std::vector<Params> shapes = root.tables("shapes");
    if (!shapes.empty()) {
        const std::vector<int> interior = read_interior_media(shapes, scene->media.size());
        scene->surfaces = Surfaces::create(shapes);
        scene->bounds.extend(scene->surfaces->bounds());
        scene->build_log.push_back("Embree: " + scene->surfaces->describe());
        for (const auto& [glass, other] : scene->surfaces->coplanar_glass_contacts())
            scene->build_log.push_back("warning: [[shapes]] tables " + std::to_string(glass) + " (glass) and " + std::to_string(other) +
                                       " touch in one plane: light leaving the glass there misses the other surface while paths "
                                       "from it enter the glass, so photon-map and path-traced images disagree; leave a small "
                                       "gap between them (scene/surfaces/coplanar_contact.h)");
        confine_interior_media(*scene, shapes, interior);
    } else {
        scene->build_log.push_back("Embree: not built (no shapes)");
    }
    scene->build_log.push_back(scene->openvdb_media_ ? "OpenVDB: " + std::to_string(scene->openvdb_media_) + " grid(s) loaded"
                                                     : "OpenVDB: not used (no grid media)");

    // Area lights are opaque geometry: what can be lit (and can block light) includes them.
    for (auto& light : scene->lights)
        if (!light->bounds().empty()) scene->area_lights_.push_back(light.get());
    Bounds3 lit = scene->bounds;   // media and shapes
    for (const Light* l : scene->area_lights_) lit.extend(l->bounds());
    for (size_t i = 0; i < scene->lights.size(); ++i) {
        Light& light = *scene->lights[i];
        // What a light can light: the scene's bounds without its own box (an area light lights the rest).
        Bounds3 target = light.bounds().empty() ? lit : scene->bounds;
        if (!light.bounds().empty())
            for (const Light* l : scene->area_lights_)
                if (l != &light) target.extend(l->bounds());
        light.set_scene_bounds(target);
        // Lights at infinity emit over the bounds: their power is known only now.
        check_light_contract(light, light_tables[i],
                             "emission over the scene's bounds, " + format_value((target.hi - target.lo).norm()) + " across");
        scene->build_log.push_back("light: " + light.describe());
    }
    scene->bounds = lit;
    focus_lights_at_infinity(*scene);
    scene->build_log.push_back("camera: " + scene->camera.describe());
    return scene;
}

const std::vector<std::string>& Scene::prepare_photon_emission() const {
    std::call_once(emission_guides_once_, [this] { emission_guides_log_ = guide_photon_emission(*this); });
    return emission_guides_log_;
}

double Scene::optical_depth(const Ray& ray, double tmax) const {
    double depth = 0.0;
    OpticalDepthProfile profile;
    for (const auto& m : media) {
        m->optical_depth_profile(ray, tmax, profile);
        depth += profile.total();
    }
    return depth;
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

bool Scene::intersect(const Ray& ray, double tmax, SurfaceHit& hit) const {
    bool found = surfaces && surfaces->intersect(ray, tmax, hit);
    EmitterHit e;
    for (const Light* light : area_lights_) {
        const bool on_emitter = found && hit.emitter;
        if (!light->intersect(ray, on_emitter ? std::min(tmax, hit.t * (1.0 + kCoincidentEmitters)) : found ? hit.t : tmax, e))
            continue;
        if (on_emitter && e.t >= hit.t * (1.0 - kCoincidentEmitters)) {   // the same point: both emit
            hit.emitted += e.radiance;
            hit.coincident_emitters = true;
            continue;
        }
        found = true;
        hit = SurfaceHit{};
        hit.t = e.t;
        hit.position = ray.at(e.t);
        hit.normal = e.normal;
        hit.emitter = light;
        hit.emitted = e.radiance;
    }
    return found;
}

double Scene::transmittance(const Ray& ray, double tmax, Rng& rng, const Light* target) const {
    if (surfaces && surfaces->occluded(ray, tmax)) return 0.0;
    EmitterHit e;
    for (const Light* light : area_lights_)
        if (light != target && light->intersect(ray, tmax * (1.0 - kCoincidentEmitters), e)) return 0.0;
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
