#include "analysis/scene_info.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "analysis/density_extent.h"
#include "config/params.h"
#include "core/error.h"
#include "io/vdb_io.h"
#include "scene/media/grid_medium.h"
#include "scene/media/homogeneous_medium.h"

namespace vpm {

namespace {

nlohmann::json vec(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
nlohmann::json rgb(const Rgb& v) { return {v[0], v[1], v[2]}; }

nlohmann::json box(const Bounds3& b) {
    if (b.empty()) return nullptr;
    return {{"lo", vec(b.lo)}, {"hi", vec(b.hi)}, {"size", vec(b.hi - b.lo)}};
}

// The integral of sigma_t along the axis line through the box's centre, face to face.
Vec3 tau_across(const Medium& m) {
    const Bounds3 b = m.bounds();
    Vec3 tau = Vec3::Zero();
    if (b.empty()) return tau;
    const Vec3 c = 0.5 * (b.lo + b.hi);
    for (int a = 0; a < 3; ++a) {
        const double len = b.hi[a] - b.lo[a], step = len / kTauSteps;
        double sum = 0.0;
        for (int i = 0; i < kTauSteps; ++i) {
            Vec3 p = c;
            p[a] = b.lo[a] + (i + 0.5) * step;
            sum += m.sigma_t(p);
        }
        tau[a] = sum * step;
    }
    return tau;
}

// Voxel edge lengths in world units: the columns of the index-to-world linear part.
Vec3 voxel_size(const Eigen::Affine3d& index_to_world) {
    const Eigen::Matrix3d l = index_to_world.linear();
    return {l.col(0).norm(), l.col(1).norm(), l.col(2).norm()};
}

nlohmann::json grid_json(const DensityGrid& g, const Eigen::Affine3d& index_to_world) {
    Bounds3 world;
    if (!g.empty()) {
        const Bounds3& ib = g.index_bounds();
        for (int corner = 0; corner < 8; ++corner) {
            const Vec3 p((corner & 1) ? ib.hi.x() : ib.lo.x(), (corner & 2) ? ib.hi.y() : ib.lo.y(),
                         (corner & 4) ? ib.hi.z() : ib.lo.z());
            world.extend(index_to_world * p);
        }
    }
    return {{"name", g.name()},
            {"voxel_lo", {g.voxel_lo().x(), g.voxel_lo().y(), g.voxel_lo().z()}},
            {"voxel_hi", {g.voxel_hi().x(), g.voxel_hi().y(), g.voxel_hi().z()}},
            {"voxel_size", vec(voxel_size(index_to_world))},
            {"world_bounds", box(world)},
            {"active_voxels", g.active_voxel_count()},
            {"density_min", g.min_density()},
            {"density_max", g.max_density()},
            {"memory_bytes", g.memory_bytes()}};
}

nlohmann::json medium_json(const Medium& m) {
    nlohmann::json j = {{"describe", m.describe()}, {"bounds", box(m.bounds())}, {"albedo", rgb(m.albedo())},
                        {"g", m.g()}, {"tau_across", vec(tau_across(m))}};
    if (const auto* grid = dynamic_cast<const GridMedium*>(&m)) {
        j["type"] = "grid";
        j["grid"] = grid_json(grid->grid(), grid->index_to_world());
        j["sigma_t_scale"] = grid->sigma_t_scale();
        j["sigma_t_max"] = grid->sigma_t_scale() * grid->grid().max_density();
    } else if (dynamic_cast<const HomogeneousMedium*>(&m)) {
        j["type"] = "homogeneous";
        const Bounds3 b = m.bounds();
        j["sigma_t_max"] = b.empty() ? 0.0 : m.sigma_t(0.5 * (b.lo + b.hi));
    }
    return j;
}

// Fractions of the sampled primary rays that meet a medium first... (see the header).
nlohmann::json seen(const Scene& scene, int width, int height) {
    const int nx = std::min(width, kSeenSide), ny = std::min(height, kSeenSide);
    size_t medium = 0, surface = 0, nothing = 0, surface_behind_medium = 0;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const double x = (i + 0.5) * width / nx, y = (j + 0.5) * height / ny;
            const Ray ray = scene.camera.generate_ray(x, y);
            SurfaceHit hit;
            const bool hits = scene.intersect(ray, kInfinity, hit);
            const double depth = scene.has_media() ? scene.optical_depth(ray, hits ? hit.t : kInfinity) : 0.0;
            if (depth > 0.0) {
                ++medium;
                surface_behind_medium += hits;
            } else if (hits) {
                ++surface;
            } else {
                ++nothing;
            }
        }
    const double n = double(nx) * double(ny);
    return {{"rays", nx * ny},
            {"medium", double(medium) / n},
            {"surface_behind_medium", double(surface_behind_medium) / n},
            {"surface_only", double(surface) / n},
            {"nothing", double(nothing) / n}};
}

std::string fmt(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

std::string triple(const nlohmann::json& v) {
    if (!v.is_array()) return "-";
    std::string s = "(";
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + fmt(v[i].get<double>());
    return s + ")";
}

std::string box_text(const nlohmann::json& b) {
    if (b.is_null()) return "empty";
    return triple(b["lo"]) + " .. " + triple(b["hi"]) + ", size " + triple(b["size"]);
}

std::string percent(double f) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f%%", 100.0 * f);
    return buf;
}

void grid_text(std::ostringstream& out, const nlohmann::json& g, const std::string& indent) {
    out << indent << "index box " << g["voxel_lo"].dump() << " .. " << g["voxel_hi"].dump() << ", voxel size "
        << triple(g["voxel_size"]) << "\n"
        << indent << "world bounds " << box_text(g["world_bounds"]) << "\n"
        << indent << g["active_voxels"].get<int64_t>() << " active voxels, density " << fmt(g["density_min"].get<double>())
        << " .. " << fmt(g["density_max"].get<double>()) << ", " << fmt(g["memory_bytes"].get<double>() / 1e6) << " MB\n";
}

}  // namespace

nlohmann::json scene_info(const RunConfig& config) {
    const Scene& scene = *config.scene;
    const RenderSettings& rs = config.render;
    nlohmann::json j;
    j["kind"] = "scene";
    j["source"] = config.source_file;
    j["image"] = {{"width", rs.width}, {"height", rs.height}, {"spp", rs.spp}, {"integrator", config.integrator->name}};
    j["world_bounds"] = box(scene.bounds);
    j["media"] = nlohmann::json::array();
    for (const auto& m : scene.media) j["media"].push_back(medium_json(*m));
    j["lights"] = nlohmann::json::array();
    for (const auto& l : scene.lights) j["lights"].push_back({{"describe", l->describe()}, {"power", rgb(l->power())}});
    j["total_light_power"] = rgb(scene.total_light_power());
    if (scene.surfaces)
        j["shapes"] = {{"describe", scene.surfaces->describe()}, {"triangles", scene.surfaces->triangle_count()}};
    else
        j["shapes"] = nullptr;
    // The resolved [camera] keys: numbers and lists of numbers (position, look_at, up, fov).
    nlohmann::json settings = nlohmann::json::object();
    if (const auto* cam = config.resolved.get_as<toml::table>("camera"))
        for (const auto& [key, node] : *cam) {
            if (const auto v = node.value<double>()) settings[std::string(key.str())] = *v;
            else if (const auto* a = node.as_array()) {
                nlohmann::json list = nlohmann::json::array();
                for (const auto& x : *a) list.push_back(x.value<double>().value_or(0.0));
                settings[std::string(key.str())] = list;
            }
        }
    j["camera"] = {{"settings", settings}, {"seen", seen(scene, rs.width, rs.height)}};
    return j;
}

nlohmann::json vdb_info(const std::string& path) {
    nlohmann::json j;
    j["kind"] = "vdb";
    j["source"] = path;
    j["grids"] = nlohmann::json::array();
    Bounds3 all, all_mass;
    for (const VdbGridInfo& g : list_vdb_grids(path)) {
        nlohmann::json e = {{"name", g.name}, {"type", g.type}};
        if (g.type == "float" || g.type == "double") {
            const DensityGrid grid = load_vdb_density(path, g.name);
            e.update(grid_json(grid, grid.index_to_world()));
            const GridMedium unit(grid, 1.0, Rgb::Ones(), 0.0);
            e["tau_across_at_scale_1"] = vec(tau_across(unit));
            if (!unit.bounds().empty()) all.extend(unit.bounds());
            const DensityExtent x = density_extent(grid);
            e["nonzero_voxels"] = x.nonzero_voxels;
            e["density_bounds"] = box(x.nonzero);
            e["mass_bounds"] = box(x.mass);
            e["mass_inside"] = x.mass_inside;
            if (!x.mass.empty()) all_mass.extend(x.mass);
        }
        j["grids"].push_back(e);
    }
    if (!all_mass.empty() || !all.empty()) {
        // A camera on +z of the centre of where the density is (the grids' mass boxes; their boxes
        // when all are 0) whose vertical field of view (40 degrees) holds that box's bounding sphere.
        const Bounds3 framed = all_mass.empty() ? all : all_mass;
        j["suggested_camera_frames"] = all_mass.empty() ? "the grids' boxes (no density)" : "the density (mass bounds)";
        all = framed;
        const Vec3 c = 0.5 * (all.lo + all.hi);
        const double r = 0.5 * (all.hi - all.lo).norm(), fov = 40.0;
        const double d = r / std::sin(0.5 * fov * kPi / 180.0);
        j["suggested_camera"] = {{"position", vec(c + Vec3(0.0, 0.0, d))}, {"look_at", vec(c)}, {"fov", fov}};
    }
    return j;
}

std::string info_text(const nlohmann::json& j) {
    std::ostringstream out;
    out << j["source"].get<std::string>() << "\n";
    if (j["kind"] == "vdb") {
        for (const auto& g : j["grids"]) {
            out << "grid \"" << g["name"].get<std::string>() << "\" (" << g["type"].get<std::string>() << ")";
            if (!g.contains("active_voxels")) {
                out << ": not a density grid (vpm reads float and double grids)\n";
                continue;
            }
            out << "\n";
            grid_text(out, g, "  ");
            out << "  optical thickness across the centre (x, y, z) at sigma_t_scale = 1: "
                << triple(g["tau_across_at_scale_1"]) << "\n";
            if (g.contains("density_bounds"))
                out << "  where the density is: " << g["nonzero_voxels"].get<int64_t>() << " voxels > 0 in "
                    << box_text(g["density_bounds"]) << "\n  " << percent(g["mass_inside"].get<double>())
                    << " of the density in " << box_text(g["mass_bounds"]) << "\n";
        }
        if (j.contains("suggested_camera")) {
            const auto& c = j["suggested_camera"];
            auto list = [](const nlohmann::json& v) {
                std::string t = triple(v);
                return "[" + t.substr(1, t.size() - 2) + "]";
            };
            out << "suggested camera (" << j.value("suggested_camera_frames", std::string("the grids' boxes"))
                << " in view):\n  [camera]\n  position = "
                << list(c["position"]) << "\n  look_at = " << list(c["look_at"]) << "\n  fov = " << fmt(c["fov"].get<double>())
                << "\n";
        }
        return out.str();
    }
    const auto& im = j["image"];
    out << "image " << im["width"].get<int>() << "x" << im["height"].get<int>() << ", " << im["spp"].get<int>()
        << " spp, integrator " << im["integrator"].get<std::string>() << "\n"
        << "world bounds " << box_text(j["world_bounds"]) << "\n"
        << "media: " << j["media"].size() << "\n";
    for (size_t i = 0; i < j["media"].size(); ++i) {
        const auto& m = j["media"][i];
        out << "  " << i << ": " << m["describe"].get<std::string>() << "\n"
            << "     bounds " << box_text(m["bounds"]) << "\n";
        if (m.contains("grid")) grid_text(out, m["grid"], "     ");
        if (m.contains("sigma_t_max")) out << "     sigma_t max " << fmt(m["sigma_t_max"].get<double>());
        out << ", albedo " << triple(m["albedo"]) << ", g " << fmt(m["g"].get<double>()) << "\n"
            << "     optical thickness across the centre (x, y, z): " << triple(m["tau_across"]) << "\n";
    }
    out << "lights: " << j["lights"].size() << ", total power into the scene " << triple(j["total_light_power"]) << " W\n";
    for (const auto& l : j["lights"])
        out << "  " << l["describe"].get<std::string>() << "; power " << triple(l["power"]) << "\n";
    if (j["shapes"].is_null()) out << "shapes: none\n";
    else out << "shapes: " << j["shapes"]["describe"].get<std::string>() << "\n";
    out << "camera:";
    for (const auto& [key, v] : j["camera"]["settings"].items())
        out << " " << key << " " << (v.is_array() ? triple(v) : v.is_number() ? fmt(v.get<double>()) : v.dump());
    out << "\n";
    const auto& s = j["camera"]["seen"];
    out << "camera sees (" << s["rays"].get<int>() << " pixel centres): a medium " << percent(s["medium"].get<double>())
        << " (a surface behind it " << percent(s["surface_behind_medium"].get<double>()) << "), a surface only "
        << percent(s["surface_only"].get<double>()) << ", nothing " << percent(s["nothing"].get<double>()) << "\n";
    return out.str();
}

}  // namespace vpm
