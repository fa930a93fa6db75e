#include "scene/grid_medium.h"

#include <cmath>
#include <sstream>

#include "core/error.h"
#include "scene/params.h"
#include "scene/transform_params.h"
#include "scene/vdb_io.h"

namespace vpm {

namespace {

// Russian roulette for ratio tracking: below this weight, survive with probability T / kRrWeight
// and continue with weight kRrWeight (unbiased; bounds the work in dense media).
constexpr double kRrWeight = 1e-2;

// Exponential step with rate mu from t; always advances t (a huge majorant times a large t could
// otherwise round the step away and loop forever).
inline double exp_step(double t, double mu, Rng& rng) {
    const double tn = t - std::log1p(-rng.uniform()) / mu;
    return tn > t ? tn : std::nextafter(t, kInfinity);
}

std::string vec_str(const Vec3& v) {
    std::ostringstream s;
    s.precision(6);
    s << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
    return s.str();
}

}  // namespace

GridMedium::GridMedium(DensityGrid grid, double sigma_t_scale, const Rgb& albedo, double g,
                       const Eigen::Affine3d& config_transform, std::string file)
    : Medium(albedo, g), grid_(std::move(grid)), scale_(sigma_t_scale), file_(std::move(file)) {
    index_to_world_ = config_transform * grid_.index_to_world();
    world_to_index_ = index_to_world_.inverse();
    if (!grid_.empty()) {
        const Bounds3& ib = grid_.index_bounds();
        for (int c = 0; c < 8; ++c) {
            const Vec3 corner((c & 1) ? ib.hi.x() : ib.lo.x(), (c & 2) ? ib.hi.y() : ib.lo.y(),
                              (c & 4) ? ib.hi.z() : ib.lo.z());
            world_bounds_.extend(index_to_world_ * corner);
        }
    }
}

namespace {

// Walks the tentative collisions of the majorant process along `ray` in (0, tmax), block by
// block (empty blocks are skipped without sampling; restarting at each block entry is exact, the
// exponential is memoryless), and calls visit(t, sigma_t(t), majorant) at each. visit returns
// false to stop. Shared by delta tracking and ratio tracking.
template <class Visit>
void track_majorant(const DensityGrid& grid, double scale, const Eigen::Affine3d& world_to_index, const Ray& ray,
                    double tmax, Rng& rng, TrackingStats* stats, const Visit& visit) {
    const Vec3 o = world_to_index * ray.origin;
    const Vec3 d = world_to_index.linear() * ray.dir;   // not normalised: t stays in world units
    int64_t lookups = 0;
    const int blocks = grid.traverse(o, d, 0.0, tmax, [&](double ta, double tb, float majorant) {
        if (!(majorant > 0.0f)) return true;
        const double mu = scale * majorant;
        for (double t = ta;;) {
            t = exp_step(t, mu, rng);
            if (!(t < tb)) return true;
            ++lookups;
            if (!visit(t, scale * grid.density(o + t * d), mu)) return false;
        }
    });
    if (stats) {
        stats->blocks += blocks;
        stats->lookups += lookups;
    }
}

}  // namespace

double GridMedium::sample_free_flight(const Ray& ray, double tmax, Rng& rng, TrackingStats* stats) const {
    if (!(scale_ > 0.0) || !(tmax > 0.0)) return kInfinity;
    double result = kInfinity;
    track_majorant(grid_, scale_, world_to_index_, ray, tmax, rng, stats, [&](double t, double sigma_t, double mu) {
        if (rng.uniform() * mu >= sigma_t) return true;   // null collision
        result = t;
        return false;
    });
    return result;
}

double GridMedium::transmittance(const Ray& ray, double tmax, Rng& rng, TrackingStats* stats) const {
    if (!(scale_ > 0.0) || !(tmax > 0.0)) return 1.0;
    double T = 1.0;
    track_majorant(grid_, scale_, world_to_index_, ray, tmax, rng, stats, [&](double, double sigma_t, double mu) {
        T *= std::max(0.0, 1.0 - sigma_t / mu);   // sigma_t <= mu up to rounding
        if (T < kRrWeight) {
            if (T <= 0.0 || rng.uniform() * kRrWeight >= T) {
                T = 0.0;
                return false;
            }
            T = kRrWeight;
        }
        return true;
    });
    return T;
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
