// type = "environment": light from every direction, seen by rays that escape. Photons start on
// the silhouette of the bounds of what can be lit (scene/lights/emission_bounds.h).
//
//   radiance   constant radiance (a uniform sky), or
//   file       a lat-long OpenEXR environment map (scene/lights/latlong_map.h: convention, sampling),
//              relative to the config file; with
//   scale      RGB or number multiplying the map (default 1), and
//   rotate_y   degrees about +Y, right-handed (default 0).
// Giving both radiance and file is an error; scale and rotate_y need file.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/sampling/sampling.h"
#include "scene/lights/emission_bounds.h"
#include "io/exr_read.h"
#include "scene/lights/latlong_map.h"
#include "scene/lights/light_registry.h"
#include "config/params.h"

namespace vpm {

namespace {

class EnvironmentLight : public Light {
public:
    explicit EnvironmentLight(const Rgb& radiance) : radiance_(radiance) {}

    bool sample_incident(const Vec3&, Rng& rng, LightSample& out) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        out.wi = sample_uniform_sphere(u1, u2);
        out.distance = kInfinity;
        out.weight = radiance_ * (4.0 * kPi);
        out.pdf = 1.0 / (4.0 * kPi);
        return true;
    }
    double pdf_incident(const Vec3&, const Vec3&) const override { return 1.0 / (4.0 * kPi); }
    // Direction uniform over the sphere (pdf 1 / 4 pi), origin uniform over the silhouette of what
    // can be lit seen along it (pdf 1 / A_proj(dir)): power L 4 pi A_proj(dir), whose mean over
    // directions is power() = L pi S (emission_bounds.h).
    EmissionSample sample_emission(Rng& rng) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform(), u4 = rng.uniform(),
                     u5 = rng.uniform();
        const Vec3 dir = sample_uniform_sphere(u1, u2);   // travel direction of the photon
        const EmissionLine line = bounds_.sample_line(dir, u3, u4, u5);
        return {Ray{line.origin, dir}, radiance_ * (4.0 * kPi * line.area)};
    }
    Rgb power() const override { return radiance_ * (4.0 * kPi * bounds_.mean_projected_area()); }
    Rgb escaped_radiance(const Vec3&) const override { return radiance_; }
    void set_scene_bounds(const Bounds3& b) override { bounds_.set(b); }
    bool at_infinity() const override { return true; }
    bool set_emission_focus(const Bounds3& f) override {
        bounds_.set_focus(f);
        return bounds_.focused();
    }
    std::string describe() const override { return "constant environment, radiance " + format_rgb(radiance_); }

private:
    Rgb radiance_;
    EmissionBounds bounds_;
};

// An environment map, importance-sampled by luminance for next-event estimation and for photons.
class EnvironmentMapLight : public Light {
public:
    EnvironmentMapLight(LatLongMap map, std::string file, const Rgb& scale, double rotate_y)
        : map_(std::move(map)), file_(std::move(file)), scale_(scale), rotate_y_(rotate_y) {}

    bool sample_incident(const Vec3&, Rng& rng, LightSample& out) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        if (map_.black()) return false;
        Rgb radiance;
        map_.sample(u1, u2, out.wi, radiance, out.pdf);
        out.distance = kInfinity;
        out.weight = radiance / out.pdf;
        return true;
    }
    double pdf_incident(const Vec3&, const Vec3& wi) const override { return map_.pdf(wi); }
    // Incident direction wi by luminance (pdf p(wi)); the photon travels along d = -wi from a point
    // uniform over the silhouette seen along d (pdf 1 / A_proj(d)). Its power L(wi) A_proj(d) / p(wi)
    // has mean  integral of L(w) A_proj(w) dw = sum_a A_a integral of L(w) |w_a| dw = power()
    // (A_proj(-w) = A_proj(w)).
    EmissionSample sample_emission(Rng& rng) const override {
        const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform(), u4 = rng.uniform(),
                     u5 = rng.uniform();
        if (map_.black() || bounds_.empty())   // nothing to emit; a valid ray that carries nothing
            return {Ray{bounds_.box().empty() ? Vec3::Zero() : bounds_.box().lo, Vec3::UnitZ()}, Rgb::Zero()};
        Vec3 wi;
        Rgb radiance;
        double pdf;
        map_.sample(u1, u2, wi, radiance, pdf);
        const Vec3 dir = -wi;
        const EmissionLine line = bounds_.sample_line(dir, u3, u4, u5);
        return {Ray{line.origin, dir}, radiance * (line.area / pdf)};
    }
    Rgb power() const override {
        if (bounds_.empty()) return Rgb::Zero();
        const Vec3& a = bounds_.face_area();
        return a[0] * map_.abs_axis_integral(0) + a[1] * map_.abs_axis_integral(1) + a[2] * map_.abs_axis_integral(2);
    }
    Rgb escaped_radiance(const Vec3& dir) const override { return map_.radiance(dir); }
    void set_scene_bounds(const Bounds3& b) override { bounds_.set(b); }
    bool at_infinity() const override { return true; }
    bool set_emission_focus(const Bounds3& f) override {
        bounds_.set_focus(f);
        return bounds_.focused();
    }
    std::string describe() const override {
        std::ostringstream s;
        s << "environment map '" << file_ << "' (" << map_.width() << " x " << map_.height() << "), scale "
          << format_rgb(scale_) << ", rotate_y " << rotate_y_ << " deg, mean radiance "
          << format_rgb(map_.integral() / (4.0 * kPi));
        if (map_.black()) s << "; every texel is black: the light has zero power and is never sampled";
        return s.str();
    }

private:
    LatLongMap map_;
    std::string file_;
    Rgb scale_;
    double rotate_y_;
    EmissionBounds bounds_;
};

// Reads the map of key `file`: every channel of every pixel finite and >= 0.
std::unique_ptr<Light> make_environment_map_light(Params& p) {
    const std::string file = p.path("file").string();
    const Rgb scale = p.rgb("scale", Rgb::Ones(), emission_range());
    const double rotate_y = p.real("rotate_y", 0.0, Range::closed(-360.0, 360.0));
    ExrPixels pixels;
    try {
        pixels = read_exr_pixels(file);
    } catch (const FileError& e) {
        p.fail("file", e.what());
    }
    for (size_t k = 0; k < pixels.rgb.size(); ++k) {
        const float v = pixels.rgb[k];
        if (!(v >= 0.0f) || !std::isfinite(v)) {
            const size_t texel = k / 3;
            std::ostringstream s;
            s << file << ": pixel (" << texel % size_t(pixels.width) << ", " << texel / size_t(pixels.width)
              << ") channel " << "RGB"[k % 3] << " is " << v
              << "; an environment map's radiance must be finite and >= 0 in every pixel";
            p.fail("file", s.str());
        }
    }
    float brightest = 0.0f;
    for (const float v : pixels.rgb) brightest = std::max(brightest, v);
    if (!(double(brightest) * scale.maxCoeff() <= kMaxEmission)) {
        std::ostringstream s;
        s << "scale " << format_rgb(scale) << " times the brightest texel of " << file << " (" << brightest << ") exceeds "
          << kMaxEmission << ", the largest radiance a light may have (scene/lights/light_registry.h)";
        p.fail("scale", s.str());
    }
    LatLongMap map(pixels.width, pixels.height, std::move(pixels.rgb), scale, rotate_y);
    return std::make_unique<EnvironmentMapLight>(std::move(map), file, scale, rotate_y);
}

}  // namespace

std::unique_ptr<Light> make_environment_light(Params& p) {
    if (p.has("file")) {
        if (p.has("radiance"))
            p.fail("radiance", "give either radiance (a constant sky) or file (an environment map), not both");
        return make_environment_map_light(p);
    }
    for (const char* key : {"scale", "rotate_y"})
        if (p.has(key)) p.fail(key, "applies to an environment map only: give file as well (or leave it out)");
    return std::make_unique<EnvironmentLight>(p.rgb("radiance", emission_range()));
}

}  // namespace vpm
