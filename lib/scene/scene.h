#pragma once
// A scene built from a config: camera, lights, media, surfaces, and the run settings.
// Only what the config uses is built: no Embree device without [[shapes]], no OpenVDB grid
// without a grid medium. `build_log` says what was built; sidecars copy it.
//
// Top-level tables: [render] [camera] [photons] [[lights]] [[media]] [[shapes]].
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/rng.h"
#include "scene/camera.h"
#include "scene/light.h"
#include "scene/medium.h"
#include "scene/params.h"
#include "scene/surfaces.h"

namespace vpm {

// [render]
struct RenderSettings {
    int width = 256;
    int height = 256;
    int spp = 16;
    uint64_t seed = 1;
    int threads = 0;                       // 0: all cores
    std::string output = "out/render.exr"; // relative to the working directory
    std::string integrator = "path";       // "path" (reference) | "photon_map"
    int max_depth = -1;                    // scattering events per path; -1: unlimited (unbiased)
    int rr_depth = 5;                      // Russian roulette from this depth on
    double exposure = 0.0;                 // PNG preview only: pixel * 2^exposure
};

// [photons]
struct PhotonSettings {
    int64_t count = 100000;            // photons emitted
    int k = 32;                        // nearest neighbours per estimate
    std::string estimator = "corrected";
    std::string direct = "nee";        // "nee": single scattering by NEE | "photon_map"
    double max_radius = 0.0;           // 0: unbounded kNN search
    int max_bounces = 1000;            // path-length cap (collisions per photon path)
    double memory_budget_fraction = 0.5;
    // Surfaces: false (default) reads indirect light on surfaces from the surface photon map
    // (its estimator's bias stays visible); true skips the surface map and continues camera paths
    // through surfaces with a diffuse bounce until the first medium collision (final gather).
    bool final_gather = false;
    // Extinction the volume estimate is divided by: "ball" = mean sigma_t over the kNN ball,
    // "point" = sigma_t at the collision (DESIGN.md's formula); see photon_map_integrator.h.
    std::string extinction = "ball";
    // Dense media: the kNN radius is bounded by this many mean free paths at the query, 1/sigma_t(x)
    // each; where fewer than k photons lie within it the camera path continues instead
    // (photon/bounded_radius.h). 0: no bound.
    double max_radius_mfp = 2.0;
    // Photons per light: "importance" (a pilot finds where each light's photons meet the camera's
    // view) | "power" (proportional to power); photon/photon_allocation.h.
    std::string allocation = "importance";
};

// A real collision sampled along a ray among all media.
struct MediumEvent {
    double t = kInfinity;
    const Medium* medium = nullptr;
    explicit operator bool() const { return medium != nullptr; }
};

class Scene {
public:
    // Builds everything from a loaded document; throws ConfigError / FileError.
    static std::unique_ptr<Scene> build(std::shared_ptr<const ConfigDocument> doc);
    static std::unique_ptr<Scene> load(const std::string& path, const std::vector<std::string>& overrides = {});

    RenderSettings render;
    PhotonSettings photons;
    Camera camera;
    std::vector<std::unique_ptr<Light>> lights;
    std::vector<std::unique_ptr<Medium>> media;
    std::unique_ptr<Surfaces> surfaces;   // null when the scene has no shapes
    Bounds3 bounds;                       // media and surfaces
    toml::table resolved;                 // the full config with every default filled in
    std::vector<std::string> build_log;   // one line per subsystem built or skipped
    std::string source_file;

    bool has_media() const { return !media.empty(); }
    bool uses_openvdb() const { return openvdb_media_ > 0; }
    bool uses_embree() const { return surfaces != nullptr; }

    // Closest surface hit in (0, tmax).
    bool intersect(const Ray& ray, double tmax, SurfaceHit& hit) const {
        return surfaces && surfaces->intersect(ray, tmax, hit);
    }
    // First real collision among all media in (0, tmax). Overlapping media add their sigma_t; the
    // minimum of independent free flights is exactly the free flight of the sum.
    MediumEvent sample_medium(const Ray& ray, double tmax, Rng& rng) const;
    // Visibility times medium transmittance (unbiased estimate) along ray over (0, tmax).
    double transmittance(const Ray& ray, double tmax, Rng& rng) const;
    // Radiance of rays escaping the scene in direction dir (environment lights).
    Rgb escaped_radiance(const Vec3& dir) const;
    Rgb total_light_power() const;
    std::string resolved_toml() const { return to_toml_string(resolved); }

private:
    int openvdb_media_ = 0;
};

}  // namespace vpm
