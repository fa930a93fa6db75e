// vpm.trace_photons and vpm.PhotonMap: the photon pass on its own (the same code and streams as a
// render's first pass, so the counts are the sidecar's), the stored photons as NumPy arrays, kNN
// queries and the in-scattered radiance estimate at arbitrary points.
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "bindings.h"
#include "config.h"
#include "native_call.h"
#include "core/progress.h"
#include "photon/estimate/estimators.h"
#include "photon/estimate/walk_estimate.h"
#include "photon/map/photon_map.h"
#include "photon/trace/photon_budget.h"
#include "render/photon_map/photon_map_integrator.h"
#include "render/photon_map/photon_pass.h"
#include "render/run/run_record.h"

namespace py = pybind11;

namespace vpm::python {

namespace {

using Points = py::array_t<double, py::array::c_style | py::array::forcecast>;

struct PyPhotonMap {
    std::shared_ptr<const PhotonMap> map;
    std::shared_ptr<const RunConfig> config;   // null for a map built from arrays
    std::string kind = "volume";               // "volume" or "surface"
    std::string stats_json = "{}";             // the photon pass's statistics (trace_photons)
    std::shared_ptr<PyPhotonMap> surface;      // the surface map, when the pass built one
};

// (n, 3) float64 rows checked against what a call needs; `what` names the argument in errors.
Points rows_of_three(const py::handle& h, const char* what) {
    Points a = Points::ensure(h);
    if (!a || a.ndim() != 2 || a.shape(1) != 3)
        throw Error(std::string(what) + ": expected an array of shape (n, 3)");
    return a;
}

// Row i of a direction array as a unit vector, or vpm::Error: zero, non-finite and unnormalised
// directions are refused alike (an estimate's phase function needs a unit direction).
Vec3 unit_direction(const Vec3& dir, size_t i, const char* what) {
    const double len = dir.norm();
    if (!(std::abs(len - 1.0) < 1e-6)) {
        std::ostringstream s;
        s << what << "[" << i << "] has length " << len << ", expected 1";
        throw Error(s.str());
    }
    return dir;
}

// Row i of a query array, or vpm::Error when it is not finite (no neighbour is nearest to NaN).
Vec3 finite_point(const double* row, size_t i, const char* what) {
    const Vec3 x(row[0], row[1], row[2]);
    if (!x.allFinite()) throw Error(std::string(what) + "[" + std::to_string(i) + "] is not finite");
    return x;
}

// The renderer's memory guard for maps built from arrays: the peak of storing n photons and
// building their kd-tree (photon_budget.h) must fit in half the machine's memory, the other half
// left to the caller's arrays and the interpreter.
void check_photon_map_memory(size_t n) {
    const double peak = double(n) * kPeakBytesPerStoredPhoton, limit = 0.5 * double(physical_memory_bytes());
    if (peak <= limit) return;
    std::ostringstream s;
    s.precision(3);
    s << "PhotonMap: " << double(n) << " photons need about " << peak / 1e9 << " GB while the kd-tree is built ("
      << kPeakBytesPerStoredPhoton << " bytes each), more than half of this machine's "
      << double(physical_memory_bytes()) / 1e9 << " GB; at most " << std::floor(limit / kPeakBytesPerStoredPhoton)
      << " photons fit";
    throw Error(s.str());
}

// The walk label of every row: `walks` (n,) non-negative integers, photons with equal labels one walk;
// None: every photon its own walk (independent points). The walk group is label mod kWalkGroups, as
// the tracer's.
void set_walks(std::vector<PhotonInput>& photons, const py::handle& walks) {
    if (walks.is_none()) {
        for (size_t i = 0; i < photons.size(); ++i) {
            photons[i].walk = i;
            photons[i].group = uint8_t(i % kWalkGroups);
        }
        return;
    }
    const py::array given = py::array::ensure(walks);
    if (!given || given.ndim() != 1 || size_t(given.shape(0)) != photons.size())
        throw Error("PhotonMap: walks: expected an integer array of shape (" + std::to_string(photons.size()) +
                    ",) (one walk label per photon) or None");
    const char kind = given.dtype().kind();
    if (kind != 'i' && kind != 'u')
        throw Error("PhotonMap: walks: expected integer labels, got dtype " + std::string(py::str(given.dtype())));
    const auto labels = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(given);
    if (kind == 'u' && given.dtype().itemsize() == 8) {   // uint64 above 2^63 would wrap to negative int64
        const auto raw = py::array_t<uint64_t, py::array::c_style>::ensure(given);
        for (size_t i = 0; i < photons.size(); ++i)
            if (raw.data()[i] > uint64_t(std::numeric_limits<int64_t>::max()))
                throw Error("PhotonMap: walks[" + std::to_string(i) + "] = " + std::to_string(raw.data()[i]) +
                            " is above 2^63 - 1");
    }
    for (size_t i = 0; i < photons.size(); ++i) {
        const int64_t label = labels.data()[i];
        if (label < 0)
            throw Error("PhotonMap: walks[" + std::to_string(i) + "] = " + std::to_string(label) +
                        " is negative (walk labels are non-negative integers)");
        photons[i].walk = uint64_t(label);
        photons[i].group = uint8_t(uint64_t(label) % kWalkGroups);
    }
}

std::vector<PhotonInput> photons_from_arrays(const py::handle& positions, const py::handle& powers,
                                             const py::handle& directions) {
    // Checked on the caller's array before the float64 copies below, which could not be made either.
    if (py::isinstance<py::array>(positions)) {
        const auto caller = py::reinterpret_borrow<py::array>(positions);
        if (caller.ndim() == 2) check_photon_map_memory(size_t(caller.shape(0)));
    }
    const Points p = rows_of_three(positions, "positions"), w = rows_of_three(powers, "powers"),
                 d = rows_of_three(directions, "directions");
    if (w.shape(0) != p.shape(0) || d.shape(0) != p.shape(0))
        throw Error("PhotonMap: positions, powers and directions must have the same number of rows (" +
                    std::to_string(p.shape(0)) + ", " + std::to_string(w.shape(0)) + ", " + std::to_string(d.shape(0)) + ")");
    check_photon_map_memory(size_t(p.shape(0)));
    std::vector<PhotonInput> out(size_t(p.shape(0)));
    auto pp = p.unchecked<2>();
    auto ww = w.unchecked<2>();
    auto dd = d.unchecked<2>();
    // The records hold positions as float32 offsets from the map's centre and powers as binary16
    // mantissas under a per-photon exponent: a coordinate beyond +-1e38 (offsets then pass float32's
    // 3.4e38) or a non-finite value would become an infinity silently.
    constexpr double kMaxCoordinate = 1e38;
    for (size_t i = 0; i < out.size(); ++i) {
        const auto r = py::ssize_t(i);
        out[i].position = Vec3(pp(r, 0), pp(r, 1), pp(r, 2));
        out[i].power = Rgb(ww(r, 0), ww(r, 1), ww(r, 2));
        if (!out[i].position.allFinite() || out[i].position.cwiseAbs().maxCoeff() > kMaxCoordinate) {
            std::ostringstream m;
            m << "PhotonMap: positions[" << i << "] = (" << out[i].position.transpose()
              << ") is not a finite point within +-1e38 (photon records store float32 offsets)";
            throw Error(m.str());
        }
        if (!out[i].power.allFinite()) {
            std::ostringstream m;
            m << "PhotonMap: powers[" << i << "] = (" << out[i].power.transpose() << ") is not finite";
            throw Error(m.str());
        }
        out[i].direction = unit_direction(Vec3(dd(r, 0), dd(r, 1), dd(r, 2)), i, "PhotonMap: directions");
    }
    return out;
}

// Integer arguments arrive as int64 so that a negative or huge value is a vpm.Error naming the
// argument and its range, not pybind's TypeError or a silent wrap.
int64_t checked_int(int64_t v, int64_t lo, int64_t hi, const char* what) {
    if (v < lo || v > hi)
        throw Error(std::string(what) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                    std::to_string(v));
    return v;
}
// photons.k's range (render/photon_map/photon_map_settings.cpp).
constexpr int64_t kMaxK = int64_t(1) << 20;

PyPhotonMap from_arrays(const py::handle& positions, const py::handle& powers, const py::handle& directions,
                        int64_t leaf_size, const py::handle& walks) {
    checked_int(leaf_size, 1, int64_t(1) << 30, "PhotonMap: leaf_size");
    std::vector<PhotonInput> photons = photons_from_arrays(positions, powers, directions);
    set_walks(photons, walks);
    PyPhotonMap m;
    call_native([&](const std::atomic<bool>&) { m.map = std::make_shared<const PhotonMap>(photons, size_t(leaf_size)); });
    return m;
}

PyPhotonMap trace(const Config& config, uint64_t stream_offset, std::optional<int> threads, bool progress, bool log) {
    if (threads) check_threads(*threads);
    const RunConfig& rc = *config.run;
    const PhotonMapSettings& settings = photon_map_settings(rc);
    const bool surface = rc.scene->uses_embree() && !settings.final_gather;
    PhotonMaps maps;
    RunStats stats;
    call_native(
        [&](const std::atomic<bool>&) {
            // The context of a run's first pass with render.first_pass = 0 (lib/render/run/run.cpp).
            PassContext context;
            context.seed = rc.render.seed;
            context.stream_offset = stream_offset;
            context.run_stream_offset = stream_offset;
            context.pass = 0;
            context.progress = progress;
            context.log = log ? &std::cerr : nullptr;
            std::optional<LightAllocation> allocation;
            if (rc.scene->has_media() || surface)
                maps = run_photon_pass(*rc.scene, settings, context, surface, stats, allocation);
        },
        threads ? *threads : rc.render.threads);   // 0: all cores
    RunRecord record;
    write_run_stats(stats, record);
    PyPhotonMap out;
    out.config = config.run;
    out.stats_json = record.dump();
    out.map = std::make_shared<const PhotonMap>(std::move(maps.volume));
    if (surface) {
        out.surface = std::make_shared<PyPhotonMap>();
        out.surface->config = config.run;
        out.surface->kind = "surface";
        out.surface->map = std::make_shared<const PhotonMap>(std::move(maps.surface));
    }
    return out;
}

// Decoded per-photon attributes as an (n, 3) float64 array (a copy: the records are compressed).
template <class Get>
py::array_t<double> attribute(const PhotonMap& map, Get get) {
    py::array_t<double> a({py::ssize_t(map.size()), py::ssize_t(3)});
    auto out = a.mutable_unchecked<2>();
    for (size_t i = 0; i < map.size(); ++i) {
        const auto v = get(i);
        for (int c = 0; c < 3; ++c) out(py::ssize_t(i), c) = double(v[c]);
    }
    return a;
}

double radius_or_infinity(std::optional<double> r, const char* what) {
    if (!r) return kInfinity;
    if (!(*r > 0.0)) throw Error(std::string(what) + ": expected a positive radius or None, got " + std::to_string(*r));
    return *r;
}

py::tuple knn(const PyPhotonMap& m, const py::handle& points, int64_t k_given, std::optional<double> max_radius) {
    const size_t k = size_t(checked_int(k_given, 1, kMaxK, "knn: k"));
    const Points q = rows_of_three(points, "points");
    const double radius = radius_or_infinity(max_radius, "max_radius");
    const py::ssize_t n = q.shape(0), kk = py::ssize_t(k);
    // The (m, k) distances and indices: 16 bytes a neighbour, refused beyond half of the memory.
    if (const double bytes = 16.0 * double(n) * double(kk); bytes > 0.5 * double(physical_memory_bytes())) {
        std::ostringstream msg;
        msg.precision(3);
        msg << "knn: " << double(n) << " points x k = " << kk << " need " << bytes / 1e9
            << " GB of results, more than half of this machine's " << double(physical_memory_bytes()) / 1e9 << " GB";
        throw Error(msg.str());
    }
    py::array_t<double> distances({n, kk});
    py::array_t<int64_t> indices({n, kk});
    const double* qp = q.data();
    double* dp = distances.mutable_data();
    int64_t* ip = indices.mutable_data();
    for (size_t i = 0; i < size_t(n); ++i) finite_point(qp + 3 * i, i, "knn: points");
    const PhotonMap& map = *m.map;
    call_native([&](const std::atomic<bool>&) {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, size_t(n), 64), [&](const tbb::blocked_range<size_t>& range) {
            NeighbourList list;
            for (size_t i = range.begin(); i != range.end(); ++i) {
                const size_t found = map.knn(Vec3(qp[3 * i], qp[3 * i + 1], qp[3 * i + 2]), k, radius, list);
                for (size_t j = 0; j < k; ++j) {   // missing neighbours (k > size, or beyond max_radius): inf, -1
                    dp[i * k + j] = j < found ? std::sqrt(list[j].d2) : kInfinity;
                    ip[i * k + j] = j < found ? int64_t(list[j].index) : -1;
                }
            }
        });
    });
    return py::make_tuple(distances, indices);
}

// The g every medium of the scene shares (the estimate's phase function), or an error asking for it.
double scene_g(const PyPhotonMap& m) {
    if (!m.config || m.config->scene->media.empty())
        throw Error("estimate: no scene media to take g from; pass g=");
    const double g = m.config->scene->media.front()->g();
    for (const auto& medium : m.config->scene->media)
        if (medium->g() != g) throw Error("estimate: the scene's media have different g; pass g=");
    return g;
}

py::object estimate(const PyPhotonMap& m, const py::handle& points, const py::handle& directions,
                   std::optional<std::string> estimator, std::optional<int64_t> k, std::optional<std::string> kernel,
                   std::optional<double> g, std::optional<double> max_radius, bool return_radius,
                   std::optional<int64_t> pass_index, std::optional<std::string> neighbours) {
    if (k) checked_int(*k, 1, kMaxK, "estimate: k");
    if (pass_index) checked_int(*pass_index, 0, std::numeric_limits<int>::max(), "estimate: pass_index");
    if (m.kind != "volume") throw Error("estimate: only the volume photon map has an in-scattering estimate");
    const Points q = rows_of_three(points, "points"), w = rows_of_three(directions, "directions");
    if (w.shape(0) != q.shape(0))
        throw Error("estimate: points and directions must have the same number of rows");
    const PhotonMapSettings defaults;
    const PhotonMapSettings& s = m.config ? photon_map_settings(*m.config) : defaults;
    Estimator e = estimator ? Estimator::named(*estimator).with_kernel(s.estimator.kernel()) : s.estimator;
    if (kernel) e = e.with_kernel(Kernel::named(*kernel));
    size_t kk = k ? size_t(*k) : size_t(s.k);
    if (pass_index) {   // the config's photons.schedule at that pass, starting from k: the pass's k and radius scale
        PhotonMapSettings scheduled = s;
        scheduled.k = int(kk);
        const PassRadii r = scheduled.radii_for_pass(int(*pass_index), true, false);
        kk = size_t(r.k);
        e = e.with_radius_scale(r.volume_scale);
    }
    e.validate_k(kk);
    const Neighbourhood hood = neighbours ? parse_neighbourhood(*neighbours, "estimate: neighbours") : s.neighbourhood;
    if (hood == Neighbourhood::walks) validate_walk_estimator(e);
    // Fewer photons than k: every estimate would use them all, silently a smaller k.
    if (kk > m.map->size())
        throw Error("estimate: k = " + std::to_string(kk) + (k ? "" : " (photons.k of the config)") + " but the map holds " +
                    std::to_string(m.map->size()) + " photons; k must be at most " + std::to_string(m.map->size()));
    const double gg = g ? *g : scene_g(m);
    if (!(gg > -1.0 && gg < 1.0)) throw Error("estimate: g must be in (-1, 1), got " + std::to_string(gg));
    const double radius = max_radius ? radius_or_infinity(max_radius, "max_radius") : s.search_radius();
    const py::ssize_t n = q.shape(0);
    py::array_t<double> values({n, py::ssize_t(3)});
    py::array_t<double> radii(n);
    const double* qp = q.data();
    const double* wp = w.data();
    double* vp = values.mutable_data();
    double* rp = radii.mutable_data();
    for (size_t i = 0; i < size_t(n); ++i) {
        finite_point(qp + 3 * i, i, "estimate: points");
        unit_direction(Vec3(wp[3 * i], wp[3 * i + 1], wp[3 * i + 2]), i, "estimate: directions");
    }
    const PhotonMap& map = *m.map;
    call_native([&](const std::atomic<bool>&) {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, size_t(n), 64), [&](const tbb::blocked_range<size_t>& range) {
            GatherBuffers buffers;
            for (size_t i = range.begin(); i != range.end(); ++i) {
                const Vec3 x(qp[3 * i], qp[3 * i + 1], qp[3 * i + 2]);
                const Vec3 w_o(wp[3 * i], wp[3 * i + 1], wp[3 * i + 2]);
                const Estimate<Rgb> est = hood == Neighbourhood::walks
                                              ? estimate_in_scattering_walks(map, x, w_o, gg, e, kk, radius, buffers)
                                              : estimate_in_scattering(map, x, w_o, gg, e, kk, radius, buffers);
                for (int c = 0; c < 3; ++c) vp[3 * i + size_t(c)] = est.value[c];
                rp[i] = est.radius;
            }
        });
    });
    if (return_radius) return py::make_tuple(values, radii);
    return std::move(values);
}

}  // namespace

void bind_photon_map(py::module_& m) {
    py::class_<PyPhotonMap, std::shared_ptr<PyPhotonMap>>(
        m, "PhotonMap",
        "A photon map: compressed photon records in Morton order and a kd-tree (lib/photon/map/photon_map.h). "
        "From vpm.trace_photons(config), or PhotonMap(positions, powers, directions) from (n, 3) arrays.")
        .def(py::init(&from_arrays), py::arg("positions"), py::arg("powers"), py::arg("directions"),
             py::arg("leaf_size") = 32, py::arg("walks") = py::none(),
             "walks: (n,) non-negative integer labels, photons with equal labels from one random walk (for "
             "neighbours=\"walks\"); None: every photon its own walk.")
        .def("__len__", [](const PyPhotonMap& p) { return p.map->size(); })
        .def_property_readonly("kind", [](const PyPhotonMap& p) { return p.kind; }, "\"volume\" or \"surface\".")
        .def_property_readonly("positions", [](const PyPhotonMap& p) {
            return attribute(*p.map, [&](size_t i) { return p.map->position(i); });
        }, "(n, 3) float64 positions in stored order (indices of knn refer to it); decoded on each access.")
        .def_property_readonly("powers", [](const PyPhotonMap& p) {
            return attribute(*p.map, [&](size_t i) { return p.map->power(i); });
        }, "(n, 3) float64 RGB photon powers (watts).")
        .def_property_readonly("directions", [](const PyPhotonMap& p) {
            return attribute(*p.map, [&](size_t i) { return p.map->direction(i); });
        }, "(n, 3) float64 unit incoming travel directions.")
        .def_property_readonly("walks", [](const PyPhotonMap& p) {
            py::array_t<int64_t> a(py::ssize_t(p.map->size()));
            int64_t* out = a.mutable_data();
            for (size_t i = 0; i < p.map->size(); ++i) out[i] = int64_t(p.map->walk(i));
            return a;
        }, "(n,) int64 walk of every photon in stored order: a dense id per distinct walk (a traced map: the "
           "emitted path that stored it; a map from arrays: its walks labels, numbered in their order).")
        .def_property_readonly("surface", [](const PyPhotonMap& p) { return p.surface; },
                               "The surface photon map of the same pass, or None.")
        .def_property_readonly("_stats_json", [](const PyPhotonMap& p) { return p.stats_json; })
        .def("knn", &knn, py::arg("points"), py::arg("k"), py::arg("max_radius") = py::none(),
             "(distances, indices), each (m, k): the k nearest stored photons of every point, nearest first "
             "(ties by index). Missing neighbours (k above the map size, or beyond max_radius) are inf and -1.")
        .def("estimate", &estimate, py::arg("points"), py::arg("directions"), py::arg("estimator") = py::none(),
             py::arg("k") = py::none(), py::arg("kernel") = py::none(), py::arg("g") = py::none(),
             py::arg("max_radius") = py::none(), py::arg("return_radius") = false, py::arg("pass_index") = py::none(),
             py::arg("neighbours") = py::none(),
             "The in-scattering estimate S(x, w_o) (RGB, (m, 3) float64) at each point for the outgoing travel "
             "direction w_o (towards the viewer), as the renderer computes it (estimate_in_scattering in "
             "lib/photon/estimate/estimators.h, rules (a)-(c) included). Unset arguments come from the config's [photons] "
             "(estimator, k, kernel, max_radius) and its media (g). return_radius: also the radius of each ball (the "
             "one counted in). pass_index: the estimate of that pass under photons.schedule starting from k (the pass's own k "
             "and radius scale: docs/progressive.md). neighbours: \"photons\" or \"walks\" (the k nearest independent "
             "walks: docs/walk_correlation.md; classic and corrected only), unset: the config's photons.neighbours. Points must be finite and directions unit vectors (vpm.Error naming "
             "the row otherwise).");
    m.def("_trace_photons", &trace, py::arg("config"), py::arg("stream_offset") = 0, py::arg("threads") = py::none(),
          py::arg("progress") = false, py::arg("log") = false);
}

}  // namespace vpm::python
