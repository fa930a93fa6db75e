#!/usr/bin/python3
"""Plots for `vpm sweep`; every number comes from OUT/points.csv (written by the C++ tool).

usage: /usr/bin/python3 tools/plot_sweep.py OUT_DIR
writes, each as .png, .pdf and .svg (vector, for a paper):
       OUT_DIR/error_vs_time      the sweep's metric (points.csv: error, relMSE by default, the
                                   reference's noise floor subtracted) against mean run time, log-log:
                                   every configuration of each estimator and of the path tracer with
                                   its standard error over the repeats as an error bar, each method's
                                   lower envelope (the least error it reaches within a time), and the
                                   reference's noise floor (what a perfect image would score)
       OUT_DIR/error_vs_k         the metric against k, one line per estimator and photon count
       OUT_DIR/bias_vs_k          relative bias (+- standard error) against k with the k/(k-1)
                                   prediction: 1/(k-1) if all radiance came from photons, and
                                   f/(k-1) with the photon share f fitted to the classic points
One panel per scene (combination of the non-photon axes other than time budgets, e.g. media.0.g), at most 9.
"""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import NullFormatter, ScalarFormatter  # noqa: E402

COLOURS = {"classic": "tab:red", "corrected": "tab:blue", "mse_optimal": "tab:green", "path": "black"}
FIXED = ["point", "method", "spp", "repeats", "trace_s", "build_s", "render_s", "total_s", "run_s", "photons_stored",
         "integrator_used", "gather_used", "map_estimates", "off_plan_repeats", "rel_rmse", "rel_mse", "rel_bias", "rel_bias_se", "rel_bias2", "rel_variance", "rel_std", "nonfinite_pixels",
         "metric", "error", "error_se", "error_raw", "noise_floor"]
MAX_PANELS = 9


def num(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return float("nan")


def photon_axis(a):
    return a in ("k", "estimator", "kernel") or a.startswith("photons.")


def budget_axis(a):
    """Time budgets are where a run lands on the time axis, not a different scene."""
    return a in ("time_limit", "render.time_limit")


def scene_name(out):
    """The base scene's file name from sweep.json, for the panel title of a sweep with no scene axis."""
    try:
        with open(os.path.join(out, "sweep.json")) as f:
            return os.path.basename(json.load(f).get("scene", "")) or "all runs"
    except (OSError, ValueError):
        return "all runs"


def panels(rows, axes, name="all runs"):
    scene_axes = [a for a in axes if not photon_axis(a) and not budget_axis(a)]
    groups = {}
    for r in rows:
        key = tuple(r[a] for a in scene_axes)
        groups.setdefault(key, []).append(r)
    items = list(groups.items())[:MAX_PANELS]
    titles = [", ".join(f"{a}={v}" for a, v in zip(scene_axes, key)) or name for key, _ in items]
    return [g for _, g in items], titles, len(groups)


def figure(n):
    cols = min(n, 3)
    rows = (n + cols - 1) // cols
    fig, axs = plt.subplots(rows, cols, figsize=(5.5 * cols, 4.3 * rows), squeeze=False)
    for ax in axs.flat[n:]:
        ax.set_visible(False)
    return fig, list(axs.flat[:n])


def colour(m):
    return COLOURS.get(m, None)


def off_plan(r):
    """A photon-map point some of whose repeats did not estimate from a map (points.csv off_plan_repeats)."""
    return r["method"] != "path" and num(r.get("off_plan_repeats", "0")) > 0


def what_ran(rows, m):
    """Legend text for method m: what its points ran (integrator_used, gather_used from points.csv)."""
    if m == "path":
        return "path tracer"
    gathers = sorted({g for r in rows if r["method"] == m for g in r.get("gather_used", "").split("/") if g and g != "none"})
    label = m + (f", {'/'.join(gathers)} gather" if gathers else "")
    bad = sum(1 for r in rows if r["method"] == m and off_plan(r))
    if bad:
        label += f"; {bad} point(s) ran the path tracer (x)"
    return label


def legend(ax, fontsize):
    """A legend only where something is labelled (matplotlib warns on an empty one)."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=fontsize)


def save(fig, out, stem):
    """PNG for a look, PDF and SVG (vector) for a paper, side by side."""
    for ext in ("png", "pdf", "svg"):
        fig.savefig(os.path.join(out, f"{stem}.{ext}"), dpi=120 if ext == "png" else None)
    plt.close(fig)


def metric_of(rows):
    """The metric points.csv reports (older folders: relative RMSE from rel_rmse)."""
    names = {r.get("metric") for r in rows if r.get("metric")}
    return names.pop() if len(names) == 1 else None


def error_of(r, metric):
    return num(r["error"]) if metric else num(r["rel_rmse"])


def envelope(points):
    pts = sorted(points)
    out, best = [], math.inf
    for t, e in pts:
        if e < best:
            best = e
            out.append((t, e))
    return out


def error_vs_time(groups, titles, out, metric):
    fig, axs = figure(len(groups))
    for ax, g, title in zip(axs, groups, titles):
        methods = []
        for r in g:
            if r["method"] not in methods:
                methods.append(r["method"])
        hidden = 0
        for m in methods:
            pts = [(num(r.get("run_s") or r["total_s"]), error_of(r, metric), num(r.get("error_se", "nan")) if metric else
                    float("nan"), off_plan(r)) for r in g if r["method"] == m]
            ok = [p for p in pts if p[0] > 0 and p[1] > 0 and math.isfinite(p[0]) and math.isfinite(p[1])]
            hidden += len(pts) - len(ok)   # at or below zero after the floor: nothing to draw on a log axis
            if not ok:
                continue
            c = colour(m)
            for bad, marker in ((False, "o"), (True, "x")):
                sel = [p for p in ok if p[3] == bad]
                if sel:
                    # Error bars: the standard error over the repeats, clipped above zero for the log axis.
                    yerr = [[min(p[2], 0.999 * p[1]) if math.isfinite(p[2]) else 0 for p in sel],
                            [p[2] if math.isfinite(p[2]) else 0 for p in sel]]
                    ax.errorbar([p[0] for p in sel], [p[1] for p in sel], yerr=yerr, fmt=marker, ms=3 if not bad else 5,
                                alpha=0.5 if not bad else 0.9, color=c, capsize=2, elinewidth=0.8)
            env = envelope([(t, e) for t, e, _, _ in ok])
            ax.plot([p[0] for p in env], [p[1] for p in env], "-", color=c, label=what_ran(g, m) + " (envelope)")
        floors = sorted({num(r.get("noise_floor", "nan")) for r in g} - {float("nan")})
        floors = [f for f in floors if math.isfinite(f) and f > 0]
        if floors:
            ax.axhline(floors[0], color="grey", ls="--", lw=1, label="reference noise floor (subtracted; errors near it are unresolved)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("mean run time (run_s: every phase), s")
        ax.set_ylabel((metric + ", reference noise subtracted") if metric else "relative RMSE")
        ax.set_title(title + (f"\n({hidden} point(s) at or below zero after the floor not drawn)" if hidden else ""), fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        legend(ax, 8)
    fig.suptitle("Error against run time (bars: standard error over repeats)")
    fig.tight_layout()
    save(fig, out, "error_vs_time")


def by_line(g, axes):
    """Photon-map rows grouped into lines over k: (estimator, other photon axes)."""
    others = [a for a in axes if photon_axis(a) and a not in ("k", "estimator", "kernel")]   # in the method
    lines = {}
    for r in g:
        if r["method"] == "path" or "k" not in r or r["k"] == "":
            continue
        key = (r["method"],) + tuple(f"{a}={r[a]}" for a in others)
        lines.setdefault(key, []).append(r)
    for key in lines:
        lines[key].sort(key=lambda r: num(r["k"]))
    return lines


def line_label(key, rr):
    """A line's legend text; says how many of its points did not estimate from a photon map."""
    bad = sum(1 for r in rr if off_plan(r))
    return " ".join(key) + (f" ({bad} of {len(rr)} points ran the path tracer)" if bad else "")


STYLES = ["-", "--", "-.", ":"]


def style(key, lines):
    """Line style by the non-estimator part of the key (e.g. the photon count), colour by estimator."""
    rests = []
    for k in lines:
        if k[1:] not in rests:
            rests.append(k[1:])
    return STYLES[rests.index(key[1:]) % len(STYLES)]


def k_axis(ax, ylabel, title, ks):
    """Log k axis with a plain tick label at every k swept (a log axis alone labels only the
    decades: one "10" for k = 4..64), grid and legend, shared by the plots against k."""
    ax.set_xscale("log")
    ax.set_xlabel("k")
    if ks:
        ax.set_xticks(ks)
        ax.set_xticklabels([f"{k:g}" for k in ks])
    else:
        ax.xaxis.set_major_formatter(ScalarFormatter())
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    legend(ax, 7)


def error_vs_k(groups, titles, axes, out, metric):
    fig, axs = figure(len(groups))
    for ax, g, title in zip(axs, groups, titles):
        lines = by_line(g, axes)
        for key, rr in lines.items():
            rr = [r for r in rr if error_of(r, metric) > 0]
            if not rr:
                continue
            se = [num(r.get("error_se", "nan")) if metric else float("nan") for r in rr]
            ax.errorbar([num(r["k"]) for r in rr], [error_of(r, metric) for r in rr],
                        yerr=[[min(s, 0.999 * error_of(r, metric)) if math.isfinite(s) else 0 for s, r in zip(se, rr)],
                              [s if math.isfinite(s) else 0 for s in se]],
                        marker="o", ms=3, capsize=2, ls=style(key, lines), color=colour(key[0]), label=line_label(key, rr))
        ax.set_yscale("log")
        k_axis(ax, (metric + ", reference noise subtracted") if metric else "relative RMSE", title,
               sorted({num(r["k"]) for rr in lines.values() for r in rr}))
    fig.suptitle("Error against k (error bars: standard error over the repeats)")
    fig.tight_layout()
    save(fig, out, "error_vs_k")


def bias_vs_k(groups, titles, axes, out):
    fig, axs = figure(len(groups))
    for ax, g, title in zip(axs, groups, titles):
        lines = by_line(g, axes)
        ks = sorted({num(r["k"]) for rr in lines.values() for r in rr if num(r["k"]) > 1})
        for key, rr in lines.items():
            ax.errorbar([num(r["k"]) for r in rr], [num(r["rel_bias"]) for r in rr],
                        yerr=[num(r["rel_bias_se"]) if math.isfinite(num(r["rel_bias_se"])) else 0 for r in rr],
                        marker="o", ls=style(key, lines), ms=3, capsize=2, color=colour(key[0]),
                        label=line_label(key, rr))
        if ks:
            ax.plot(ks, [1 / (k - 1) for k in ks], ":", color="grey", label="1/(k-1): k/(k-1) if all light were photons")
            cl = [(num(r["k"]), num(r["rel_bias"])) for key, rr in lines.items() if key[0] == "classic" for r in rr]
            cl = [(k, b) for k, b in cl if k > 1 and math.isfinite(b)]
            if cl:
                # least squares b = f/(k-1): f = sum(b x) / sum(x^2), x = 1/(k-1)
                f = sum(b / (k - 1) for k, b in cl) / sum(1 / (k - 1) ** 2 for k, _ in cl)
                ax.plot(ks, [f / (k - 1) for k in ks], "--", color="tab:red",
                        label=f"classic prediction f/(k-1), fitted f={f:.3f}")
            ax.axhline(0, color="tab:blue", lw=0.8, ls="--", label="corrected prediction 0")
        k_axis(ax, "relative bias (mean over repeats)", title, sorted({num(r["k"]) for rr in lines.values() for r in rr}))
    fig.suptitle("Bias against k (error bars: standard error over repeats)")
    fig.tight_layout()
    save(fig, out, "bias_vs_k")


def main():
    if len(sys.argv) == 2 and sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out = sys.argv[1]
    try:
        with open(os.path.join(out, "points.csv"), newline="") as f:
            reader = csv.DictReader(f)
            rows = list(reader)
            axes = [c for c in reader.fieldnames if c not in FIXED]
    except OSError as e:
        print(f"plot_sweep: cannot read {os.path.join(out, 'points.csv')}: {e.strerror}", file=sys.stderr)
        return 1
    if not rows:
        print("plot_sweep: points.csv has no rows", file=sys.stderr)
        return 1
    groups, titles, n = panels(rows, axes, scene_name(out))
    if n > MAX_PANELS:
        print(f"plot_sweep: {n} scenes, plotting the first {MAX_PANELS}", file=sys.stderr)
    metric = metric_of(rows)
    error_vs_time(groups, titles, out, metric)
    error_vs_k(groups, titles, axes, out, metric)
    bias_vs_k(groups, titles, axes, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
