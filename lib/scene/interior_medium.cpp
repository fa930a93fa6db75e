#include "scene/interior_medium.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "scene/dielectric_regions.h"
#include "scene/media/ball_clip_moments.h"

namespace vpm {

namespace {

// The distance from x to the box b (0 inside it).
double distance_to_box(const Vec3& x, const Bounds3& b) {
    const Vec3 below = (b.lo - x).cwiseMax(0.0), above = (x - b.hi).cwiseMax(0.0);
    return (below + above).norm();
}

}  // namespace

InteriorMedium::InteriorMedium(std::unique_ptr<Medium> inner, const Surfaces& surfaces, int shape)
    : Medium(inner->albedo(), inner->g()),
      inner_(std::move(inner)),
      homogeneous_(dynamic_cast<const HomogeneousMedium*>(inner_.get())),
      surfaces_(surfaces),
      shape_geometry_(surfaces.dielectric_shapes().at(size_t(shape))),
      shape_(shape) {
    const Bounds3 a = inner_->bounds(), b = shape_geometry_.bounds;
    bounds_ = Bounds3{a.lo.cwiseMax(b.lo), a.hi.cwiseMin(b.hi)};
    if (bounds_.empty()) bounds_ = Bounds3{};
}

bool InteriorMedium::contains(const Vec3& p) const {
    if (shape_geometry_.sphere) return (p - shape_geometry_.center).squaredNorm() < shape_geometry_.radius * shape_geometry_.radius;
    if (distance_to_box(p, shape_geometry_.bounds) > 0.0) return false;
    return (region_at(&surfaces_, p) >> shape_) & 1;
}

int InteriorMedium::inside_intervals(const Ray& ray, double tmax, double (*t)[2]) const {
    if (shape_geometry_.sphere) {
        // The chord from the centre's distance to the ray's line (accurate for far origins), as the
        // sphere's own intersection computes it.
        const Vec3 oc = ray.origin - shape_geometry_.center;
        const double b = oc.dot(ray.dir);
        const double h2 = shape_geometry_.radius * shape_geometry_.radius - (oc - b * ray.dir).squaredNorm();
        if (h2 < 0.0) return 0;
        const double h = std::sqrt(h2);
        t[0][0] = std::max(0.0, -b - h);
        t[0][1] = std::min(tmax, -b + h);
        return t[0][0] < t[0][1] ? 1 : 0;
    }
    double ta, tb;
    if (!shape_geometry_.bounds.intersect(ray, tmax, ta, tb)) return 0;
    // The shape's crossings along the ray to infinity: inside on [0, first) iff their count is odd
    // (a ray starting on the surface skips it, so the parity holds there too). n crossings make at
    // most (n + 1) / 2 intervals inside (n odd: the ray starts inside), so 2 kMaxIntervals crossings
    // fit t's kMaxIntervals.
    double crossing[2 * kMaxIntervals];
    int n = 0;
    Ray r = ray;
    double travelled = 0.0;
    SurfaceHit hit;
    while (surfaces_.intersect(r, kInfinity, hit)) {
        travelled += hit.t;
        if (hit.dielectric == shape_) {
            if (n == 2 * kMaxIntervals)
                throw Error("interior_medium: a ray crosses closed shape " + std::to_string(shape_geometry_.table) + " more than " +
                            std::to_string(2 * kMaxIntervals) + " times (scene/interior_medium.h)");
            crossing[n++] = travelled;
        }
        r.origin = hit.position;
    }
    int count = 0;
    bool inside = n % 2 == 1;
    double start = 0.0;
    for (int i = 0; i <= n && start < tmax; ++i) {
        const double end = i < n ? std::min(crossing[i], tmax) : tmax;
        if (inside && end > start) {
            t[count][0] = start;
            t[count][1] = end;
            ++count;
        }
        inside = !inside;
        start = end;
    }
    return count;
}

double InteriorMedium::sample_free_flight(const Ray& ray, double tmax, Rng& rng) const {
    double t[kMaxIntervals][2];
    const int n = inside_intervals(ray, tmax, t);
    for (int i = 0; i < n; ++i) {
        const double s = inner_->sample_free_flight(Ray{ray.at(t[i][0]), ray.dir}, t[i][1] - t[i][0], rng);
        if (s < t[i][1] - t[i][0]) return t[i][0] + s;
    }
    return kInfinity;
}

double InteriorMedium::transmittance(const Ray& ray, double tmax, Rng& rng) const {
    double t[kMaxIntervals][2];
    const int n = inside_intervals(ray, tmax, t);
    double tr = 1.0;
    for (int i = 0; i < n && tr > 0.0; ++i) tr *= inner_->transmittance(Ray{ray.at(t[i][0]), ray.dir}, t[i][1] - t[i][0], rng);
    return tr;
}

double InteriorMedium::sigma_t(const Vec3& p) const { return contains(p) ? inner_->sigma_t(p) : 0.0; }

InteriorMedium::BallSide InteriorMedium::ball_side(const Vec3& x, double r) const {
    if (shape_geometry_.sphere) {
        const double d = (x - shape_geometry_.center).norm();
        if (d + r <= shape_geometry_.radius) return BallSide::inside;
        if (d - r >= shape_geometry_.radius) return BallSide::outside;
        return BallSide::crossing;
    }
    return distance_to_box(x, shape_geometry_.bounds) >= r ? BallSide::outside : BallSide::crossing;
}

bool InteriorMedium::uniform_lens(const Vec3& x, double r, double& sigma, ClipMoments& lens) const {
    if (!homogeneous_ || !homogeneous_->contains_ball(x, r)) return false;
    sigma = homogeneous_->sigma_t_value();
    lens = shape_geometry_.sphere ? ball_ball_moments(r, shape_geometry_.center - x, shape_geometry_.radius)
                                  : shape_ball_moments(surfaces_, x, r, shape_);
    return true;
}

bool InteriorMedium::ball_integral(const Vec3& x, double r, double& integral) const {
    switch (ball_side(x, r)) {
        case BallSide::inside: return inner_->ball_integral(x, r, integral);
        case BallSide::outside: integral = 0.0; return true;
        case BallSide::crossing: break;
    }
    double sigma;
    ClipMoments lens;
    if (!uniform_lens(x, r, sigma, lens)) return false;
    integral = sigma * lens.m0;
    return true;
}

bool InteriorMedium::ball_moments(const Vec3& x, double r, double& m0, Vec3& m1, Eigen::Matrix3d& m2) const {
    switch (ball_side(x, r)) {
        case BallSide::inside: return inner_->ball_moments(x, r, m0, m1, m2);
        case BallSide::outside:
            m0 = 0.0;
            m1 = Vec3::Zero();
            m2 = Eigen::Matrix3d::Zero();
            return true;
        case BallSide::crossing: break;
    }
    double sigma;
    ClipMoments lens;
    if (!uniform_lens(x, r, sigma, lens)) return false;
    m0 = sigma * lens.m0;
    m1 = sigma * lens.m1;
    m2 = sigma * lens.m2;
    return true;
}

void InteriorMedium::majorant_pieces(const Ray& ray, double tmax, const MajorantVisitor& visit) const {
    double t[kMaxIntervals][2];
    const int n = inside_intervals(ray, tmax, t);
    bool more = true;
    for (int i = 0; i < n && more; ++i) {
        const double a = t[i][0];
        inner_->majorant_pieces(Ray{ray.at(a), ray.dir}, t[i][1] - a, [&](double ta, double tb, double majorant) {
            more = visit(a + ta, a + tb, majorant);
            return more;
        });
    }
}

void InteriorMedium::optical_depth_profile(const Ray& ray, double tmax, OpticalDepthProfile& out) const {
    double t[kMaxIntervals][2];
    const int n = inside_intervals(ray, tmax, t);
    out.reset(1.0);
    thread_local OpticalDepthProfile piece;
    for (int i = 0; i < n; ++i) {
        inner_->optical_depth_profile(Ray{ray.at(t[i][0]), ray.dir}, t[i][1] - t[i][0], piece);
        if (piece.empty()) continue;
        if (out.empty()) out.reset(piece.scale());
        if (!out.append_shifted(piece, t[i][0])) break;
    }
}

std::string InteriorMedium::describe() const {
    return inner_->describe() + ", inside closed dielectric shape " + std::to_string(shape_geometry_.table) +
           " only (interior_medium)";
}

}  // namespace vpm
