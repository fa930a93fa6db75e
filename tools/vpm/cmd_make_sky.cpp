// `vpm make-sky [--out FILE.exr] [options]`: writes a small procedural sun-and-sky environment map
// in the lat-long layout of scene/lights/latlong_map.h (the file media/sky.exr is made by the defaults).
// Not a physical sky model: a zenith-to-horizon gradient, a glow around the sun, a dim ground, and
// a sun disc (much larger than the real one, so that a 128 x 64 map resolves it), anti-aliased by
// 8 x 8 samples per texel. Deterministic.
#include "arguments.h"
#include "command.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include <CLI/CLI.hpp>

#include "core/math.h"
#include "core/progress.h"
#include "render/run/image.h"
#include "render/run/image_io.h"
#include "render/run/staged_file.h"
#include "scene/lights/latlong_map.h"

namespace vpm {

namespace {

constexpr double kMaxSkyRadiance = 1e30;

struct SkyOptions {
    int width = 128, height = 64;
    double sun_elevation = 35.0;   // degrees above the horizon
    double sun_azimuth = 225.0;    // degrees from -Z towards +X (the map's convention)
    double sun_radius = 3.0;       // angular radius, degrees
    double sun_radiance = 400.0;
    double sky_radiance = 1.0;     // zenith blue scaled by this
};

// The unit direction towards the sun: azimuth 0 = -Z, 90 = +X, 180 = +Z, 270 = -X.
Vec3 sun_direction(const SkyOptions& o) {
    const double el = o.sun_elevation * kPi / 180.0, az = o.sun_azimuth * kPi / 180.0;
    return Vec3(std::sin(az) * std::cos(el), std::sin(el), -std::cos(az) * std::cos(el));
}

// Sky radiance (without the disc) towards unit direction d.
Rgb sky(const SkyOptions& o, const Vec3& d, const Vec3& sun) {
    const Rgb zenith(0.18, 0.32, 0.75), horizon(0.75, 0.82, 0.95), ground(0.12, 0.11, 0.10);
    const double y = d.y();
    Rgb c;
    if (y >= 0.0) {
        const double t = std::pow(y, 0.45);   // pale near the horizon, deep blue above
        c = horizon * (1.0 - t) + zenith * t;
    } else {
        const double t = std::min(1.0, -y / 0.08);   // short blend into the ground
        c = horizon * (1.0 - t) + ground * t;
    }
    // Warm glow around the sun, fading over ~15 degrees.
    const double cos_angle = std::min(1.0, std::max(-1.0, d.dot(sun)));
    c += Rgb(1.0, 0.8, 0.55) * (1.5 * std::exp(-std::acos(cos_angle) / 0.25));
    return c * o.sky_radiance;
}

Image make_sky(const SkyOptions& o, double& sun_share, bool progress) {
    Image image(o.width, o.height);
    const Vec3 sun = sun_direction(o);
    const double cos_sun = std::cos(o.sun_radius * kPi / 180.0);
    const Rgb sun_colour = Rgb(1.0, 0.93, 0.82) * o.sun_radiance;
    const int n = 8;   // samples per texel side
    // Rows in parallel (the largest map is 1.1e8 texels of 64 samples each); the power sums are
    // kept per row and added in row order, so the output does not depend on the thread count.
    std::vector<double> row_sun(size_t(o.height), 0.0), row_total(size_t(o.height), 0.0);
    Progress bar("make-sky", uint64_t(o.height), progress);
    tbb::parallel_for(0, o.height, [&](int j) {
        // Solid angle of one texel of this row: (2 pi / W)(cos theta_j - cos theta_j+1).
        const double omega = 2.0 * kPi / o.width * (std::cos(kPi * j / o.height) - std::cos(kPi * (j + 1) / o.height));
        for (int i = 0; i < o.width; ++i) {
            Rgb sum = Rgb::Zero();
            double covered = 0.0;
            for (int b = 0; b < n; ++b)
                for (int a = 0; a < n; ++a) {
                    const Vec3 d = latlong_direction((i + (a + 0.5) / n) / o.width, (j + (b + 0.5) / n) / o.height);
                    sum += sky(o, d, sun);
                    if (d.dot(sun) >= cos_sun) covered += 1.0;
                }
            const Rgb disc = sun_colour * (covered / (n * n));
            const Rgb texel = sum / double(n * n) + disc;
            image.set(i, j, texel);
            row_sun[size_t(j)] += luminance(disc) * omega;
            row_total[size_t(j)] += luminance(texel) * omega;
        }
        bar.advance();
    });
    bar.done();
    double sun_power = 0.0, total_power = 0.0;
    for (int j = 0; j < o.height; ++j) {
        sun_power += row_sun[size_t(j)];
        total_power += row_total[size_t(j)];
    }
    sun_share = total_power > 0.0 ? sun_power / total_power : 0.0;
    return image;
}

// A finite number in [lo, hi]; NaN and Inf fail (CLI11's Range lets NaN through, and its message
// would print DBL_MAX in full).
CLI::Validator finite_in(double lo, double hi) {
    std::ostringstream range;
    range << "[" << lo << ", " << hi << "]";
    return CLI::Validator(
        [lo, hi, r = range.str()](std::string& text) -> std::string {
            double v = 0.0;
            try {
                size_t pos = 0;
                v = std::stod(text, &pos);
                if (pos != text.size()) return "'" + text + "' is not a number";
            } catch (const std::exception&) {
                // stod refuses "1e999" (out of range) as well as text
                return "'" + text + "' is not a finite number in " + r;
            }
            if (!std::isfinite(v) || v < lo || v > hi) return "'" + text + "' is not a finite number in " + r;
            return std::string();
        },
        "in " + range.str());
}

int run_make_sky(int argc, char** argv) {
    CLI::App app{"Write a procedural sun-and-sky environment map (lat-long OpenEXR; +Y up, the image centre "
                 "looks along -Z; docs/rendering.md, \"Environment maps\")",
                 "vpm make-sky"};
    std::string out = "media/sky.exr";
    SkyOptions o;
    app.add_option("--out", out, "Output file (.exr; its folder is created if missing)")->capture_default_str();
    app.add_option("--width", o.width, "Width in texels (the height is usually width / 2)")
        ->check(CLI::Range(4, 16384))->capture_default_str();
    app.add_option("--height", o.height, "Height in texels")->check(CLI::Range(2, 8192))->capture_default_str();
    app.add_option("--sun-elevation", o.sun_elevation, "Sun elevation above the horizon, degrees")
        ->check(finite_in(-90.0, 90.0))->capture_default_str();
    app.add_option("--sun-azimuth", o.sun_azimuth, "Sun azimuth, degrees from -Z towards +X (90 = +X, 180 = +Z)")
        ->check(finite_in(-360.0, 360.0))->capture_default_str();
    app.add_option("--sun-radius", o.sun_radius, "Angular radius of the sun disc, degrees")
        ->check(finite_in(0.0, 90.0))->capture_default_str();
    // Radiances up to 1e30: every texel (at most ~2.3e30) is then a finite float in the EXR, with
    // eight orders of magnitude left for the renderer's sums of radiance times area.
    app.add_option("--sun-radiance", o.sun_radiance, "Radiance of the sun disc (white-ish)")
        ->check(finite_in(0.0, kMaxSkyRadiance))->capture_default_str();
    app.add_option("--sky-radiance", o.sky_radiance, "Multiplier of the sky gradient and the sun's glow")
        ->check(finite_in(0.0, kMaxSkyRadiance))->capture_default_str();
    bool quiet = false;
    app.add_flag("-q,--quiet", quiet, "No progress bar or progress lines on stderr");
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;
    std::string ext = std::filesystem::path(out).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext != ".exr") throw vpm::cli::UsageError("--out must end in .exr, got '" + out + "' (see vpm make-sky --help)");
    const std::filesystem::path parent = std::filesystem::path(out).parent_path();
    if (!parent.empty()) prepare_output_folder(parent);
    check_output_file(out);   // before minutes of work on a large map

    double sun_share = 0.0;
    const Image image = make_sky(o, sun_share, !quiet);
    write_exr(out, image);
    std::cout << out << ": " << o.width << " x " << o.height << ", " << std::filesystem::file_size(out)
              << " bytes, mean value " << image.mean() << ", sun disc " << 100.0 * sun_share
              << "% of the luminance integral\n";
    return 0;
}

}  // namespace

}  // namespace vpm

VPM_REGISTER_COMMAND({"make-sky", "write a procedural sun-and-sky environment map (lat-long EXR) such as media/sky.exr",
                      vpm::run_make_sky});
