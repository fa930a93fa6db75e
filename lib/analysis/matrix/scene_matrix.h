#pragma once
// The scene matrix: does the photon map with its defaults beat the path tracer on
// scenes nobody tuned it for? Each cell is a generated scene (a homogeneous box or sphere, the
// smooth Gaussian blob or the plume of media/, fitted into [-1, 1]^3, seen from (0, 0, 4), no
// surfaces) at one optical thickness, albedo, g, light and scale. Per cell, at equal time (every
// method gets render.time_limit = budget): the path tracer, the photon map with its defaults, and
// the photon map with each gather forced (the beam gather), then render.integrator = "auto"; each image's error against a long path-traced
// reference, cached by scene hash under OUT/references/ and reused by later runs.
//
// Figures per method (error_metrics.h: luminance, relative to the reference's mean):
//   mse  = rel_rmse^2 - reference noise (the reference is the mean of two half renders on their
//          own streams; its variance per pixel is estimated as ((A - B) / 2)^2, averaged), so a
//          short reference does not flatten the ratios of good methods
//   C    = mse * seconds (error^2 x time: the time to a given error is proportional to it)
//   ratio photon map / path tracer = C_pm / C_path: the photon map's time to equal error over
//          the path tracer's (< 1: the photon map wins)
//   relmse (matrix.csv) = the per-pixel relative MSE (error_metrics.h, eps 0.01), the reference's
//          per-pixel noise (from the halves, kept as REF.variance.exr) subtracted
// Optical thickness: the optical depth along the z axis through the centre of the medium's
// bounds (box, sphere: the diameter). A scaled cell multiplies every length by `scale` and
// divides sigma_t by it (point and spot intensities by scale^2), which leaves the image as it
// was: it is compared with the unscaled cell's reference, so its figures must match that cell's.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace vpm {

struct MatrixCell {
    std::string group;       // the axis this cell varies ("thickness", "albedo", ...)
    std::string shape;       // box | sphere | blob | plume
    double tau = 1.0;        // optical thickness across the medium
    double albedo = 0.9;
    double g = 0.0;
    std::string light;       // point | spot | quad | environment
    double scale = 1.0;      // every length times this
    std::string id() const;  // e.g. "box-tau10-a0.9-g0-point-s1" (file names, --only)
    std::string unscaled_id() const;
};

// The full matrix (56 cells) or the --quick subset (4 cells, one of them scaled).
std::vector<MatrixCell> matrix_cells(bool quick);

// The methods run per cell, in table order: label and the --set overrides.
struct MatrixMethod {
    std::string label;
    std::vector<std::string> sets;
};
const std::vector<MatrixMethod>& matrix_methods();

struct MatrixOptions {
    bool quick = false;
    double budget = 4.0;              // seconds per method (render.time_limit); 0: fixed work (passes)
    int passes = 0;                   // with budget 0: render.passes for every method (spp 16 per pass)
    double reference_seconds = 40.0;  // path tracer time for each cell's reference (two halves)
    int size = 64;                    // image width = height
    std::filesystem::path media;      // folder with blob.vdb and plume.vdb
    std::filesystem::path out;        // scenes/, references/
    std::ostream* log = nullptr;
    std::function<bool(const MatrixCell&)> filter;   // null: every cell
    std::vector<std::string> sets;    // --set overrides for every run after the method's (tests: fewer photons)
    // `vpm bench matrix --set`: photons.* and render.seed for the compared runs (path tracer and photon
    // map settings), before the method's own, so that a forced gather stays forced; never for the
    // references, which are cached by scene (check_matrix_method_set).
    std::vector<std::string> method_sets;
};

struct MatrixReport;

// Throws vpm::Error unless `set` is KEY=VALUE with KEY photons.* or render.seed: a key that changes
// the scene or the render (media, lights, camera, render.time_limit) would be compared against
// references cached for another scene or budget.
void check_matrix_method_set(const std::string& set);

struct MatrixMethodResult {
    std::string label;
    double seconds = 0;     // wall time of the whole run (photon pass, build, render)
    int passes = 0;
    double rel_rmse = 0;    // against the reference, reference noise included
    double mse = 0;         // rel_rmse^2 minus the reference's noise
    double relmse = 0;      // per-pixel relative MSE (error_metrics.h), the reference's noise floor subtracted (raw when the cached reference has no variance image)
    double cost() const { return mse * seconds; }   // C
    uint64_t nonfinite_pixels = 0;
    std::string chosen;     // "pilot": the gather its pilot chose (last pass); "auto": the plan's gather, photons x spp per pass
    double march_weight_max = 0, march_weight_mean = 0;   // march points' relative weights (RunStats)
    double beam_crossed_per_query = 0;   // photons.gather = "beam": photon discs per segment query
};

struct MatrixRow {
    MatrixCell cell;
    double sigma_t_scale = 0;         // what the thickness came to (at scale 1)
    std::string reference;            // reference file name (scene hash of the unscaled cell)
    bool reference_reused = false;    // read from the cache rather than rendered by this run
    double reference_noise = 0;       // relative variance of the reference mean
    double reference_seconds = 0;
    std::vector<MatrixMethodResult> methods;   // matrix_methods() order
    double ratio(size_t method) const;         // C_method / C_path
    double best_forced_ratio() const;          // C_default / min over the forced gathers (collision, march)
    double beam_over_best_point() const;       // C_beam / min over the point gathers (default, collision, march, pilot)
};

struct MatrixReport {
    std::vector<MatrixRow> rows;
    MatrixOptions options;
    double seconds = 0;
    int references_rendered = 0, references_reused = 0;
    std::string to_markdown(const std::string& command, const std::string& machine) const;
    std::string to_csv() const;
};

// on_row (may be empty) is called with the report so far after every cell, so a long run that is
// stopped still leaves its finished cells written.
MatrixReport run_scene_matrix(const MatrixOptions& options, const std::function<void(const MatrixReport&)>& on_row = {});

// The scene of a cell as TOML (exposed for tests); media paths are absolute under `media`.
std::string matrix_scene_toml(const MatrixCell& cell, double sigma_t_scale, const std::filesystem::path& media, int size);

}  // namespace vpm
