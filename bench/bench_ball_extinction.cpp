// The ball-extinction normalisation (photons.extinction = "ball", issue 20): error and cost of each
// quadrature of the mean sigma_t over a kNN ball inside a grid medium, against a 16384-point
// reference, and how often the ball sits inside one voxel cell (where the centre value is exact).
// Not a Google Benchmark: one table. usage: bench_ball_extinction [balls=2000] [seed=1]
//
// Balls: centres drawn in the medium's box with probability proportional to sigma_t (rejection,
// where photons and camera queries are), radius a fixed number of voxels, the whole ball inside
// the box. Errors are relative to the reference mean, per ball: bias = their mean, rms = their RMS.
// usage: bench_ball_extinction [balls=2000] [seed=1] [wide: the second table only]
//
// Second table (issue 20 item 3): wide balls (radius 1/4 to 1 of the box, where BallExtinction
// takes the lattice; centres in proportion to sigma_t), the clipped 4096-point Halton rule against
// the mass lattice (photon/estimate/mass_lattice.h), both against a 64^3-point stratified quadrature.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/progress.h"
#include "core/sampling/rng.h"
#include "core/sampling/sampling.h"
#include "io/vdb_io.h"
#include "photon/estimate/ball_extinction.h"
#include "photon/estimate/mass_lattice.h"
#include "scene/media/grid_medium.h"

using namespace vpm;

namespace {

struct Ball {
    Vec3 x;
    double r;
    double reference;
};

std::vector<Ball> make_balls(const Medium& m, double r, size_t n, uint64_t seed) {
    Rng rng(seed, 0);
    const Bounds3 b = m.bounds();
    double peak = 0.0;
    for (int i = 0; i < 100000; ++i)
        peak = std::max(peak, m.sigma_t(b.lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()).cwiseProduct(b.hi - b.lo)));
    std::vector<Ball> balls;
    while (balls.size() < n) {
        const Vec3 x = b.lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()).cwiseProduct(b.hi - b.lo);
        if (!b.contains(x - Vec3::Constant(r)) || !b.contains(x + Vec3::Constant(r))) continue;
        if (rng.uniform() * peak > m.sigma_t(x)) continue;
        double sum = 0.0;
        const int q = 16384;   // stratified in the unit cube, warped into the ball
        for (int i = 0; i < q; ++i) {
            const double u = (i % 32 + rng.uniform()) / 32, v = ((i / 32) % 32 + rng.uniform()) / 32, w = (i / 1024 + rng.uniform()) / 16;
            sum += m.sigma_t(x + r * sample_uniform_ball(u, v, w));
        }
        balls.push_back({x, r, sum / q});
    }
    return balls;
}

double halton(uint32_t i, uint32_t base) {
    double f = 1.0, r = 0.0;
    for (; i > 0; i /= base) {
        f /= base;
        r += f * (i % base);
    }
    return r;
}

// The clipped rule of ball_extinction.cpp: 4096 Halton points over the ball's cube within the box.
struct Clipped {
    std::vector<Vec3> points;
    Clipped() {
        for (uint32_t i = 1; i <= 4096; ++i) points.push_back(Vec3(halton(i, 2), halton(i, 3), halton(i, 5)));
    }
    double integral(const Medium& m, const Vec3& x, double r) const {
        const Bounds3 b = m.bounds();
        const Vec3 lo = b.lo.cwiseMax(x - Vec3::Constant(r)), hi = b.hi.cwiseMin(x + Vec3::Constant(r));
        if ((hi - lo).minCoeff() <= 0.0) return 0.0;
        double sum = 0.0;
        for (const Vec3& h : points) {
            const Vec3 p = lo + h.cwiseProduct(hi - lo);
            if ((p - x).squaredNorm() <= r * r) sum += m.sigma_t(p);
        }
        const Vec3 e = hi - lo;
        return sum * e[0] * e[1] * e[2] / double(points.size());
    }
};

double stratified(const Medium& m, const Vec3& x, double r, Rng& rng) {
    const Bounds3 b = m.bounds();
    const Vec3 lo = b.lo.cwiseMax(x - Vec3::Constant(r)), hi = b.hi.cwiseMin(x + Vec3::Constant(r));
    if ((hi - lo).minCoeff() <= 0.0) return 0.0;
    const int n = 64;
    double sum = 0.0;
    for (int i = 0; i < n * n * n; ++i) {
        const Vec3 u((i % n + rng.uniform()) / n, ((i / n) % n + rng.uniform()) / n, (i / (n * n) + rng.uniform()) / n);
        const Vec3 p = lo + u.cwiseProduct(hi - lo);
        if ((p - x).squaredNorm() <= r * r) sum += m.sigma_t(p);
    }
    const Vec3 e = hi - lo;
    return sum * e[0] * e[1] * e[2] / double(n * n * n);
}

void wide_balls(const char* name, const Medium& m, size_t n, uint64_t seed) {
    Rng rng(seed, 1);
    const Bounds3 b = m.bounds();
    const Vec3 size = b.hi - b.lo;
    const Timer build;
    const MassLattice lattice(m, b);
    const double build_ms = build.seconds() * 1e3;
    double peak = 0.0;
    for (int i = 0; i < 20000; ++i) peak = std::max(peak, m.sigma_t(b.lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()).cwiseProduct(size)));
    std::vector<Ball> balls;
    while (balls.size() < n) {
        const Vec3 x = b.lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()).cwiseProduct(size);
        if (rng.uniform() * peak > m.sigma_t(x)) continue;
        const double r = size.minCoeff() * (0.25 + 0.75 * rng.uniform());
        if (!lattice.wide_enough(r)) continue;
        balls.push_back({x, r, stratified(m, x, r, rng)});
    }
    const Clipped clipped;
    double sink = 0.0;
    const Timer tc;
    for (const Ball& ball : balls) sink += clipped.integral(m, ball.x, ball.r);
    const double ns_clipped = tc.seconds() / double(n) * 1e9;
    const int reps = 100;
    const Timer tl;
    for (int rep = 0; rep < reps; ++rep)
        for (const Ball& ball : balls) sink += lattice.ball_integral(ball.x, ball.r);
    const double ns_lattice = tl.seconds() / double(n * reps) * 1e9;
    double bias[2] = {0, 0}, sq[2] = {0, 0}, worst[2] = {0, 0};
    uint64_t cells = 0;
    for (const Ball& ball : balls) {
        const double e[2] = {clipped.integral(m, ball.x, ball.r) / ball.reference - 1.0,
                             lattice.ball_integral(ball.x, ball.r, &cells) / ball.reference - 1.0};
        for (int i = 0; i < 2; ++i) {
            bias[i] += e[i] / double(n);
            sq[i] += e[i] * e[i] / double(n);
            worst[i] = std::max(worst[i], std::abs(e[i]));
        }
    }
    std::printf("| %s | clipped 4096 | %+.4f | %.4f | %.4f | %.0f | - |%s\n", name, bias[0], std::sqrt(sq[0]), worst[0], ns_clipped,
                sink < 0 ? " " : "");
    std::printf("| %s | mass lattice 16^3 | %+.4f | %.4f | %.4f | %.0f | %.0f cells and columns per ball, build %.1f ms |\n", name, bias[1],
                std::sqrt(sq[1]), worst[1], ns_lattice, double(cells) / double(n), build_ms);
}

}  // namespace

int main(int argc, char** argv) {
    const size_t n = argc > 1 ? size_t(std::atof(argv[1])) : 2000;
    const uint64_t seed = argc > 2 ? uint64_t(std::atoll(argv[2])) : 1;
    const std::string media = std::string(VPM_SOURCE_DIR) + "/media/";
    struct Case {
        const char* name;
        double voxel;
    };
    std::printf("| medium | radius (voxels) | rule | bias | rms error | ns per ball | centre exact |\n|---|---|---|---|---|---|---|\n");
    const bool wide_only = argc > 3 && std::string(argv[3]) == "wide";
    for (const Case c : {Case{"blob", 1.0 / 32}, Case{"plume", 1.0 / 64}}) {
        if (wide_only) break;
        const GridMedium m(load_vdb_density(media + c.name + ".vdb"), 1.0, Rgb::Constant(0.9), 0.0);
        for (double rv : {0.3, 1.0, 3.0, 10.0}) {
            const std::vector<Ball> balls = make_balls(m, rv * c.voxel, n, seed);
            size_t exact = 0;
            double unused = 0.0;
            for (const Ball& b : balls) exact += m.ball_integral(b.x, b.r, unused);
            const struct {
                const char* name;
                BallRule rule;
                bool shortcut;
            } rules[] = {{"halton32", BallRule::halton32, false}, {"degree5", BallRule::degree5, false},
                         {"degree3", BallRule::degree3, false},   {"centre (point)", BallRule::centre, false},
                         {"halton32 + cell shortcut", BallRule::halton32, true}, {"degree5 + cell shortcut", BallRule::degree5, true}};
            for (const auto& rule : rules) {
                double bias = 0.0, sq = 0.0, sink = 0.0;
                const int reps = 20;
                const Timer t;
                for (int rep = 0; rep < reps; ++rep)
                    for (const Ball& b : balls) {
                        const bool cut = rule.shortcut && m.ball_integral(b.x, b.r, unused);
                        sink += ball_mean_by_rule(m, b.x, b.r, cut ? BallRule::centre : rule.rule);
                    }
                const double ns = t.seconds() / double(reps * balls.size()) * 1e9;
                for (const Ball& b : balls) {
                    const bool cut = rule.shortcut && m.ball_integral(b.x, b.r, unused);
                    const double e = ball_mean_by_rule(m, b.x, b.r, cut ? BallRule::centre : rule.rule) / b.reference - 1.0;
                    bias += e;
                    sq += e * e;
                }
                std::printf("| %s | %g | %s | %+.4f | %.4f | %.0f | %.2f |%s\n", c.name, rv, rule.name, bias / double(balls.size()),
                            std::sqrt(sq / double(balls.size())), ns, double(exact) / double(balls.size()), sink < 0 ? " " : "");
            }
        }
    }
    std::printf("\n| medium | rule (wide balls crossing the box) | bias | rms error | worst | ns per ball | |\n|---|---|---|---|---|---|---|\n");
    for (const Case c : {Case{"blob", 1.0 / 32}, Case{"plume", 1.0 / 64}}) {
        const GridMedium m(load_vdb_density(media + c.name + ".vdb"), 1.0, Rgb::Constant(0.9), 0.0);
        wide_balls(c.name, m, std::min<size_t>(n, 200), seed);
    }
    return 0;
}
