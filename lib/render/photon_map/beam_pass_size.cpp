#include "render/photon_map/beam_pass_size.h"

#include <algorithm>
#include <cmath>

namespace vpm {

namespace {

// The exponent g of y ~ x^g from two readings, within [0, 1]: 0 where either is not positive.
double growth(double y_small, double y_large, double x_small, double x_large) {
    if (!(y_small > 0.0) || !(y_large > 0.0) || !(x_large > x_small)) return 0.0;
    return std::clamp(std::log(y_large / y_small) / std::log(x_large / x_small), 0.0, 1.0);
}

double per(double a, double b) { return b > 0.0 ? a / b : 0.0; }

// The camera side's operations other than the beams' queries, per probe sample.
double other_camera_units(const BeamPilotCounts& c, const WorkUnits& w) {
    return per(c.camera.queries * w.query + c.camera.rays * w.ray + c.camera.lookups * w.lookup +
                   c.camera.steps * w.step + c.camera.density_lookups * w.density_lookup + c.camera.cells * w.cell,
               c.samples);
}

// Halves N and doubles S while the photon side (map) holds more than half of the pass and the pair
// still fits: the error of a pass falls with both photons and camera samples, and neither side gains
// from more than its share of the work (the photon map's plan balances them by measured variances;
// the beams have no variance pilot, so the work is split).
template <class Fits>
void balance_camera_share(const BeamPassInputs& in, const Fits& fits, int64_t& n, int& s) {
    const int64_t floor_n = std::max<int64_t>(1, int64_t(in.small.photons));
    for (;;) {
        double map = 0.0;
        const double pass = beam_pass_units(in, double(n), double(s), &map);
        if (!(2.0 * map > pass) || n / 2 < floor_n || s * 2 > in.spp || !fits(double(n / 2), double(s * 2))) return;
        n /= 2;
        s *= 2;
    }
}

}  // namespace

BeamWorkUnits beam_work_units() {
    // Fitted to 1- and 2-thread runs of configs/glass_sphere_fog.toml with photon_beams (balloon at
    // 50,000 and 100,000 photons, sample_point at 12,500 and 25,000), each phase's share of the
    // user CPU time over the counts the run record gives (a loaded machine: 120-210 per crossing
    // test, 110-184 per width test; the upper half kept, so a pass errs short). docs/photon_beams.md,
    // "Time limits".
    BeamWorkUnits b;
    b.query = 2000.0;
    b.test = 150.0;
    b.width_test = 150.0;
    b.beam = 150.0;
    b.piece = 300.0;
    return b;
}

BeamWorkUnits point_beam_work_units(double radius_query) {
    // The point-beam gather's measured costs (docs/beam_estimate.md): a segment query's set-up, each
    // disc it crosses, a BVH item; the upper side kept, so a pass errs short.
    BeamWorkUnits b;
    b.query = 20000.0;
    b.test = 250.0;
    b.width_test = 0.0;
    b.beam = radius_query;
    b.piece = 600.0;
    return b;
}

double beam_pilot_units(const BeamPilotCounts& c, const WorkUnits& w, const BeamWorkUnits& b) {
    return c.photons * w.path + c.collisions * w.collision + c.surface_stored * w.stored + c.beams * b.beam +
           c.pieces * b.piece + c.width_tests * b.width_test +
           c.samples * other_camera_units(c, w) + c.beam_queries * b.query + c.beam_tests * b.test;
}

double beam_pass_units(const BeamPassInputs& in, double n, double s, double* map_units) {
    const BeamPilotCounts& L = in.large;
    const BeamPilotCounts& S = in.small;
    const WorkUnits& w = in.units;
    const BeamWorkUnits& b = in.beam_units;
    const double scale = n / std::max(L.photons, 1.0);
    // Per photon: the walk, its collisions and stored surface photons, its beams (linear in N).
    const double beams = per(L.beams, L.photons) * n;
    double map = n * (w.path + per(L.collisions, L.photons) * w.collision + per(L.surface_stored, L.photons) * w.stored) +
                 beams * b.beam;
    // Pieces per beam and width tests per beam grow with the beams' density.
    const double pieces_growth = growth(per(S.pieces, S.beams), per(L.pieces, L.beams), S.photons, L.photons);
    map += beams * per(L.pieces, L.beams) * std::pow(scale, pieces_growth) * b.piece;
    const double width_growth =
        std::max(in.least_width_growth, growth(per(S.width_tests, S.beams), per(L.width_tests, L.beams), S.photons, L.photons));
    map += beams * per(L.width_tests, L.beams) * std::pow(scale, width_growth) * b.width_test;
    const double test_growth =
        std::max(in.least_test_growth, growth(per(S.beam_tests, S.beam_queries), per(L.beam_tests, L.beam_queries), S.photons, L.photons));
    const double sample = other_camera_units(L, w) +
                          per(L.beam_queries, L.samples) * (b.query + per(L.beam_tests, L.beam_queries) * std::pow(scale, test_growth) * b.test);
    if (map_units) *map_units = map;
    return map + in.pixels * s * sample;
}

BeamPassSize size_beam_pass(const BeamPassInputs& in) {
    BeamPassSize out;
    const BeamPilotCounts& L = in.large;
    const BeamPilotCounts& S = in.small;
    out.test_growth =
        std::max(in.least_test_growth, growth(per(S.beam_tests, S.beam_queries), per(L.beam_tests, L.beam_queries), S.photons, L.photons));
    out.width_growth =
        std::max(in.least_width_growth, growth(per(S.width_tests, S.beams), per(L.width_tests, L.beams), S.photons, L.photons));
    out.pilot_units = beam_pilot_units(S, in.units, in.beam_units) + beam_pilot_units(L, in.units, in.beam_units);
    out.pass_budget = std::max(0.0, in.budget - out.pilot_units) / kBeamPlanMinPasses;
    auto fits = [&](double n, double s) { return beam_pass_units(in, n, s) <= out.pass_budget; };
    int64_t n = in.count;
    int s = in.size_samples ? std::min(in.spp, std::max(1, in.least_spp)) : in.spp;
    if (in.size_photons) {
        // Halve N until the pass fits, down to the small pilot's photons (at least 1).
        const int64_t floor_n = std::max<int64_t>(1, int64_t(S.photons));
        while (n > floor_n && !fits(double(n), double(s))) n = std::max(floor_n, n / 2);
    }
    if (in.size_samples)   // the least S does not fit even at the fewest photons: fewer samples
        while (s > 1 && !fits(double(n), double(s))) s /= 2;
    if (in.size_samples)
        while (s * 2 <= in.spp && fits(double(n), double(s * 2))) s *= 2;
    if (in.balance_camera && in.size_photons && in.size_samples) balance_camera_share(in, fits, n, s);
    out.count = n;
    out.spp = s;
    out.pass_units = beam_pass_units(in, double(n), double(s), &out.map_units);
    out.fits = out.pass_units <= out.pass_budget;
    return out;
}

}  // namespace vpm
