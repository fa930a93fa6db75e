#pragma once
// scene/: what is seen. A Scene is the camera, the lights, the media and the surfaces of a
// config; how it is measured (film, integrator and its passes) belongs to render/. Lights and
// media are created by name through their registries (scene/lights/light_registry.h,
// scene/media/medium_registry.h); surfaces are Embree geometry (scene/surfaces/surfaces.h); Params reads every
// config table and reports unknown keys.
//
// Only what the config uses is built: no Embree device without [[shapes]], no OpenVDB grid
// without a grid medium. `build_log` says what was built; sidecars copy it.
//
// Tables read here: [camera] [[lights]] [[media]] [[shapes]].
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/sampling/rng.h"
#include "scene/camera.h"
#include "scene/lights/light.h"
#include "scene/media/medium.h"
#include "config/params.h"
#include "scene/surfaces/surfaces.h"

namespace vpm {

// Relative distance within which two area lights' hits along a ray are the same point: coincident
// or coplanar overlapping emitters add their radiance there and do not shadow each other.
constexpr double kCoincidentEmitters = 1e-9;

// A real collision sampled along a ray among all media.
struct MediumEvent {
    double t = kInfinity;
    const Medium* medium = nullptr;
    explicit operator bool() const { return medium != nullptr; }
};

// The contracts of the registry headers that a scene can check at build time, each one error
// naming the table (`table` is the light's or medium's own Params): a medium's bounds are a
// finite box (empty only when it holds no density), a light's power is finite (the error names
// the light's emission key and says `why`, e.g. the bounds it emits over) and >= 0, an area
// light's bounds are finite. Scene::build calls them for every object; a new light or medium
// type that breaks them fails there, not as a dark or NaN image later.
void check_medium_contract(const Medium& medium, const Params& table);
void check_light_contract(const Light& light, const Params& table, const std::string& why);

class Scene {
public:
    // Builds the seen objects from the config's root table, for a film of width x height
    // (the camera's aspect). Reads [camera], [[lights]], [[media]], [[shapes]]; the caller owns
    // the root's other tables and its finish(). Throws ConfigError / FileError.
    static std::unique_ptr<Scene> build(Params& root, int width, int height);

    Camera camera;
    std::vector<std::unique_ptr<Light>> lights;
    std::vector<std::unique_ptr<Medium>> media;
    std::unique_ptr<Surfaces> surfaces;   // null when the scene has no shapes
    Bounds3 bounds;                       // media, surfaces and area lights
    std::vector<std::string> build_log;   // one line per subsystem built or skipped

    bool has_media() const { return !media.empty(); }
    bool uses_openvdb() const { return openvdb_media_ > 0; }
    bool uses_embree() const { return surfaces != nullptr; }

    // Closest hit in (0, tmax) among the surfaces and the area lights (an analytic test per area
    // light: there are few, and a scene without shapes still builds no Embree device). An area
    // light's hit is black (reflectance 0) with `emitter` and `emitted` set; where several area
    // lights meet the ray at the same point (kCoincidentEmitters), `emitted` is their sum.
    bool intersect(const Ray& ray, double tmax, SurfaceHit& hit) const;
    // First real collision among all media in (0, tmax). Overlapping media add their sigma_t; the
    // minimum of independent free flights is exactly the free flight of the sum.
    MediumEvent sample_medium(const Ray& ray, double tmax, Rng& rng) const;
    // Visibility times medium transmittance (unbiased estimate) along ray over (0, tmax). Area
    // lights occlude, except `target`: the light a shadow ray was sent to, which it reaches at tmax,
    // and lights that meet the ray at that same point (coincident emitters).
    double transmittance(const Ray& ray, double tmax, Rng& rng, const Light* target = nullptr) const;
    // The exact optical depth along ray over [0, tmax], summed over the media (each medium's part
    // may stop at OpticalDepthProfile::kEnoughDepth, where 1 - exp(-depth) is 1 in double).
    double optical_depth(const Ray& ray, double tmax) const;
    // Radiance of rays escaping the scene in direction dir (environment lights).
    Rgb escaped_radiance(const Vec3& dir) const;
    Rgb total_light_power() const;

    const std::vector<const Light*>& area_lights() const { return area_lights_; }

    // Builds the lights' emission guides (scene/emission_guides.h) on the first call, from any
    // thread; later calls return at once. Photon tracers call it: a scene rendered without photons
    // traces no guide rays. Returns one line per guided light.
    const std::vector<std::string>& prepare_photon_emission() const;

private:
    int openvdb_media_ = 0;
    // Lazily built state of the photon emission (the guides live in the lights).
    mutable std::once_flag emission_guides_once_;
    mutable std::vector<std::string> emission_guides_log_;
    std::vector<const Light*> area_lights_;   // the lights that are geometry (non-empty bounds())
};

}  // namespace vpm
