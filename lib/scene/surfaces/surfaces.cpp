// Opaque surfaces in one Embree 3 scene. This is the only file of vpm that includes Embree.
//
// Parameters of one [[shapes]] entry
// ---------------------------------------------------------------------------------------------
//  key          type / default           meaning
//  type         "mesh" | "quad" | "box" | "sphere"   required
//  material     "lambertian" (default), "black", "mirror", "dielectric": its keys
//               (reflectance, ior, transmittance) are read by scene/materials/material_registry.h
//  transform    table, optional          object-to-world, see below (not for spheres)
//  type = "mesh":  file    path to .obj or .ply, relative to the config file
//  type = "quad":  center  [x,y,z]       required; the parallelogram's centre
//                  u, v    [x,y,z]       required; HALF edge vectors: corners are center +- u +- v
//                                        (so a 2 x 2 square is u = [1,0,0], v = [0,1,0])
//  type = "box":   min, max [x,y,z]      required; axis-aligned in object space, min < max
//  type = "sphere": center [x,y,z], radius (> 0)   required; intersected analytically in double
//                                        (no Embree geometry), beside the triangles
// A dielectric needs a closed shape whose inside is known: a box, a sphere, or a mesh in which
// every edge joins exactly two triangles of opposite winding (vertices welded by position); each
// closed part of the mesh is turned to face out of the glass (outwards, or into a cavity it
// encloses). A quad or an open mesh is an error.
//  [shapes.transform]: scale     number or [sx,sy,sz], default 1; no zero component
//                      rotate    [ax,ay,az,degrees], default [1,0,0,0]; axis need not be unit
//                      translate [x,y,z], default [0,0,0]
//                      applied in that order: p_world = T * R * S * p_object
//
// Precision. Geometry is kept in double precision here; Embree sees float vertices relative to
// the centre of the triangles' bounds (so scenes far from the origin lose nothing), and ray origins
// are shifted by the same centre in double before rounding. Embree's float hit distance is then
// refined in double against the plane of the hit triangle, and the normal is computed in double.
// Self-intersection, judged at the scale of the hit and the ray, never of the whole scene (a
// 1e6-wide shape elsewhere must not blur a 1e-6 sphere): see offsets.h for the two tolerances.
//  - A query skips the surface its ray starts on: a triangle whose plane lies behind the origin or
//    within kStartTolerance x (the triangle's and the origin's coordinates) of it, judged by the
//    double-precision distance across the plane (not along the ray, which a grazing angle
//    stretches without bound); a sphere's root nearest zero when the origin lies within that
//    tolerance of the sphere (radius, centre and origin coordinates).
//  - Each hit carries epsilon, kSpawnOffset x the same scale at the hit: an error bound of its
//    position across the surface with a wide margin, by which spawned rays leave it.
//  - Embree's float test starts at tnear = kFloatStart x the origin's float coordinates (its own
//    rounding), so most float self-hits never come back; the rest are refined and skipped above.
// Triangles are resolved to Embree's float precision about the centre of the triangles' bounds
// (spheres are not in Embree and do not move that centre); spheres to double precision.
#include "scene/surfaces/surfaces.h"
#include "scene/surfaces/offsets.h"
#include "scene/surfaces/coplanar_contact.h"

#include <atomic>
#include <cfloat>
#include <cmath>
#include <map>
#include <mutex>
#include <sstream>

#include <embree3/rtcore.h>

#include "core/error.h"
#include "io/mesh_io.h"
#include "config/transform_params.h"
#include "scene/materials/material.h"
#include "scene/materials/material_registry.h"

namespace vpm {
namespace {

std::atomic<size_t> g_devices_created{0};

struct ErrorLog {
    std::mutex mutex;
    std::string first;
    size_t count = 0;
};

void embree_error(void* user, RTCError code, const char* str) {
    auto* log = static_cast<ErrorLog*>(user);
    std::lock_guard<std::mutex> lock(log->mutex);
    if (log->count++ == 0) log->first = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (str ? str : "");
}

struct Geometry {
    std::string type;
    std::vector<Vec3> vertices;   // world space, double
    std::vector<std::array<uint32_t, 3>> triangles;
    Rgb reflectance = Rgb::Zero();
    std::shared_ptr<const Material> material;
    const Material* specular = nullptr;   // material.get() when it is specular
    // type = "sphere": no triangles.
    Vec3 center = Vec3::Zero();
    double radius = 0.0;
    int dielectric = -1;   // index among the closed dielectric shapes (SurfaceHit::dielectric)
    size_t table = 0;      // its [[shapes]] table
};

// Whether the ray from o along d crosses triangle (a, b, c) at t > 0 (Moller-Trumbore, in double).
bool ray_crosses(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 e1 = b - a, e2 = c - a, pv = d.cross(e2);
    const double det = e1.dot(pv);
    if (std::abs(det) < 1e-300) return false;
    const Vec3 tv = o - a;
    const double u = tv.dot(pv) / det;
    if (u < 0.0 || u > 1.0) return false;
    const Vec3 qv = tv.cross(e1);
    const double v = d.dot(qv) / det;
    if (v < 0.0 || u + v > 1.0) return false;
    return e2.dot(qv) / det > 0.0;
}

// A dielectric's mesh must enclose a volume with a known inside: every edge shared by exactly two
// triangles that run through it in opposite directions. Each closed part (connected by edges) is
// turned so that its triangles face out of the glass: a part inside an even number of the others
// (0: a solid, the outside of a shell) winds outwards (positive volume), one inside an odd number
// (a shell's cavity) inwards. Which part holds which is read by ray parity from one of its vertices.
void orient_closed_mesh(TriangleMesh& mesh, const Params& p, const std::string& type) {
    const std::string why = "material = \"dielectric\" needs a closed, consistently oriented " + type +
                            " (which side is glass is read from it): ";
    std::map<std::array<double, 3>, uint32_t> welded;
    std::vector<uint32_t> id(mesh.vertices.size());
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
        const Vec3& v = mesh.vertices[i];
        id[i] = welded.emplace(std::array<double, 3>{v.x(), v.y(), v.z()}, uint32_t(welded.size())).first->second;
    }
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (const auto& t : mesh.triangles)
        for (int e = 0; e < 3; ++e) ++directed[{id[t[e]], id[t[(e + 1) % 3]]}];
    for (const auto& [edge, n] : directed) {
        const auto back = directed.find({edge.second, edge.first});
        if (n != 1 || back == directed.end() || back->second != 1)
            p.fail("material", why + "an edge is used by " + std::to_string(n) + " triangle(s) one way and " +
                                   std::to_string(back == directed.end() ? 0 : back->second) + " the other");
    }
    // The closed parts: triangles joined by shared (welded) vertices.
    std::vector<uint32_t> parent(welded.size());
    for (uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
    auto root = [&](uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    for (const auto& t : mesh.triangles)
        for (int e = 1; e < 3; ++e) parent[root(id[t[e]])] = root(id[t[0]]);
    std::map<uint32_t, size_t> part_of_root;
    std::vector<size_t> part(mesh.triangles.size());
    for (size_t i = 0; i < mesh.triangles.size(); ++i)
        part[i] = part_of_root.emplace(root(id[mesh.triangles[i][0]]), part_of_root.size()).first->second;
    const size_t parts = part_of_root.size();
    std::vector<double> volume(parts, 0.0);
    std::vector<Vec3> probe(parts);
    for (size_t i = 0; i < mesh.triangles.size(); ++i) {
        const auto& t = mesh.triangles[i];
        volume[part[i]] += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
        probe[part[i]] = mesh.vertices[t[0]];
    }
    const Vec3 dir = Vec3(0.5773, 0.6129, 0.5397).normalized();   // off every axis and diagonal
    for (size_t a = 0; a < parts; ++a) {
        if (!(std::abs(volume[a]) > 0.0)) p.fail("material", why + "a closed part of the mesh encloses no volume");
        int depth = 0;   // the other parts that contain part a
        for (size_t b = 0; b < parts; ++b) {
            if (b == a) continue;
            int crossings = 0;
            for (size_t i = 0; i < mesh.triangles.size(); ++i) {
                const auto& t = mesh.triangles[i];
                if (part[i] == b && ray_crosses(probe[a], dir, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]))
                    ++crossings;
            }
            depth += crossings % 2;
        }
        const bool outwards = depth % 2 == 0;
        if ((volume[a] > 0.0) != outwards)
            for (size_t i = 0; i < mesh.triangles.size(); ++i)
                if (part[i] == a) std::swap(mesh.triangles[i][1], mesh.triangles[i][2]);
    }
}

Geometry read_shape(Params& p) {
    Geometry g;
    g.type = p.choice("type", {"mesh", "quad", "box", "sphere"});
    if (g.type == "sphere") {
        g.center = p.vec3("center");
        g.radius = p.real("radius", Range::positive());
        if (!std::isfinite(g.radius)) p.fail("radius", "must be finite");
        if (p.has("transform")) p.fail("transform", "a sphere takes center and radius, not a transform");
        g.material = make_material(p);
        g.reflectance = g.material->diffuse_reflectance();
        if (g.material->specular()) g.specular = g.material.get();
        p.finish();
        return g;
    }
    TriangleMesh mesh;
    if (g.type == "mesh") {
        mesh = load_mesh(p.path("file").string());
    } else if (g.type == "quad") {
        const Vec3 c = p.vec3("center"), u = p.vec3("u"), v = p.vec3("v");
        if (!(u.cross(v).norm() > 0.0)) p.fail("v", "u and v must be non-zero and not parallel");
        mesh.vertices = {c - u - v, c + u - v, c + u + v, c - u + v};
        mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    } else {
        const Vec3 lo = p.vec3("min"), hi = p.vec3("max");
        if (!(lo.array() < hi.array()).all())
            p.fail("max", "must exceed " + p.path_of("min") + " (" + p.where("min") + ") in every axis");
        for (int i = 0; i < 8; ++i)
            mesh.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
        // Outward winding (normals are recomputed and flipped per query anyway).
        const uint32_t faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                      {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
        for (const auto& f : faces) {
            mesh.triangles.push_back({f[0], f[1], f[2]});
            mesh.triangles.push_back({f[0], f[2], f[3]});
        }
    }
    if (p.has("transform")) {
        Params tp = p.table("transform");
        const Eigen::Affine3d m = read_transform(tp);
        tp.finish();
        for (Vec3& v : mesh.vertices) v = m * v;
    }
    g.material = make_material(p);
    g.reflectance = g.material->diffuse_reflectance();
    if (g.material->specular()) g.specular = g.material.get();
    if (g.material->needs_closed_shape()) {
        if (g.type == "quad") p.fail("material", "material = \"" + g.material->name() + "\" needs a closed shape (box, sphere or closed mesh); a quad is open");
        orient_closed_mesh(mesh, p, g.type);
    }
    p.finish();
    g.vertices = std::move(mesh.vertices);
    g.triangles = std::move(mesh.triangles);
    return g;
}

class EmbreeSurfaces final : public Surfaces {
public:
    explicit EmbreeSurfaces(std::vector<Geometry> shapes) {
        size_t table = 0;
        for (Geometry& g : shapes) {
            ++counts_[g.type];
            const size_t this_table = table++;
            g.table = this_table;
            if (g.material->needs_closed_shape()) {
                g.dielectric = int(dielectrics_.size());
                DielectricShape d;
                d.sphere = g.type == "sphere";
                d.center = g.center;
                d.radius = g.radius;
                d.table = this_table;
                if (d.sphere) {
                    d.bounds.extend(g.center - Vec3::Constant(g.radius));
                    d.bounds.extend(g.center + Vec3::Constant(g.radius));
                }
                for (const Vec3& v : g.vertices) d.bounds.extend(v);
                dielectrics_.push_back(d);
            }
            if (g.type == "sphere") {
                bounds_.extend(g.center - Vec3::Constant(g.radius));
                bounds_.extend(g.center + Vec3::Constant(g.radius));
                spheres_.push_back(std::move(g));
                continue;
            }
            for (const Vec3& v : g.vertices) bounds_.extend(v);
            triangles_ += g.triangles.size();
            geoms_.push_back(std::move(g));
        }
        if (geoms_.empty() && spheres_.empty()) return;   // no shapes
        const double half = 0.5 * (bounds_.hi - bounds_.lo).maxCoeff();
        far_ = 1e6 * std::max(half, 1e-9);
        if (geoms_.empty()) return;   // spheres only: no Embree device
        Bounds3 triangles;
        for (const Geometry& g : geoms_)
            for (const Vec3& v : g.vertices) triangles.extend(v);
        center_ = 0.5 * (triangles.lo + triangles.hi);

        device_ = rtcNewDevice(nullptr);
        if (!device_)
            throw Error("cannot create an Embree device (error " +
                        std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
        ++g_devices_created;
        rtcSetDeviceErrorFunction(device_, embree_error, &log_);
        scene_ = rtcNewScene(device_);
        rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
        for (size_t id = 0; id < geoms_.size(); ++id) {
            const Geometry& g = geoms_[id];
            RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
            auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
                geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), g.vertices.size()));
            auto* ib = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
                geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), g.triangles.size()));
            if (!vb || !ib) {
                rtcReleaseGeometry(geom);
                fail_on_error("allocating geometry buffers");
            }
            for (size_t i = 0; i < g.vertices.size(); ++i)
                for (int c = 0; c < 3; ++c) vb[3 * i + c] = static_cast<float>(g.vertices[i][c] - center_[c]);
            for (size_t i = 0; i < g.triangles.size(); ++i)
                for (int c = 0; c < 3; ++c) ib[3 * i + c] = g.triangles[i][c];
            rtcCommitGeometry(geom);
            rtcAttachGeometryByID(scene_, geom, static_cast<unsigned>(id));
            rtcReleaseGeometry(geom);
        }
        rtcCommitScene(scene_);
        fail_on_error("building the scene");
    }

    ~EmbreeSurfaces() override {
        if (scene_) rtcReleaseScene(scene_);
        if (device_) rtcReleaseDevice(device_);
    }

    bool intersect(const Ray& ray, double tmax, SurfaceHit& hit) const override {
        if ((!scene_ && spheres_.empty()) || !(tmax > 0.0)) return false;
        if (is_far(ray)) {
            Ray near;
            double shift;
            if (!move_near(ray, tmax, near, shift)) return false;
            if (!intersect(near, tmax - shift, hit)) return false;
            hit.t += shift;   // hit.position is near's, accurate
            return true;
        }
        bool found = scene_ && intersect_triangles(ray, tmax, hit);
        if (!spheres_.empty()) found = intersect_spheres(ray, found ? hit.t : tmax, hit) || found;
        return found;
    }

    // Embree's any-hit query; its positives are confirmed by intersect() so that the two agree
    // (a grazing self-hit must not shadow). Unoccluded rays, the common case, cost one query.
    bool occluded(const Ray& ray, double tmax) const override {
        if ((!scene_ && spheres_.empty()) || !(tmax > 0.0)) return false;
        if (is_far(ray)) {
            Ray near;
            double shift;
            return move_near(ray, tmax, near, shift) && occluded(near, tmax - shift);
        }
        for (const Geometry& s : spheres_) {
            double t;
            if (sphere_hit(s, ray, tmax, t)) return true;
        }
        if (!scene_) return false;
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        RTCRay r;
        setup(ray, tmax, r);
        rtcOccluded1(scene_, &ctx, &r);
        if (!(r.tfar < 0.0f)) return false;   // tfar is set to -inf on a hit
        SurfaceHit h;
        return intersect(ray, tmax, h);
    }

    Bounds3 bounds() const override { return bounds_; }
    size_t triangle_count() const override { return triangles_; }
    const std::vector<DielectricShape>& dielectric_shapes() const override { return dielectrics_; }
    bool has_specular() const override {
        for (const auto* list : {&geoms_, &spheres_})
            for (const Geometry& g : *list)
                if (g.specular) return true;
        return false;
    }

    std::vector<std::pair<size_t, size_t>> coplanar_glass_contacts() const override {
        std::vector<std::pair<size_t, size_t>> contacts;
        for (const Geometry& glass : geoms_) {
            if (glass.dielectric < 0) continue;
            for (const Geometry& other : geoms_)
                if (&other != &glass && touch_in_a_plane({glass.vertices, glass.triangles}, {other.vertices, other.triangles}))
                    contacts.emplace_back(glass.table, other.table);
        }
        return contacts;
    }

    std::string describe() const override {
        std::ostringstream s;
        s << "surfaces: " << geoms_.size() + spheres_.size() << " shape" << (geoms_.size() + spheres_.size() == 1 ? "" : "s");
        if (!counts_.empty()) {
            s << " (";
            bool first = true;
            for (const auto& [type, n] : counts_) {
                s << (first ? "" : ", ") << n << " " << type;
                first = false;
            }
            s << ")";
        }
        s << ", " << triangles_ << " triangles";
        if (!geoms_.empty() || !spheres_.empty()) {
            s << ", bounds [" << bounds_.lo.x() << ", " << bounds_.lo.y() << ", " << bounds_.lo.z() << "] to ["
              << bounds_.hi.x() << ", " << bounds_.hi.y() << ", " << bounds_.hi.z() << "]";
            if (!geoms_.empty()) s << ", Embree " << RTC_VERSION_STRING;
            else s << ", no Embree device (spheres only)";
        } else {
            s << ", no Embree device";
        }
        std::map<std::string, size_t> materials;
        for (const auto* list : {&geoms_, &spheres_})
            for (const Geometry& g : *list)
                if (g.material->name() != "lambertian" && g.material->name() != "black") ++materials[g.material->describe()];
        for (const auto& [m, n] : materials) s << "; " << n << " x " << m;
        return s.str();
    }

private:
    bool intersect_triangles(const Ray& ray, double tmax, SurfaceHit& hit) const {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        RTCRayHit rh;
        setup(ray, tmax, rh.ray);
        // A hit that the double-precision plane test puts at t <= epsilon is the surface the ray
        // starts on, found by Embree's float test at a grazing angle: skip it and trace on.
        for (int attempt = 0; attempt < 4; ++attempt) {
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene_, &ctx, &rh);
            if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;

            const Geometry& g = geoms_[rh.hit.geomID];
            const auto& tri = g.triangles[rh.hit.primID];
            const Vec3& a = g.vertices[tri[0]];
            const Vec3& b = g.vertices[tri[1]];
            const Vec3& c = g.vertices[tri[2]];
            Vec3 n = (b - a).cross(c - a);
            const double len = n.norm();
            if (len > 0.0 && std::isfinite(len)) n /= len;
            else n = Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();   // degenerate in double
            const double scale = std::max({magnitude(a), magnitude(b), magnitude(c)}) + magnitude(ray.origin);
            const double cos = n.dot(ray.dir);
            const double across = n.dot(a - ray.origin);   // signed distance from the origin to the plane
            if ((cos >= 0.0 ? across : -across) <= kStartTolerance * scale) {
                // Behind the origin or within rounding of it: the surface the ray starts on (or one
                // coincident with it), found by Embree's float test. Skip it and trace on.
                rh.ray.tnear = std::nextafter(rh.ray.tfar, INFINITY);
                rh.ray.tfar = float_tmax(tmax);
                if (!(rh.ray.tnear < rh.ray.tfar)) return false;
                continue;
            }
            double t = rh.ray.tfar;
            if (std::abs(cos) > 1e-12) {   // refine the float distance against the double plane
                t = across / cos;
                if (t >= tmax) return false;   // Embree's float tfar let it in; nothing is closer
            }
            hit.t = t;
            hit.position = ray.at(t);
            hit.normal = cos > 0.0 ? Vec3(-n) : n;
            hit.reflectance = g.reflectance;
            hit.specular = g.specular;
            hit.dielectric = g.dielectric;
            hit.exiting = cos > 0.0;   // along the outward winding (dielectric meshes are oriented so)
            hit.epsilon = kSpawnOffset * (scale + magnitude(hit.position));
            return true;
        }
        return false;
    }

    // The nearest root of |o + t d - c| = r in (0, tmax), in double. The roots come from the
    // ray's closest approach (no cancellation of |o - c|^2 against r^2 far from the sphere) and the
    // stable quadratic form. A ray whose origin lies on the sphere (within kStartTolerance of the
    // sphere's and the origin's coordinates) starts on it: the root nearest zero is that start.
    static bool sphere_hit(const Geometry& s, const Ray& ray, double tmax, double& t) {
        const Vec3 oc = ray.origin - s.center;
        const double a = ray.dir.squaredNorm();
        const double b = oc.dot(ray.dir);
        const Vec3 h = oc - (b / a) * ray.dir;
        const double disc = s.radius * s.radius - h.squaredNorm();
        if (!(disc >= 0.0)) return false;
        const double q = -(b + std::copysign(std::sqrt(a * disc), b));
        if (q == 0.0) return false;
        const double dist = oc.norm();
        const double c = (dist - s.radius) * (dist + s.radius);
        double t0 = c / q, t1 = q / a;
        if (t0 > t1) std::swap(t0, t1);
        const double scale = magnitude(s.center) + s.radius + magnitude(ray.origin);
        if (std::abs(dist - s.radius) <= kStartTolerance * scale)
            t = std::abs(t0) < std::abs(t1) ? t1 : t0;   // the other root than the start
        else
            t = t0 > 0.0 ? t0 : t1;
        return t > 0.0 && t < tmax;
    }

    bool intersect_spheres(const Ray& ray, double tmax, SurfaceHit& hit) const {
        const Geometry* best = nullptr;
        double best_t = tmax;
        for (const Geometry& s : spheres_) {
            double t;
            if (sphere_hit(s, ray, best_t, t)) {
                best = &s;
                best_t = t;
            }
        }
        if (!best) return false;
        const Vec3 outward = (ray.at(best_t) - best->center).normalized();
        const double cos = outward.dot(ray.dir);
        hit = SurfaceHit{};
        hit.t = best_t;
        hit.position = best->center + best->radius * outward;
        hit.normal = cos > 0.0 ? Vec3(-outward) : outward;
        hit.reflectance = best->reflectance;
        hit.specular = best->specular;
        hit.dielectric = best->dielectric;
        hit.exiting = cos > 0.0;
        hit.epsilon = kSpawnOffset * (magnitude(best->center) + best->radius);
        return true;
    }

    // Rays that start far from the surfaces (more than 1e6 x their half extent: photons emitted
    // around a medium of 1e32 units, paths inside it) would reach Embree with float origins
    // beyond its valid range (|org| <= ~1.8e18, asserted by the library) or with no precision
    // left. They are first advanced in double to just outside the surfaces' bounds (backed off by
    // the bounds' size, so no surface is near the new origin) and traced from there.
    // The new origin is rounded like any point at that distance (relative 1e-16), nothing more.
    // Each step shrinks the distance by ~1e15, so at most a few steps are taken.
    bool is_far(const Ray& ray) const { return !((ray.origin - center_).cwiseAbs().maxCoeff() <= far_); }
    bool move_near(const Ray& ray, double tmax, Ray& near, double& shift) const {
        double t0, t1;
        if (!bounds_.intersect(ray, tmax, t0, t1)) return false;
        // Also back off by several units of rounding of t0 (the new origin is computed from it),
        // so that it lies before the bounds; if it is still far, intersect() repeats the step.
        const double back = 2.0 * (bounds_.hi - bounds_.lo).norm() + 16.0 * DBL_EPSILON * t0;
        shift = std::max(0.0, t0 - back);
        near = Ray{ray.at(shift), ray.dir};
        return tmax - shift > 0.0;
    }

    void setup(const Ray& ray, double tmax, RTCRay& r) const {
        r.org_x = static_cast<float>(ray.origin.x() - center_.x());
        r.org_y = static_cast<float>(ray.origin.y() - center_.y());
        r.org_z = static_cast<float>(ray.origin.z() - center_.z());
        r.dir_x = static_cast<float>(ray.dir.x());
        r.dir_y = static_cast<float>(ray.dir.y());
        r.dir_z = static_cast<float>(ray.dir.z());
        r.tnear = static_cast<float>(kFloatStart * magnitude(ray.origin - center_) / ray.dir.norm());
        r.tfar = float_tmax(tmax);
        r.time = 0.0f;
        r.mask = 0xFFFFFFFFu;
        r.id = 0;
        r.flags = 0;
    }

    static float float_tmax(double tmax) {
        float tf = tmax >= static_cast<double>(FLT_MAX) ? INFINITY : static_cast<float>(tmax);
        if (static_cast<double>(tf) > tmax) tf = std::nextafter(tf, 0.0f);   // never beyond tmax
        return tf;
    }

    void fail_on_error(const std::string& what) {
        const RTCError code = rtcGetDeviceError(device_);
        std::lock_guard<std::mutex> lock(log_.mutex);
        if (log_.count == 0 && code == RTC_ERROR_NONE) return;
        std::string msg = log_.count ? log_.first : "Embree error " + std::to_string(static_cast<int>(code));
        if (scene_) rtcReleaseScene(scene_);
        if (device_) rtcReleaseDevice(device_);
        scene_ = nullptr;
        device_ = nullptr;
        throw Error("surfaces: " + what + ": " + msg);
    }

    std::vector<Geometry> geoms_;     // triangle meshes, by Embree geometry id
    std::vector<Geometry> spheres_;   // analytic spheres
    std::vector<DielectricShape> dielectrics_;   // SurfaceHit::dielectric indexes it
    std::map<std::string, size_t> counts_;
    Bounds3 bounds_;
    size_t triangles_ = 0;
    Vec3 center_ = Vec3::Zero();
    double far_ = 0.0;   // see is_far
    ErrorLog log_;
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
};

}  // namespace

std::unique_ptr<Surfaces> Surfaces::create(std::vector<Params>& shapes) {
    std::vector<Geometry> geoms;
    geoms.reserve(shapes.size());
    size_t dielectrics = 0;
    for (Params& p : shapes) {   // all config errors before Embree
        geoms.push_back(read_shape(p));
        if (geoms.back().material->needs_closed_shape() && ++dielectrics > kMaxDielectricShapes)
            p.fail("material", "at most " + std::to_string(kMaxDielectricShapes) +
                                   " closed dielectric shapes per scene (each is one bit of a photon's region, "
                                   "scene/dielectric_regions.h)");
    }
    return std::make_unique<EmbreeSurfaces>(std::move(geoms));
}

size_t Surfaces::devices_created() { return g_devices_created.load(); }

}  // namespace vpm
