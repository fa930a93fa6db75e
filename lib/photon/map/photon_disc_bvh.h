#pragma once
// A bounding-volume hierarchy over photon balls (centre x_i, radius r_i from photon_radii.h) for
// the beam radiance estimate: a ray segment collects every photon whose disc perpendicular to the
// ray it crosses, i.e. whose foot point t_i = (x_i - o)·d lies in [0, tmax] and whose distance from
// the ray is below r_i (sample_point_estimate.h's beam_line_density, answered in one query).
//
// vpm's own BVH rather than Embree user geometry: a scene without shapes builds no Embree device
// (docs/design.md), and the query needs the foot-point rule, not a ray-sphere hit. Nodes are boxes
// around the balls, split at the median of the longest axis of the centres; leaves hold up to 4
// balls. Build and queries are deterministic: the same photons give the same tree and the same
// visiting order.
#include <cstdint>
#include <vector>

#include "core/math.h"

namespace vpm {

class PhotonDiscBvh {
public:
    PhotonDiscBvh() = default;
    // Balls with non-finite or zero radius are left out (a starved map's photons have r = inf).
    PhotonDiscBvh(const std::vector<Vec3>& centres, const std::vector<double>& radii);

    // Calls visit(index, t, d2) for every ball whose foot point t on the ray lies in [0, tmax] and
    // whose squared distance d2 from the ray is below r^2. `dir` must be unit length.
    template <class Visit>
    void for_each_crossed(const Vec3& origin, const Vec3& dir, double tmax, Visit&& visit) const {
        for_each_crossed_ball(origin, dir, tmax, [&](uint32_t index, double t, double d2, double) { visit(index, t, d2); });
    }
    // The same with the ball's radius: visit(index, t, d2, r).
    template <class Visit>
    void for_each_crossed_ball(const Vec3& origin, const Vec3& dir, double tmax, Visit&& visit) const;

    size_t size() const { return balls_.size(); }
    size_t node_count() const { return nodes_.size(); }
    size_t memory_bytes() const { return balls_.capacity() * sizeof(Ball) + nodes_.capacity() * sizeof(Node); }

private:
    struct Ball {
        Vec3 centre;
        double radius;
        uint32_t index;
    };
    struct Node {
        Bounds3 bounds;
        uint32_t first;   // leaf: first ball; inner: index of the second child (the first follows)
        uint32_t count;   // leaf: number of balls; inner: 0
    };
    uint32_t build(uint32_t begin, uint32_t end);
    std::vector<Ball> balls_;
    std::vector<Node> nodes_;
};

template <class Visit>
void PhotonDiscBvh::for_each_crossed_ball(const Vec3& origin, const Vec3& dir, double tmax, Visit&& visit) const {
    if (nodes_.empty() || !(tmax >= 0.0)) return;
    const Ray ray{origin, dir};
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = nodes_[stack[--top]];
        double t0, t1;
        // A crossed disc's foot point lies inside its ball, so inside the node's box.
        if (!node.bounds.intersect(ray, tmax, t0, t1)) continue;
        if (node.count == 0) {
            stack[top++] = node.first;
            stack[top++] = uint32_t(&node - nodes_.data()) + 1;
            continue;
        }
        for (uint32_t i = node.first; i < node.first + node.count; ++i) {
            const Ball& b = balls_[i];
            const Vec3 v = b.centre - origin;
            const double t = v.dot(dir);
            if (t < 0.0 || t > tmax) continue;
            const double d2 = std::max(0.0, v.squaredNorm() - t * t);
            if (d2 < b.radius * b.radius) visit(b.index, t, d2, b.radius);
        }
    }
}

}  // namespace vpm
