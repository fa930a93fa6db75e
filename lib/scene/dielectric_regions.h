#pragma once
// Regions of space cut by closed dielectric (glass) shapes: a region is the set of glass shapes that
// contain a point, one bit per shape (SurfaceHit::dielectric). Radiance inside glass is eta^2 times
// that outside (docs/caustics.md), so a density estimate must not mix photons across a glass
// interface: photons and camera paths carry their region (docs/interface_regions.md).
//
// Walks track it: a light or the camera starts with region_at() (a ray-parity test), and every
// refraction through a dielectric toggles that shape's bit (region_after_specular; a reflection keeps
// it). The estimate at x then counts only photons of x's region, and region_ball_fraction() gives the
// share of its kNN ball that lies in that region: the volume the photons found there came from
// (region_disc_fraction() the same for a surface photon map's disc).
#include <cstdint>

#include "core/math.h"
#include "scene/media/ball_clip_moments.h"
#include "scene/surfaces/surfaces.h"

namespace vpm {

using RegionMask = uint64_t;

// The glass shapes containing x (0 outside all, and for a scene without dielectrics). Spheres by
// distance; meshes by the parity of a ray's crossings of each (a fixed direction off every axis).
RegionMask region_at(const Surfaces* surfaces, const Vec3& x);

// The region after a specular event at `hit` that sent the walk on along `dir`: a refraction (the walk
// goes through the surface: dir against the normal, which faces the incoming ray) through a
// dielectric toggles its bit.
inline RegionMask region_after_specular(RegionMask region, const SurfaceHit& hit, const Vec3& dir) {
    if (hit.dielectric < 0 || dir.dot(hit.normal) >= 0.0) return region;
    return region ^ (RegionMask(1) << hit.dielectric);
}

// The share of the ball B(x, r) that lies in `region` (x's own region), in (0, 1]. 1 where no glass
// surface crosses the ball. A ball crossed by one sphere's surface alone: the exact lens volume.
// Otherwise (meshes, two or more surfaces): kRegionBallPoints fixed points over the ball, each point's
// region read by toggling x's region at the glass crossings of the segment from x to it.
constexpr int kRegionBallPoints = 256;
double region_ball_fraction(const Surfaces* surfaces, const Vec3& x, double r, RegionMask region);

// The share of the disc of radius r about x, in the plane through x normal to n, that lies in
// `region`: the surface map's kNN disc where a glass shape meets a Lambertian surface (a bottle
// standing on a floor). x is taken just off the surface, on the side n faces, so the disc's points
// are read above coplanar glass (a bottle's base on the floor). 1 where no glass crosses the disc.
// One sphere: the exact lens area of the disc and the sphere's circle in the plane. Otherwise
// kRegionDiscPoints fixed points over the disc, each point's region read as the ball's are.
constexpr int kRegionDiscPoints = 128;
double region_disc_fraction(const Surfaces* surfaces, const Vec3& x, const Vec3& n, double r, RegionMask region);

// The volume moments about x of the part of B(x, r) inside closed dielectric shape `shape` (a mesh's
// inside for an interior medium's ball integral, scene/interior_medium.h): m0 the volume, m1 the
// integral of p - x, m2 of (p - x)(p - x)^T. The kRegionBallPoints fixed points above, each inside
// by the shape's bit of its region read from x's (region_at) along the segment; centre-symmetric,
// so a ball wholly on one side has m1 exactly 0.
ClipMoments shape_ball_moments(const Surfaces& surfaces, const Vec3& x, double r, int shape);

}  // namespace vpm
