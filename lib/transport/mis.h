#pragma once
// Multiple importance sampling of emission (Veach 1997, ch. 9: the power heuristic, beta = 2)
// between the two ways a walk finds light: next-event estimation (one sample per light at every
// vertex, direct_light.h) and the direction the walk samples anyway (Henyey-Greenstein phase in
// media, the cosine-weighted bounce on Lambertian surfaces) when it meets an area light or escapes
// to an environment light.
//
// Both pdfs are solid-angle pdfs of the direction at the vertex. In media this follows the
// reasoning of pbrt-v4's VolPathIntegrator (Pharr, Jakob & Humphreys, Physically Based Rendering,
// 4th ed., sec. 14.2.3, its rescaled path probabilities r_u and r_l): the transmittance between the
// vertex and the light multiplies both strategies identically (NEE by its ratio-tracking estimate,
// the walk by the probability that its free flight reaches the light), and since vpm's sigma_t is
// grey the majorant factors cancel too, leaving only the directional pdfs in the weights. Weights
// that sum to one for every direction keep the sum unbiased.
//
// render.mis = false keeps light sampling only: NEE weighs 1 and emission met after a vertex
// counts 0; the camera's own view (depth 0) always sees the lights.
#include <cmath>

#include "core/math.h"
#include "scene/scene.h"

namespace vpm {

// The power heuristic weight of strategy f against g, both solid-angle pdfs, f > 0.
inline double power_heuristic(double f, double g) {
    if (std::isinf(f)) return 1.0;
    const double f2 = f * f;
    return f2 / (f2 + g * g);
}

// Weight of a light sample with solid-angle pdf light_pdf when the walk would take the same
// direction with scatter_pdf. Delta lights (pdf 0) cannot be found by the walk: weight 1.
inline double light_sample_weight(bool mis, double light_pdf, double scatter_pdf) {
    if (!mis || light_pdf == 0.0) return 1.0;
    return power_heuristic(light_pdf, scatter_pdf);
}

// How the emission the walk meets next is weighed: where the walk left from and the solid-angle pdf
// of the direction it took there.
struct EmissionWeighting {
    enum class Mode {
        full,         // the camera ray: emission seen directly counts 1
        mis,          // after a vertex whose NEE was MIS-weighted: power heuristic
        light_only,   // after a vertex whose NEE weighed 1: emission counts 0
    };
    Mode mode = Mode::full;
    Vec3 from = Vec3::Zero();
    double pdf = 0.0;

    static EmissionWeighting camera() { return {}; }
    // After scattering at x into a direction sampled with solid-angle pdf `pdf`, with NEE there
    // weighted when `mis` (else weighing 1).
    static EmissionWeighting after(bool mis, const Vec3& x, double pdf) {
        return {mis ? Mode::mis : Mode::light_only, x, pdf};
    }
    // Weight of emission from `light` met along direction dir.
    double weight(const Light& light, const Vec3& dir) const {
        if (mode == Mode::full) return 1.0;
        if (mode == Mode::light_only) return 0.0;
        const double light_pdf = light.pdf_incident(from, dir);
        if (light_pdf == 0.0) return 1.0;   // light sampling cannot reach this direction
        if (std::isinf(light_pdf)) return 0.0;
        return power_heuristic(pdf, light_pdf);
    }
};

// Radiance of an area light hit (hit.emitter set) reached along `ray`, weighted; coincident emitters
// each with their own light-sampling pdf.
Rgb emitted_radiance(const Scene& scene, const Ray& ray, const SurfaceHit& hit, const EmissionWeighting& w);
// Radiance of the environment lights for a ray escaping along dir, weighted per light.
Rgb escaped_radiance(const Scene& scene, const Vec3& dir, const EmissionWeighting& w);

}  // namespace vpm
