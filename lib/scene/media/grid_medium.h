#pragma once
// A heterogeneous medium from a density grid (OpenVDB float or double grid).
//
//   | key           | type                 | default          | meaning                            |
//   |---------------|----------------------|------------------|------------------------------------|
//   | file          | path                 | required         | .vdb file, relative to the config  |
//   | grid          | string               | first float grid | name of the density grid (float or double) |
//   | sigma_t_scale | number >= 0          | 1                | sigma_t = scale * density (1/world)|
//   | albedo        | number or rgb [0, 1] | 0.8              | single-scattering albedo           |
//   | g             | number in (-1, 1)    | 0                | Henyey-Greenstein asymmetry        |
//   | transform     | table                | identity         | see config/transform_params.h       |
//
// sigma_t(x) = sigma_t_scale * density(world_to_index(x)), with index_to_world = config
// transform * the file's index-to-world. Tracking runs in index space: the ray origin and its
// (unnormalised) direction are mapped by the affine world-to-index map, so the parameter t stays
// in world units and majorants need no rescaling. Tracking is majorant_tracking.h over the grid's
// two-level majorant walk (8^3 blocks, 2^3-voxel sub-blocks): delta / ratio tracking where the
// majorant is light, and where it would cost many null collisions the exact optical depth of
// the trilinear field, voxel cell by voxel cell (free flights by inversion, transmittance
// exp(-tau)); uniform blocks use their constant. All of it is unbiased, and the work per
// free flight stays bounded as sigma_t_scale grows.
#include <memory>
#include <string>

#include "core/density_grid.h"
#include "scene/media/majorant_tracking.h"
#include "scene/media/medium.h"

namespace vpm {

class Params;

class GridMedium : public Medium {
public:
    GridMedium(DensityGrid grid, double sigma_t_scale, const Rgb& albedo, double g,
               const Eigen::Affine3d& config_transform = Eigen::Affine3d::Identity(), std::string file = {});

    Bounds3 bounds() const override { return world_bounds_; }
    double sample_free_flight(const Ray& ray, double tmax, Rng& rng) const override {
        return sample_free_flight(ray, tmax, rng, nullptr);
    }
    double transmittance(const Ray& ray, double tmax, Rng& rng) const override {
        return transmittance(ray, tmax, rng, nullptr);
    }
    double sigma_t(const Vec3& p) const override { return scale_ * grid_.density(world_to_index_ * p); }
    bool ball_integral(const Vec3& x, double r, double& integral) const override;   // the ball inside one voxel cell
    bool continuous() const override { return true; }   // trilinear, falling to 0 over one voxel outside the data
    void majorant_pieces(const Ray& ray, double tmax, const MajorantVisitor& visit) const override;
    // Uniform blocks as constants, other blocks voxel cell by voxel cell (empty sub-blocks skipped).
    void optical_depth_profile(const Ray& ray, double tmax, OpticalDepthProfile& out) const override;
    std::string describe() const override;

    // Same as above, adding the work done to *stats when non-null.
    double sample_free_flight(const Ray& ray, double tmax, Rng& rng, TrackingStats* stats) const;
    double transmittance(const Ray& ray, double tmax, Rng& rng, TrackingStats* stats) const;

    const DensityGrid& grid() const { return grid_; }
    double sigma_t_scale() const { return scale_; }
    const Eigen::Affine3d& index_to_world() const { return index_to_world_; }
    const Eigen::Affine3d& world_to_index() const { return world_to_index_; }

private:
    DensityGrid grid_;
    double scale_;
    Eigen::Affine3d index_to_world_, world_to_index_;
    Bounds3 world_bounds_;
    // The world box around the grid's active bounds, padded: rays that miss it (by a margin, see
    // misses_active()) skip the index-space set-up (most photon rays miss a small plume).
    Bounds3 active_world_bounds_;
    bool misses_active(const Ray& ray, double tmax) const;
    bool axis_aligned_ = false;   // world_to_index_ maps the world axes onto the index axes (no rotation, no shear)
    std::string file_;
};

// Builds a GridMedium from a [[media]] table (all keys above; `type` is left to the caller,
// and so is finish()). Loader errors become ConfigErrors at the `file` or `grid` key.
std::unique_ptr<Medium> make_grid_medium(Params& p);

}  // namespace vpm
