// The ball-extinction normalisation (photons.extinction = "ball", issue 20): error and cost of each
// quadrature of the mean sigma_t over a kNN ball inside a grid medium, against a 16384-point
// reference, and how often the ball sits inside one voxel cell (where the centre value is exact).
// Not a Google Benchmark: one table. usage: bench_ball_extinction [balls=2000] [seed=1]
//
// Balls: centres drawn in the medium's box with probability proportional to sigma_t (rejection,
// where photons and camera queries are), radius a fixed number of voxels, the whole ball inside
// the box. Errors are relative to the reference mean, per ball: bias = their mean, rms = their RMS.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/progress.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "io/vdb_io.h"
#include "photon/ball_extinction.h"
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
    for (const Case c : {Case{"blob", 1.0 / 32}, Case{"plume", 1.0 / 64}}) {
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
    return 0;
}
