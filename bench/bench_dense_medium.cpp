// Dense homogeneous sphere: photon map against the path tracer as sigma_t grows (issue 12).
// Not a Google Benchmark: one table of image means with standard errors, plus diagnostics of the
// photon-map estimate (kNN radius in mean free paths, estimate cases).
//
//   bench_dense_medium [--photons N] [--size S] [--repeats R] [--pm-spp P] [--pt-spp Q]
//                      [--scales 1e2,1e3,...] [--set KEY=VALUE]...
//
// Each repeat traces an independent photon map (stream offset r) and renders it; the path tracer
// renders R independent images. Means are of the green channel over the image.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "bench_common.h"
#include "photon/map/photon_map.h"
#include "photon/trace/photon_tracer.h"
#include "render/path/path_tracer.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/run/render_loop.h"
#include "render/run/run_config.h"

using namespace vpm;

namespace {

struct Sample {
    double sum = 0, sum2 = 0;
    int n = 0;
    void add(double v) { sum += v; sum2 += v * v; ++n; }
    double mean() const { return sum / n; }
    double se() const { return n > 1 ? std::sqrt(std::max(0.0, sum2 / n - mean() * mean()) / (n - 1)) : 0.0; }
};

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double image_mean(const RunConfig& config, const Integrator& integrator, uint64_t seed, int spp, uint64_t stream) {
    const Scene& scene = *config.scene;
    RenderOptions o;
    o.width = config.render.width;
    o.height = config.render.height;
    o.spp = spp;
    o.seed = seed;
    o.progress = false;
    o.stream_offset = stream;
    RenderStats stats;
    const Image image = render_image(scene.camera, integrator, o, stats);
    double m = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) m += image.at(x, y)[1];
    return m / double(image.width * image.height);
}

}  // namespace

int main(int argc, char** argv) {
    uint64_t photons = 1000000;
    int size = 32, repeats = 4, pm_spp = 4, pt_spp = 256;
    std::vector<double> scales = {1e2, 1e3, 1e4, 1e5};
    std::vector<std::string> sets;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i], v = argv[i + 1];
        if (a == "--photons") photons = uint64_t(std::stod(v));
        else if (a == "--size") size = std::stoi(v);
        else if (a == "--repeats") repeats = std::stoi(v);
        else if (a == "--pm-spp") pm_spp = std::stoi(v);
        else if (a == "--pt-spp") pt_spp = std::stoi(v);
        else if (a == "--set") sets.push_back(v);
        else if (a == "--scales") {
            scales.clear();
            std::stringstream s(v);
            std::string item;
            while (std::getline(s, item, ',')) scales.push_back(std::stod(item));
        } else {
            std::fprintf(stderr, "unknown option %s\n", a.c_str());
            return 2;
        }
    }
    std::printf("| sigma_t_scale | PM mean +- SE | PT mean +- SE | PM/PT - 1 | (PM-PT)/SE | trace s | render s | "
                "PT render s | r_k/mfp median (unbounded) | continued per camera sample |\n"
                "|---:|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
    for (double scale : scales) {
        std::vector<std::string> o = {"render.width=" + std::to_string(size), "render.height=" + std::to_string(size),
                                      "media.0.sigma_t_scale=" + std::to_string(scale),
                                      "photons.count=" + std::to_string(photons)};
        o.insert(o.end(), sets.begin(), sets.end());
        o.push_back("render.integrator=photon_map");
        const RunConfig config = RunConfig::load(bench::config_path("homogeneous.toml"), o);
        const Scene* scene = config.scene.get();
        const PhotonMapSettings& ps = photon_map_settings(config);
        Sample pm, pt;
        double trace_s = 0, render_s = 0;
        EstimatorStats cases;
        uint64_t continued = 0;
        std::vector<double> radii;
        for (int r = 0; r < repeats; ++r) {
            PhotonTraceSettings ts;
            ts.count = photons;
            ts.seed = config.render.seed;
            ts.stream_offset = uint64_t(r);
            ts.store_direct = ps.direct == DirectLighting::photon_map;
            ts.progress = false;
            double t0 = now();
            const PhotonMap map(trace_photons(*scene, ts).photons);
            trace_s += now() - t0;
            PhotonMapIntegrator integrator(*scene, ps, map);
            t0 = now();
            pm.add(image_mean(config, integrator, 7 + uint64_t(r), pm_spp, uint64_t(r)));
            render_s += now() - t0;
            cases.merge(integrator.stats());
            continued += integrator.continued_paths();
            if (r == 0) {   // kNN radius at camera collisions, in mean free paths
                const double sigma_t = scene->media[0]->sigma_t(Vec3::Zero());
                GatherBuffers buf;
                Rng rng(99, 1);
                for (int i = 0; i < 400; ++i) {
                    const Ray ray = scene->camera.generate_ray(rng.uniform() * size, rng.uniform() * size);
                    const MediumEvent ev = scene->sample_medium(ray, kInfinity, rng);
                    if (!ev) continue;
                    const auto s = estimate_in_scattering(map, ray.at(ev.t), -ray.dir, 0.5, ps.estimator,
                                                          size_t(ps.k), kInfinity, buf);
                    radii.push_back(s.radius * sigma_t);
                }
            }
        }
        const PathTracer tracer(*scene, ps.walk);
        double pt_s = now();
        for (int r = 0; r < repeats; ++r) pt.add(image_mean(config, tracer, 1000 + uint64_t(r), pt_spp / repeats, 0));
        pt_s = (now() - pt_s) / repeats;
        std::sort(radii.begin(), radii.end());
        const double se = std::sqrt(pm.se() * pm.se() + pt.se() * pt.se());
        const double samples = double(repeats) * pm_spp * size * size;
        std::printf("| %g | %.5g +- %.2g | %.5g +- %.2g | %+.3f | %+.1f | %.2f | %.3f | %.3f | %.3g | %.3f |\n", scale,
                    pm.mean(), pm.se(), pt.mean(), pt.se(), pm.mean() / pt.mean() - 1.0, (pm.mean() - pt.mean()) / se,
                    trace_s / repeats, render_s / repeats, pt_s, radii.empty() ? 0.0 : radii[radii.size() / 2],
                    double(continued) / samples);
        std::fflush(stdout);
    }
    return 0;
}
