"""vpm from Python: render, study and inspect photon maps with NumPy arrays.

The module wraps the vpm library (not the command line): the same config validation and
messages, the same runs, the same files.

    import vpm
    config = vpm.load_config("configs/uniform_furnace.toml", overrides={"photons.k": 16})
    result = vpm.render(config, threads=2)
    result.image            # float32 (height, width, 3), a view on the run's pixels
    result.stats            # phases, photon counts, estimator rules, passes (the sidecar's keys)
    result.save("out/furnace.exr")   # EXR + PNG preview + JSON sidecar, as `vpm render -o`
    result.seconds, result.integrator_used, result.gather_used, result.map_estimates   # what ran

    vpm.compare(result, "ref.exr")   # relMSE with the reference's noise subtracted, rel_rmse, rel_bias, as sweeps report them

    photons = vpm.trace_photons(config)          # the photon pass alone
    photons.positions, photons.powers, photons.directions   # (n, 3) NumPy arrays
    distances, indices = photons.knn(points, k=8)
    radiance = photons.estimate(points, directions, estimator="classic", k=8)

Native work runs with the GIL released; Ctrl-C stops it (KeyboardInterrupt) and nothing is
written. Errors raise vpm.Error (vpm.ConfigError, vpm.FileError) with the tool's one-line message.
"""

import csv
import io
import json
import math
import numbers
import os
import warnings

from . import _vpm
from ._vpm import Config, ConfigError, Error, FileError, PhotonMap, RenderResult, exclude_lights_mask, luminance, read_exr

def _one_line(text):
    return " ".join(line.strip() for line in text.splitlines() if line.strip())


def _typed(function, name):
    """`function` with pybind11's TypeError for arguments of the wrong type raised as vpm.Error naming
    `name` and the signature it accepts (every error of the module is a vpm.Error)."""
    def call(*args, **kwargs):
        try:
            return function(*args, **kwargs)
        except TypeError as e:
            message = str(e)
            if "incompatible function arguments" not in message and "incompatible constructor arguments" not in message:
                raise
            allowed = message.split("supported:", 1)[-1].split("Invoked with", 1)[0]
            raise Error("%s: arguments of the wrong type; accepted: %s" % (name, _one_line(allowed))) from None
    call.__name__ = getattr(function, "__name__", name)
    call.__doc__ = getattr(function, "__doc__", None)
    return call


class _TypedModule:
    """The native module with every function's argument TypeErrors raised as vpm.Error."""

    def __init__(self, module):
        self._module = module

    def __getattr__(self, attr):
        value = getattr(self._module, attr)
        if callable(value) and not isinstance(value, type):
            return _typed(value, attr.lstrip("_"))
        return value


for _method in ("__init__", "knn", "estimate"):
    setattr(PhotonMap, _method, _typed(getattr(PhotonMap, _method),
                                       "PhotonMap" if _method == "__init__" else "PhotonMap." + _method))
RenderResult.save = _typed(RenderResult.save, "RenderResult.save")
luminance = _typed(luminance, "luminance")
exclude_lights_mask = _typed(exclude_lights_mask, "exclude_lights_mask")
read_exr = _typed(read_exr, "read_exr")

__version__ = _vpm.__version__
git_revision = _vpm.git_revision
_vpm = _TypedModule(_vpm)

__all__ = ["load_config", "render", "trace_photons", "study", "sweep", "compare", "exclude_lights_mask", "luminance", "info", "read_exr", "Config",
           "RenderResult",
           "PhotonMap", "Error", "ConfigError", "FileError"]


def _toml_value(value, key):
    """A Python value as TOML text for a KEY=VALUE override (what `--set` takes)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        value = float(value)
        return repr(value) if math.isfinite(value) else ("nan" if math.isnan(value) else ("inf" if value > 0 else "-inf"))
    if isinstance(value, str):
        return json.dumps(value)   # a JSON string is a TOML basic string
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v, key) for v in value) + "]"
    raise Error("overrides: %s: a %s cannot be written as a config value (use bool, int, float, str or a list)"
                % (key, type(value).__name__))


def _overrides(overrides):
    if overrides is None:
        return []
    if isinstance(overrides, dict):
        return ["%s=%s" % (k, _toml_value(v, k)) for k, v in overrides.items()]
    return [str(o) for o in overrides]   # "key=value" strings, exactly as --set


def load_config(source, overrides=None):
    """Reads a scene config and validates it exactly as `vpm render` does.

    source: a path (str or os.PathLike) to a TOML config or a run's JSON sidecar; TOML or JSON
    text (a str with a newline, an '=' or starting with '{'), relative paths then from the
    working directory; or a dict with the config's tables.
    overrides: {"photons.k": 16, "media.0.g": 0.5} or ["photons.k=16"]: applied and validated
    like `--set` (same messages).
    Raises vpm.ConfigError / vpm.FileError with the tool's message.
    """
    sets = _overrides(overrides)
    if isinstance(source, dict):
        return _load_dict(source, sets)
    if isinstance(source, os.PathLike):
        return _vpm._load_config(os.fspath(source), False, "", "", sets)
    if not isinstance(source, str):
        raise Error("load_config: expected a path, config text or a dict, got a %s" % type(source).__name__)
    if not source.strip():
        raise FileError("load_config: expected a config path, config text or a dict, got an empty string")
    if "\n" in source or "=" in source or source.lstrip().startswith("{"):
        return _vpm._load_config(source, True, "<string>", os.getcwd(), sets)
    return _vpm._load_config(source, False, "", "", sets)


# A config's nesting limit, as for TOML and JSON files (lib/config/config_file.h: kMaxConfigNesting).
_MAX_NESTING = 64


def _dict_values(table, path, non_finite, open_containers=()):
    """A copy of a config dict that JSON can carry: every key a str and every value a bool, number,
    str, list or dict (else vpm.ConfigError naming the key). JSON has no NaN or infinity, so such
    floats are replaced by 0 and their dotted paths collected in non_finite, to go in as overrides.
    open_containers: the ids of the dicts and lists around this value (a cycle, or nesting deeper
    than a config allows, is a ConfigError, not Python's RecursionError)."""
    if isinstance(table, (dict, list, tuple)):
        if id(table) in open_containers:
            raise ConfigError("<dict>: %s: the value contains itself (a cycle); a config is a tree of tables, "
                              "lists and values" % (path or "<top>"))
        if len(open_containers) >= _MAX_NESTING:
            raise ConfigError("<dict>: %s: nesting deeper than %d levels (tables and lists); a scene needs a handful"
                              % (path, _MAX_NESTING))
        open_containers = open_containers + (id(table),)
    if isinstance(table, dict):
        out = {}
        for key, value in table.items():
            if not isinstance(key, str):
                raise ConfigError("<dict>: %s: a config key must be a str, got a %s" % (path or "<top>", type(key).__name__))
            out[key] = _dict_values(value, path + "." + key if path else key, non_finite, open_containers)
        return out
    if isinstance(table, (list, tuple)):
        return [_dict_values(v, "%s.%d" % (path, i), non_finite, open_containers) for i, v in enumerate(table)]
    if isinstance(table, (bool, str)) or isinstance(table, numbers.Integral):
        return table
    if isinstance(table, numbers.Real):
        value = float(table)
        if not math.isfinite(value):
            non_finite.append((path, value))
            return 0.0
        return value
    raise ConfigError("<dict>: %s: a %s cannot be a config value (use bool, int, float, str, a list or a dict)"
                      % (path, type(table).__name__))


def _load_dict(source, sets):
    non_finite = []
    text = json.dumps(_dict_values(source, "", non_finite))
    injected = ["%s=%s" % (path, _toml_value(value, path)) for path, value in non_finite]
    try:
        return _vpm._load_config(text, True, "<dict>", os.getcwd(), injected + sets)
    except ConfigError as e:   # a non-finite value's range error: name the dict, not an override
        message = str(e)
        for path, _ in non_finite:
            if message.startswith("--set %s: " % path):
                raise ConfigError("<dict>: " + message[len("--set %s: " % path):]) from None
        raise


def _config(config):
    return config if isinstance(config, Config) else load_config(config)


def render(config, threads=None, progress=True, log=False, stream_offset=0):
    """Renders a config (a vpm.Config, or anything load_config takes) as `vpm render` does.

    threads: worker threads (None: render.threads from the config; 0: all cores).
    progress: the tool's progress bar / lines on stderr. log: the tool's log lines on stderr.
    stream_offset: independent repeats with the same seed (as sweeps use).
    Returns a RenderResult: .image, .stats, .record and .save(path), and what ran: .seconds (wall
    time), .integrator_used ("photon_map" or "path"), .gather_used, .map_estimates, .photons_traced,
    .passes and .spp_per_pass.
    """
    return _vpm._render(_config(config), threads, progress, log, stream_offset)


def _stats(self):
    return json.loads(self._stats_json)


def _record(self):
    return json.loads(self._record_json)


def _render_repr(self):
    ran = self.integrator_used
    if ran == "photon_map":
        ran += " (%s gather, %d map estimates, %d photons traced)" % (self.gather_used, self.map_estimates,
                                                                     self.photons_traced)
    return "<vpm.RenderResult %dx%d: %s, %d passes x %d spp, %.3g s>" % (
        self.image.shape[1], self.image.shape[0], ran, self.passes, self.spp_per_pass, self.seconds)


RenderResult.__repr__ = _render_repr
RenderResult.stats = property(_stats, doc="The run's typed statistics (RunStats) as the sidecar writes them: "
                                          "phases, render, photons (counts, energy, estimator rules), passes.")
RenderResult.record = property(_record, doc="The whole JSON sidecar as a dict (config, environment and stats).")
PhotonMap.stats = property(_stats, doc="The photon pass's statistics (trace_photons), as in a render's sidecar.")


def trace_photons(config, stream_offset=0, threads=None, progress=False, log=False):
    """Runs the photon pass of a config alone and returns its vpm.PhotonMap.

    The same photons as the first pass of `vpm render` with the same seed (render.first_pass = 0),
    so len(map) is the sidecar's photons.stored (and map.surface's its photons.surface_stored).
    """
    return _vpm._trace_photons(_config(config), stream_offset, threads, progress, log)


def _number(text):
    for convert in (int, float):
        try:
            return convert(text)
        except ValueError:
            pass
    return text


def _table(text, as_dataframe):
    """CSV text as a list of dicts (numbers converted), or a pandas DataFrame when pandas is importable."""
    if as_dataframe is not False:
        try:
            import pandas
            return pandas.read_csv(io.StringIO(text))
        except ImportError:
            if as_dataframe:
                raise
    return [{k: _number(v) for k, v in row.items()} for row in csv.DictReader(io.StringIO(text))]


def study(out="out/study", dims=(2, 3), k=None, trials=10000, n=1000, seed=20130619, scenarios=None,
          photon_map_size=100000, threads=0, log=False, as_dataframe=None):
    """The estimator study (`vpm study`): bias, variance and MSE of the kNN estimators against theory.

    Writes study.csv, study.md and study.json into `out` (None: write nothing) and returns the
    study.csv table: a pandas DataFrame when pandas is importable (as_dataframe=None), else a
    list of dicts (as_dataframe=False forces the list). k: list of k (None: 2 .. 256).
    scenarios: names (None: all; see `vpm study --help`).
    """
    csv_text, _, notes = _vpm._study(None if out is None else os.fspath(out), list(dims), list(k or []), trials, n,
                                     seed, None if scenarios is None else list(scenarios), photon_map_size, threads,
                                     log)
    return _table(csv_text, as_dataframe)


class SweepTables:
    """What vpm.sweep returns: .runs (runs*.csv rows), .points (points.csv), .summary (summary.md
    text), .outcome (counts: planned, ran, skipped, remaining, seconds) and .out (the folder)."""

    def __init__(self, out, outcome, as_dataframe):
        self.out = out
        self.outcome = outcome
        runs = sorted(f for f in os.listdir(out) if f.startswith("runs") and f.endswith(".csv"))
        lines = []
        for i, name in enumerate(runs):
            with open(os.path.join(out, name)) as f:
                text = f.read().splitlines()
            lines += text if i == 0 else text[1:]
        self.runs = _table("\n".join(lines) + "\n", as_dataframe)
        points = os.path.join(out, "points.csv")
        self.points = _table(open(points).read(), as_dataframe) if os.path.exists(points) else []
        summary = os.path.join(out, "summary.md")
        self.summary = open(summary).read() if os.path.exists(summary) else ""

    def __repr__(self):
        return "<vpm.SweepTables %s: %d runs>" % (self.out, len(self.runs))


def sweep(file, out=None, jobs=1, threads=0, max_runs=0, shard=(0, 1), references_only=False, progress=False,
          log=True, as_dataframe=None):
    """A parameter sweep (`vpm sweep FILE --no-plots`): resumable, into `out` (default
    out/sweeps/<file name>). Returns SweepTables. Ctrl-C stops it; what finished is kept, and the
    same call resumes. Plots: run tools/plot_sweep.py on the folder, or plot the tables yourself."""
    file = os.fspath(file)
    if out is None:
        out = os.path.join("out", "sweeps", os.path.splitext(os.path.basename(file))[0])
    out = os.fspath(out)
    outcome = _vpm._sweep(file, out, jobs, threads, max_runs, shard[0], shard[1], references_only, progress, log)
    return SweepTables(out, outcome, as_dataframe)


def _image_and_samples(x, name):
    """(pixels, camera samples or None, label) of an image given as a RenderResult, an EXR path or an array."""
    if isinstance(x, RenderResult):
        return x.image, x.stats.get("render", {}).get("samples"), name
    if isinstance(x, (str, os.PathLike)):
        path = os.fspath(x)
        samples = None
        sidecar = os.path.splitext(path)[0] + ".json"
        if os.path.exists(sidecar):
            try:
                with open(sidecar) as f:
                    samples = json.load(f).get("render", {}).get("samples")
            except (OSError, ValueError, AttributeError):
                samples = None
        return read_exr(path), samples if isinstance(samples, int) else None, path
    return x, None, name


def compare(image, reference, metric="relmse", epsilon=0.01, crop=None, exclude=(), mask=None, reference_variance=None):
    """Error of IMAGE against REFERENCE by a named metric, with the reference's noise subtracted, and the
    metrics `vpm sweep` reports (lib/analysis/metrics/error_metrics.h, docs/metrics.md): what `vpm compare` says.

    image: one image, or a list of images taken as independent repeats of one configuration; each an
    (height, width, 3) array, an EXR path (its sidecar gives its samples) or a vpm.RenderResult.
    reference: the same kinds, or a tuple (A, B) of two halves rendered on independent streams (the
    reference is their mean, its noise comes from their difference).
    metric: "relmse" (mean (I-R)^2 / (R^2 + epsilon), the default), "relrmse" (sqrt(mean (I-R)^2) / mean R)
    or "smape" (mean |I-R| / (|I| + |R| + epsilon)); all on luminance.
    crop: (x0, y0, x1, y1) pixels compared (half-open, row 0 at the top); exclude: such rectangles left
    out (a glint); mask: an array of the image's shape, compared where non-zero
    (vpm.exclude_lights_mask(config) leaves out the pixels that see an area light).
    reference_variance: the reference's per-pixel luminance variance (an array or an EXR path); by default
    REFERENCE.variance.exr when the reference is a path with one beside it (`vpm render --variance`).
    Returns a dict:
      metric, metric_formula, mask, pixels
      error, error_se             the metric (noise floor subtracted when known): mean over the images
                                  and its standard error (NaN for one image)
      noise_floor                 what a perfect image would score against this reference (NaN: unknown)
      rel_rmse, rel_bias          the sweep's relative RMSE and signed relative bias over all pixels
                                  (over the repeats: sqrt(rel_mse) and the mean of the per-image biases)
      rel_bias_se, rel_std, rel_variance   over two or more images (NaN for one)
      rel_mse, rel_bias2          rel_mse = rel_bias2 + rel_variance
      repeats, reference_luminance, nonfinite_pixels
      images                      per image: error, error_raw, noise_floor, rel_rmse, rel_bias, rgb_rmse,
                                  rgb_relative_rmse, rgb_relative_bias, mean
      samples, reference_samples  camera samples where known (None otherwise)
      warnings                    e.g. an image with more samples than its reference (also issued as a
                                  Python warning): its error is then mostly the reference's noise
    """
    many = isinstance(image, (list, tuple))
    items = [_image_and_samples(x, "image %d" % i) for i, x in enumerate(image if many else [image])]
    if isinstance(reference, tuple):
        if len(reference) != 2:
            raise Error("compare: reference: a tuple holds two halves (A, B), got %d items" % len(reference))
        if reference_variance is not None:
            raise Error("compare: give reference halves or reference_variance, not both (the halves carry their noise)")
        a, b = (_image_and_samples(x, "reference half %d" % i)[0] for i, x in enumerate(reference))
        ref, reference_variance = _vpm._reference_from_halves(a, b)
        ref_samples, ref_name = None, "the reference halves"
    else:
        ref, ref_samples, ref_name = _image_and_samples(reference, "the reference")
        if reference_variance is None and isinstance(reference, (str, os.PathLike)):
            beside = os.path.splitext(os.fspath(reference))[0] + ".variance.exr"
            if os.path.exists(beside):
                reference_variance = beside
    if isinstance(reference_variance, (str, os.PathLike)):
        reference_variance = read_exr(os.fspath(reference_variance))
    out = _vpm._compare([i[0] for i in items], ref, metric, float(epsilon), None if crop is None else list(crop),
                        [list(e) for e in exclude], mask if mask is None else _mask_array(mask), reference_variance)
    out["samples"] = [i[1] for i in items] if many else items[0][1]
    out["reference_samples"] = ref_samples
    out["warnings"] = []
    if ref_samples is not None:
        for _, samples, name in items:
            if samples is not None:
                text = _vpm._more_samples_warning(name, samples, ref_name, ref_samples)
                if text:
                    out["warnings"].append(text)
                    warnings.warn(text, stacklevel=2)
    return out


def _mask_array(mask):
    """A mask as an (height, width, 3) float array: a path is read as an EXR, a 2-D array repeated per channel."""
    if isinstance(mask, (str, os.PathLike)):
        return read_exr(os.fspath(mask))
    import numpy as np
    m = np.asarray(mask, dtype=np.float32)
    return np.repeat(m[:, :, None], 3, axis=2) if m.ndim == 2 else m


def info(target, overrides=None):
    """What a scene config or a VDB file holds (`vpm info TARGET --json`) as a dict.

    target: a config path or a .vdb path. overrides: as load_config's (configs only).
    A config gives world_bounds, media (bounds, grid: voxel_size, active_voxels, density range;
    sigma_t_max, tau_across), lights (power into the scene), shapes and camera (settings, seen:
    fractions of pixels meeting a medium, a surface, nothing); a VDB gives its grids and a
    suggested_camera.
    """
    target = os.fspath(target)
    vdb = target.endswith(".vdb")
    if vdb and overrides:
        raise Error("info: overrides apply to a scene config, not to a VDB file")
    return json.loads(_vpm._info(target, _overrides(overrides), vdb))
