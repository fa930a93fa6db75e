// `vpm make-media --out DIR`: writes plume.vdb, box.vdb, blob.vdb and sphere.vdb, each with one
// float grid "density" in [0, 1]. Fully deterministic (own hash-based value noise, no RNG state).
#include "cmd_make_media.h"
#include "arguments.h"
#include "command.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/error.h"
#include "core/sampling/rng.h"
#include "core/density_grid.h"
#include "render/run/staged_file.h"
#include "io/vdb_io.h"

namespace vpm {

namespace {

// Value noise on the integer lattice, smooth (quintic) interpolation, values in [0, 1].
double lattice(int x, int y, int z, uint64_t seed) {
    const uint64_t h = mix64(seed ^ mix64(uint64_t(uint32_t(x)) ^ mix64(uint64_t(uint32_t(y)) << 1 ^
                                                                          mix64(uint64_t(uint32_t(z)) << 2))));
    return double(h >> 11) * 0x1.0p-53;
}
double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
double value_noise(double x, double y, double z, uint64_t seed) {
    const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
    const int ix = int(fx), iy = int(fy), iz = int(fz);
    const double u = fade(x - fx), v = fade(y - fy), w = fade(z - fz);
    double r = 0;
    for (int c = 0; c < 8; ++c) {
        const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
        r += (dx ? u : 1 - u) * (dy ? v : 1 - v) * (dz ? w : 1 - w) * lattice(ix + dx, iy + dy, iz + dz, seed);
    }
    return r;
}
// Fractal sum, normalised to [0, 1].
double fbm(double x, double y, double z, int octaves, uint64_t seed) {
    double sum = 0, amp = 1, norm = 0;
    for (int o = 0; o < octaves; ++o) {
        sum += amp * value_noise(x, y, z, seed + uint64_t(o));
        norm += amp;
        amp *= 0.5;
        x *= 2.03;
        y *= 2.03;
        z *= 2.03;
    }
    return sum / norm;
}
double smoothstep(double a, double b, double x) {
    const double t = std::min(std::max((x - a) / (b - a), 0.0), 1.0);
    return t * t * (3 - 2 * t);
}

// Samples f(world position) at voxel centres of an nx*ny*nz grid with index-to-world `xf`.
DensityGrid sample_grid(const Vec3i& dims, const Eigen::Affine3d& xf, double quantum,
                        const std::function<double(const Vec3&)>& f) {
    std::vector<float> values(static_cast<size_t>(dims.prod()));
    for (int z = 0; z < dims.z(); ++z)
        for (int y = 0; y < dims.y(); ++y)
            for (int x = 0; x < dims.x(); ++x) {
                double v = std::min(std::max(f(xf * Vec3(x, y, z)), 0.0), 1.0);
                // Quantising to a fixed step makes the files compress well; below one step is 0.
                if (quantum > 0) v = std::round(v / quantum) * quantum;
                values[(size_t(z) * dims.y() + y) * dims.x() + x] = static_cast<float>(v);
            }
    DensityGrid g = DensityGrid::from_dense(Vec3i::Zero(), dims, values);
    g.set_index_to_world(xf);
    return g;
}

Eigen::Affine3d centred(const Vec3i& dims, double voxel, double y_base) {
    // Voxel (i, j, k) centre at world ((i - (nx-1)/2) h, y_base + j h, (k - (nz-1)/2) h).
    Eigen::Affine3d m = Eigen::Affine3d::Identity();
    m.translate(Vec3(-(dims.x() - 1) * 0.5 * voxel, y_base, -(dims.z() - 1) * 0.5 * voxel));
    m.scale(voxel);
    return m;
}

// A rising smoke column, 1.5 world units tall on y = 0: radius grows with height, the axis
// meanders, and fBm turbulence (advected upwards) carves the edges; fades in at the bottom and
// out at the top.
double plume(const Vec3& p) {
    const double H = 1.5;
    const double y = p.y() / H;   // 0 .. 1
    if (y <= 0.0 || y >= 1.0) return 0.0;
    const double cx = 0.08 * std::sin(5.0 * y + 0.3) + 0.05 * (fbm(0.5, 3.0 * y, 0.5, 2, 11) - 0.5);
    const double cz = 0.06 * std::cos(4.0 * y + 1.1) + 0.05 * (fbm(1.5, 3.0 * y, 2.5, 2, 12) - 0.5);
    const double r = 0.10 + 0.22 * y;
    const double dist = std::hypot(p.x() - cx, p.z() - cz) / r;
    const double turb = fbm(4.0 * p.x(), 4.0 * p.y() - 1.7, 4.0 * p.z(), 4, 42);   // ~[0.2, 0.8]
    const double shape = 1.0 - dist + 0.9 * (turb - 0.5);
    const double body = smoothstep(0.0, 0.35, shape);
    const double vertical = smoothstep(0.0, 0.08, y) * (1.0 - smoothstep(0.7, 1.0, y));
    const double wisps = 0.55 + 0.45 * fbm(9.0 * p.x(), 9.0 * p.y(), 9.0 * p.z(), 3, 77);
    return body * vertical * wisps * (1.0 - 0.4 * y);
}

void write_one(const std::filesystem::path& dir, const std::string& file, const DensityGrid& g) {
    const std::string path = (dir / file).string();
    write_vdb_density(path, "density", g);
    std::cout << path << ": " << std::filesystem::file_size(path) << " bytes, max density " << g.max_density()
              << ", " << g.dense_block_count() << " dense 8^3 blocks\n";
}

}  // namespace

int run_make_media(int argc, char** argv) {
    CLI::App app{"Write the procedural media (plume, box, blob, sphere) as OpenVDB files", "vpm make-media"};
    std::string out;
    // Required: a default folder would rewrite ./media of whatever the working directory is.
    app.add_option("--out", out, "Output folder (created if missing; existing files of the same names are replaced), "
                                 "e.g. --out media")->required();
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;
    {
        prepare_output_folder(out);
        // Plume: 64 x 96 x 64 voxels of 1/64, 1.5 tall, base at y = 0 (voxel row 0 is empty).
        {
            const Vec3i dims(64, 96, 64);
            const double h = 1.5 / 96;
            write_one(out, "plume.vdb", sample_grid(dims, centred(dims, h, 0.0), 1.0 / 256, plume));
        }
        // Box: density 1 in a 32^3 block of voxels of 1/32 (a unit cube centred on the origin).
        {
            const Vec3i dims(32, 32, 32);
            const double h = 1.0 / 32;
            write_one(out, "box.vdb", sample_grid(dims, centred(dims, h, -15.5 * h), 0.0,
                                                  [](const Vec3&) { return 1.0; }));
        }
        // Blob: Gaussian, peak 1, standard deviation 0.2, cut at 1e-3, 48^3 voxels of 1/32.
        {
            const Vec3i dims(48, 48, 48);
            const double h = 1.0 / 32;
            write_one(out, "blob.vdb", sample_grid(dims, centred(dims, h, -23.5 * h), 1.0 / 1024, [](const Vec3& p) {
                          const double v = std::exp(-p.squaredNorm() / (2 * 0.2 * 0.2));
                          return v < 1e-3 ? 0.0 : v;
                      }));
        }
        // Sphere: density 1 inside radius 0.6, 48^3 voxels of 1/32.
        {
            const Vec3i dims(48, 48, 48);
            const double h = 1.0 / 32;
            write_one(out, "sphere.vdb", sample_grid(dims, centred(dims, h, -23.5 * h), 0.0,
                                                     [](const Vec3& p) { return p.norm() <= 0.6 ? 1.0 : 0.0; }));
        }
    }
    return 0;
}

}  // namespace vpm

VPM_REGISTER_COMMAND({"make-media", "write the procedural VDB files of media/ (plume, box, blob, sphere)", vpm::run_make_media});
