#include "scene/media/grid_medium.h"
#include "scene/media/tracking_counter.h"

#include <cmath>
#include <sstream>

#include "core/error.h"
#include "config/params.h"
#include "config/transform_params.h"
#include "io/vdb_io.h"

namespace vpm {

namespace {

std::string vec_str(const Vec3& v) {
    std::ostringstream s;
    s.precision(6);
    s << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
    return s.str();
}

// The world box around an index-space box: its eight corners transformed.
Bounds3 world_box(const Eigen::Affine3d& index_to_world, const Bounds3& b) {
    Bounds3 w;
    for (int c = 0; c < 8; ++c)
        w.extend(index_to_world * Vec3((c & 1) ? b.hi.x() : b.lo.x(), (c & 2) ? b.hi.y() : b.lo.y(), (c & 4) ? b.hi.z() : b.lo.z()));
    return w;
}

}  // namespace

GridMedium::GridMedium(DensityGrid grid, double sigma_t_scale, const Rgb& albedo, double g,
                       const Eigen::Affine3d& config_transform, std::string file)
    : Medium(albedo, g), grid_(std::move(grid)), scale_(sigma_t_scale), file_(std::move(file)) {
    index_to_world_ = config_transform * grid_.index_to_world();
    world_to_index_ = index_to_world_.inverse();
    const Eigen::Matrix3d m = world_to_index_.linear();
    axis_aligned_ = m(0, 1) == 0.0 && m(0, 2) == 0.0 && m(1, 0) == 0.0 && m(1, 2) == 0.0 && m(2, 0) == 0.0 && m(2, 1) == 0.0;
    if (!grid_.empty()) {
        world_bounds_ = world_box(index_to_world_, grid_.index_bounds());
        if (!grid_.active_bounds().empty()) {
            active_world_bounds_ = world_box(index_to_world_, grid_.active_bounds());
            // Padding far above the rounding of the corners' transform.
            const Vec3 pad = 1e-6 * (active_world_bounds_.hi - active_world_bounds_.lo).cwiseAbs();
            active_world_bounds_.lo -= pad;
            active_world_bounds_.hi += pad;
        }
    }
}

bool GridMedium::misses_active(const Ray& ray, double tmax) const {
    // A slab test in world space against the padded box, rejecting only by a margin relative to
    // the parameters (so rounding that differs from the index-space clip never rejects a ray that
    // clip would keep). NaN anywhere keeps the ray: the exact path decides.
    if (active_world_bounds_.empty()) return true;   // no active block: density 0 everywhere
    const Vec3& lo = active_world_bounds_.lo;
    const Vec3& hi = active_world_bounds_.hi;
    // A ray starting in the box meets it (photons scattered in the medium): no divisions.
    if (ray.origin.x() >= lo.x() && ray.origin.x() <= hi.x() && ray.origin.y() >= lo.y() && ray.origin.y() <= hi.y() &&
        ray.origin.z() >= lo.z() && ray.origin.z() <= hi.z())
        return false;
    const Vec3 inv = ray.dir.cwiseInverse();   // the three divisions issued together
    double ta = 0.0, tb = tmax;
    for (int a = 0; a < 3; ++a) {
        const double o = ray.origin[a];
        if (ray.dir[a] == 0.0) {
            if (o < lo[a] || o > hi[a]) return true;
            continue;
        }
        const double t_lo = (lo[a] - o) * inv[a], t_hi = (hi[a] - o) * inv[a];
        // min / max (minsd, maxsd), not a swap branch on the direction's random sign; with a NaN these
        // select exactly what the swap did (grid_detail::clip_line).
        ta = std::max(ta, std::min(t_lo, t_hi));
        tb = std::min(tb, std::max(t_hi, t_lo));
    }
    return ta > tb + 1e-7 * (std::abs(ta) + std::abs(tb));
}

bool GridMedium::ball_integral(const Vec3& x, double r, double& integral) const {
    // With axis-aligned index axes the ball is an axis-aligned ellipsoid in index space, symmetric
    // in each axis about its centre c; inside one cell [n, n + 1]^3 the trilinear density is
    // a + sum b_i u_i + sum c_ij u_i u_j + d u_x u_y u_z in u = p - c, and every term but a
    // averages to 0 over it. (Rotated grids: the u_i u_j terms do not, so they integrate.)
    if (!axis_aligned_) return false;
    const Vec3 c = world_to_index_ * x;
    const Eigen::Matrix3d m = world_to_index_.linear();
    for (int a = 0; a < 3; ++a) {
        const double h = r * std::abs(m(a, a));
        if (std::floor(c[a] - h) != std::floor(c[a] + h)) return false;
    }
    integral = (4.0 / 3.0) * kPi * r * r * r * sigma_t(x);
    return true;
}

namespace {

// Work of one voxel cell's closed form (8 voxels, the cubic, a DDA step) in units of a thinned
// tentative collision of delta tracking (a logarithm, one or two uniforms, a sub-block majorant
// read, sometimes a lookup). bench_tracing's walk at sigma_t_scale 40 .. 1e8 is within noise of
// its best for 1 .. 4; 2 is in the middle.
constexpr double kCellCost = 2.0;

// The trilinear density of a DensityGrid along one ray, as a Field for majorant_tracking.h.
// Index space: o + t d with t in world units (d is not normalised), so majorants need no
// rescaling. Closed forms: uniform blocks (constant density) and, elsewhere, the exact optical
// depth of the trilinear field voxel cell by voxel cell (a cubic along the ray in each cell).
struct TrilinearRayField {
    using Segment = DensityGrid::Segment;
    static constexpr bool kHasExact = true;

    const DensityGrid& grid;
    Vec3 o, d;
    double cells_per_t;   // |d|_1: voxel-cell faces crossed per unit of t

    Vec3 id;              // 1 / d per axis
    // Per axis, the face of a sub-block the ray leaves through: its offset (2 for d > 0, 0 for
    // d < 0), and whether the ray moves along the axis at all (chosen once, not per tentative collision).
    int exit_face[3];
    bool moves[3];

    TrilinearRayField(const DensityGrid& g, const Eigen::Affine3d& world_to_index, const Ray& ray)
        : grid(g), o(world_to_index * ray.origin), d(world_to_index.linear() * ray.dir), cells_per_t(d.lpNorm<1>()),
          id(d.cwiseInverse()) {
        for (int a = 0; a < 3; ++a) {
            exit_face[a] = d[a] > 0.0 ? 2 : 0;
            moves[a] = d[a] > 0.0 || d[a] < 0.0;
        }
    }
    Vec3 inv_d() const { return id; }

    template <class V>
    int walk(double t0, double t1, V&& visit) const {
        return grid.walk_segments(o, d, id, t0, t1, visit);
    }
    double density(const Segment& s, double t) const { return grid.density_in(o + t * d, s); }
    double local_majorant(const Segment& s, double t) const { return grid.local_majorant(o + t * d, s); }

    // The sub-block holding o + t d (clamped into the block): its majorant, its closed region
    // [lo, lo + size]^3 and the t where the ray leaves it (>= t; the segment's end at most).
    // Blocks without sub-blocks: the block itself up to the segment's end.
    struct Span {
        double majorant, t_end;
        int lo[3], size;
    };
    void local_span(const Segment& s, double t, Span& sp) const {
        if (!s.sub) {
            sp.majorant = s.majorant;
            sp.t_end = s.tb;
            for (int a = 0; a < 3; ++a) sp.lo[a] = s.lo[a];
            sp.size = DensityGrid::kDim;
            return;
        }
        const Vec3 p = o + t * d;
        int i[3];
        double t_end = s.tb;
        for (int a = 0; a < 3; ++a) {   // clamp_to, then the sub-block's exit face on this axis
            const double q = std::min(std::max(p[a], double(s.lo[a])), double(s.lo[a] + DensityGrid::kDim));
            i[a] = std::min(static_cast<int>((q - s.lo[a]) * 0.5), 3);
            sp.lo[a] = s.lo[a] + 2 * i[a];
            const double te = (sp.lo[a] + exit_face[a] - o[a]) * id[a];
            if (moves[a] && te < t_end) t_end = te;
        }
        sp.majorant = s.sub[(i[0] * 4 + i[1]) * 4 + i[2]];
        sp.t_end = std::max(t_end, t);
        sp.size = 2;
    }
    // The density at o + t d clamped into the span's closed region (where its majorant holds).
    double density_local(const Segment&, const Span& sp, double t) const {
        const Vec3 p = o + t * d;
        Vec3 q;
        for (int a = 0; a < 3; ++a) q[a] = std::min(std::max(p[a], double(sp.lo[a])), double(sp.lo[a] + sp.size));
        return grid.density(q);
    }

    // The closed form costs kCellCost per cell crossed (at most 1 + |d|_1 (tb - ta)); a uniform
    // block costs nothing.
    double exact_cost(const Segment& s) const { return s.uniform ? 0.0 : kCellCost * (1.0 + cells_per_t * (s.tb - s.ta)); }

    // Visits the voxel cells of segment s: visit(cubic, ta, tb) with the density on [ta, tb] as
    // a cubic in u = (t - ta) / (tb - ta). Stops when visit returns false. In blocks with
    // sub-block majorants, sub-blocks with majorant 0 are stepped over (their density is 0),
    // so a flight that starts in empty space does not integrate its way through it.
    template <class V>
    bool cells(const Segment& s, TrackingStats& st, V&& visit) const {
        const Vec3 id = inv_d();
        const auto cell_walk = [&](const int lo[3], int n, double ta, double tb) {
            return grid_detail::dda(o, d, id, Vec3(lo[0], lo[1], lo[2]), 1.0, Vec3i::Constant(n), ta, tb,
                                    [&](const int* c, double a, double b) {
                ++st.cells;
                const int ci[3] = {lo[0] + c[0], lo[1] + c[1], lo[2] + c[2]};
                double v[8];
                grid.stencil(ci[0], ci[1], ci[2], v);
                double fa[3], fb[3];
                for (int k = 0; k < 3; ++k) {   // local coordinates; the clamp only undoes rounding
                    fa[k] = std::min(std::max(o[k] + a * d[k] - ci[k], 0.0), 1.0);
                    fb[k] = std::min(std::max(o[k] + b * d[k] - ci[k], 0.0), 1.0);
                }
                return bool(visit(tracking::trilinear_along(v, fa, fb), a, b));
            });
        };
        if (!s.sub) return cell_walk(s.lo, DensityGrid::kDim, s.ta, s.tb);
        return grid_detail::dda(o, d, id, Vec3(s.lo[0], s.lo[1], s.lo[2]), 2.0, Vec3i::Constant(4), s.ta, s.tb,
                                [&](const int* q, double a, double b) {
            ++st.blocks;
            if (!(s.sub[(q[0] * 4 + q[1]) * 4 + q[2]] > 0.0f)) return true;
            const int lo[3] = {s.lo[0] + 2 * q[0], s.lo[1] + 2 * q[1], s.lo[2] + 2 * q[2]};
            return cell_walk(lo, 2, a, b);
        });
    }

    // The same cells in one DDA over the block's 8^3 voxel cells (cells of empty sub-blocks
    // skipped): one set-up per block instead of one per sub-block crossed.
    template <class V>
    bool flat_cells(const Segment& s, V&& visit) const {
        DensityGrid::BlockWindow w;
        grid.block_window(s.lo[0], s.lo[1], s.lo[2], w);
        return grid_detail::dda(o, d, id, Vec3(s.lo[0], s.lo[1], s.lo[2]), 1.0, Vec3i::Constant(DensityGrid::kDim), s.ta, s.tb,
                                [&](const int* c, double a, double b) {
            if (s.sub && !(s.sub[((c[0] >> 1) * 4 + (c[1] >> 1)) * 4 + (c[2] >> 1)] > 0.0f)) return true;
            const int ci[3] = {s.lo[0] + c[0], s.lo[1] + c[1], s.lo[2] + c[2]};
            double v[8];
            DensityGrid::stencil(w, c[0], c[1], c[2], v);
            // A cell of zeros adds no piece (OpticalDepthProfile::add drops depth 0): skip its cubic.
            if (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0 && v[3] == 0.0 && v[4] == 0.0 && v[5] == 0.0 && v[6] == 0.0 && v[7] == 0.0)
                return true;
            double fa[3], fb[3];
            for (int k = 0; k < 3; ++k) {   // local coordinates; the clamp only undoes rounding
                fa[k] = std::min(std::max(o[k] + a * d[k] - ci[k], 0.0), 1.0);
                fb[k] = std::min(std::max(o[k] + b * d[k] - ci[k], 0.0), 1.0);
            }
            return bool(visit(tracking::trilinear_along(v, fa, fb), a, b));
        });
    }

    double exact_depth(const Segment& s, TrackingStats& st) const {
        if (s.uniform) return s.majorant * (s.tb - s.ta);
        double D = 0.0;
        cells(s, st, [&](const tracking::CubicBernstein& cb, double a, double b) {
            D += cb.integral() * (b - a);
            return true;
        });
        return D;
    }

    double exact_sample(const Segment& s, double scale, double& E, TrackingStats& st) const {
        if (s.uniform) {
            const double tau = scale * s.majorant * (s.tb - s.ta);
            if (!(tau > E)) {
                E -= tau;
                return kInfinity;
            }
            return inside(s.ta + E / (scale * s.majorant), s.ta, s.tb);
        }
        double result = kInfinity;
        cells(s, st, [&](const tracking::CubicBernstein& cb, double a, double b) {
            const double len = b - a;
            const double tau = scale * (cb.integral() * len);   // may overflow to inf: then the collision is here
            if (!(tau > E)) {
                E -= tau;
                return true;
            }
            // Solve integral_0^u cubic = E / scale / len in density units (finite even when tau is not).
            const double u = cb.invert_integral(E / scale / len);
            result = inside(a + u * len, s.ta, s.tb);
            return false;
        });
        return result;
    }

    // The collision lies strictly inside (ta, tb) mathematically (E > 0 almost surely and the
    // depth to tb exceeds E); keep it there when rounding lands on an end point.
    static double inside(double t, double ta, double tb) {
        if (!(t > ta)) t = std::nextafter(ta, kInfinity);
        if (!(t < tb)) t = std::nextafter(tb, -kInfinity);
        return t;
    }
};

}  // namespace

double GridMedium::sample_free_flight(const Ray& ray, double tmax, Rng& rng, TrackingStats* stats) const {
    if (!(scale_ > 0.0) || !(tmax > 0.0) || grid_.empty() || misses_active(ray, tmax)) return kInfinity;
    TrackingStats st;   // counted per thread (scene/media/tracking_counter.h)
    const double t = tracking::sample_free_flight(TrilinearRayField(grid_, world_to_index_, ray), scale_, 0.0, tmax, rng, &st);
    count_tracking(st);
    if (stats) stats->add(st);
    return t;
}

double GridMedium::transmittance(const Ray& ray, double tmax, Rng& rng, TrackingStats* stats) const {
    if (!(scale_ > 0.0) || !(tmax > 0.0) || grid_.empty() || misses_active(ray, tmax)) return 1.0;
    TrackingStats st;
    const double T = tracking::transmittance(TrilinearRayField(grid_, world_to_index_, ray), scale_, 0.0, tmax, rng, &st);
    count_tracking(st);
    if (stats) stats->add(st);
    return T;
}

void GridMedium::majorant_pieces(const Ray& ray, double tmax, const MajorantVisitor& visit) const {
    if (!(scale_ > 0.0) || !(tmax > 0.0) || grid_.empty()) return;
    TrilinearRayField(grid_, world_to_index_, ray).walk(0.0, tmax, [&](const auto& s) {
        return s.majorant > 0.0 ? visit(s.ta, s.tb, scale_ * s.majorant) : true;
    });
}

void GridMedium::optical_depth_profile(const Ray& ray, double tmax, OpticalDepthProfile& out) const {
    out.reset(scale_);
    if (!(scale_ > 0.0) || !(tmax > 0.0) || grid_.empty()) return;
    const TrilinearRayField f(grid_, world_to_index_, ray);
    TrackingStats st;   // counted per thread (scene/media/tracking_counter.h): the march's cost
    f.walk(0.0, tmax, [&](const DensityGrid::Segment& s) {
        ++st.blocks;
        if (s.uniform) return out.add_constant(s.ta, s.tb, s.majorant);
        return f.flat_cells(s, [&](const tracking::CubicBernstein& cb, double a, double b) {
            ++st.cells;
            return out.add(a, b, cb);
        });
    });
    count_tracking(st);
}

std::string GridMedium::describe() const {
    std::ostringstream s;
    s.precision(6);
    const DensityGrid& g = grid_;
    s << "grid medium: file '" << file_ << "', grid '" << g.name() << "', " << g.active_voxel_count()
      << " active voxels, " << g.dense_block_count() << " dense of " << g.block_total() << " 8^3 blocks ("
      << g.memory_bytes() / 1024 << " KiB), index box " << vec_str(g.voxel_lo().cast<double>()) << " - "
      << vec_str(g.voxel_hi().cast<double>()) << ", world bounds " << vec_str(world_bounds_.lo) << " - "
      << vec_str(world_bounds_.hi) << ", max density " << g.max_density() << ", sigma_t_scale " << scale_
      << ", albedo " << vec_str(albedo_.matrix()) << ", g " << g_;
    return s.str();
}

std::unique_ptr<Medium> make_grid_medium(Params& p) {
    const std::string file = p.path("file").string();
    const bool has_grid = p.has("grid");
    const std::string grid_name = p.string("grid", "");
    const double scale = p.real("sigma_t_scale", 1.0, Range::at_least(0.0));
    const Rgb albedo = p.rgb("albedo", Rgb::Constant(0.8), Range::closed(0.0, 1.0));
    const double g = p.real("g", 0.0, Range::open(-1.0, 1.0));
    Params tp = p.table("transform");
    const Eigen::Affine3d xf = read_transform(tp);
    tp.finish();   // the sub-table is ours: its unknown keys are reported here

    DensityGrid grid;
    try {
        grid = load_vdb_density(file, grid_name);
    } catch (const ConfigError& e) {   // grid selection: absent or wrong type
        p.fail(has_grid ? "grid" : "file", e.what());
    } catch (const FileError& e) {
        p.fail("file", e.what());
    }
    return std::make_unique<GridMedium>(std::move(grid), scale, albedo, g, xf, file);
}

}  // namespace vpm
