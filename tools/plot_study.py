#!/usr/bin/python3
"""Plots for `vpm study`: relative error vs k with theory curves and error bars (like the seed's
figure) and relative MSE vs k for the three scales. The numbers all come from study.csv (C++).

usage: /usr/bin/python3 tools/plot_study.py OUT/study.csv OUT_DIR
writes OUT_DIR/study_error_<scenario> and OUT_DIR/study_mse_<scenario>, each .png, .pdf and .svg; the kernels
scenario (estimators labelled "classic/<kernel>") gets one colour per kernel, the k-th photon
kept (classic: open markers, dashed theory) or discarded (corrected: filled, solid theory). The beam
scenario's rows ("sample_point/<kernel>") are plotted like the others, 2D = the beam, 3D = the point.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# Estimators come from the CSV (the registry's order); known ones keep their colours.
COLOURS = {"classic": "tab:red", "corrected": "tab:blue", "mse_optimal": "tab:green"}
OTHER_COLOURS = ["tab:purple", "tab:orange", "tab:brown", "tab:pink", "tab:olive", "tab:cyan", "tab:gray"]


def estimator_colours(rows):
    names = list(dict.fromkeys(r["estimator"] for r in rows))
    others = iter(OTHER_COLOURS * (1 + len(names) // len(OTHER_COLOURS)))
    return {n: COLOURS[n] if n in COLOURS else next(others) for n in names}


def num(s):
    if s in ("", None):
        return float("nan")
    if s in ("inf", "-inf"):
        return float(s)
    return float(s)


def legend(ax, **kwargs):
    """A legend only where something is labelled (matplotlib warns on an empty one)."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(**kwargs)


def plot_kernels(sub, out):
    dims = sorted({int(r["dim"]) for r in sub})
    kernels = list(dict.fromkeys(r["estimator"].split("/", 1)[1] if "/" in r["estimator"] else "constant" for r in sub))
    colours = dict(zip(kernels, (["tab:gray"] + OTHER_COLOURS + ["tab:red", "tab:blue"]) * 2))
    for kind in ("error", "mse"):
        fig, axes = plt.subplots(1, len(dims), figsize=(7 * len(dims), 5), squeeze=False)
        for ax, dim in zip(axes[0], dims):
            for kern in kernels:
                for est, fill, style in (("classic", "none", "--"), ("corrected", None, "-")):
                    label = est if kern == "constant" else f"{est}/{kern}"
                    rr = [r for r in sub if int(r["dim"]) == dim and r["estimator"] == label]
                    if not rr:
                        continue
                    k = [int(r["k"]) for r in rr]
                    y = [num(r["mean_rel_error" if kind == "error" else "rel_mse"]) for r in rr]
                    e = [num(r["se_mean" if kind == "error" else "se_mse"]) for r in rr]
                    th = [num(r["theory_rel_error" if kind == "error" else "theory_rel_mse"]) for r in rr]
                    ax.errorbar(k, y, yerr=e, fmt="o", ms=4, color=colours[kern], mfc=fill, capsize=2)
                    kt = [kk for kk, t in zip(k, th) if math.isfinite(t)]
                    tt = [t for t in th if math.isfinite(t)]
                    kept = "kept" if est == "classic" else "discarded"
                    ax.plot(kt, tt, style, color=colours[kern], lw=1, label=f"{kern}, k-th {kept}")
            ax.set_xscale("log")
            if kind == "error":
                ax.axhline(0.0, color="k", lw=0.5)
                ax.set_ylabel("relative error  E[S]/truth - 1")
            else:
                ax.set_yscale("log")
                ax.set_ylabel("relative MSE")
            ax.set_xlabel("k")
            ax.set_title(f"kernels, {dim}D (n = {sub[0]['n']}, {sub[0]['trials']} trials; lines: exact theory)")
            ax.grid(True, which="both", alpha=0.3)
            legend(ax, fontsize=6, ncol=2)
        fig.tight_layout()
        save(fig, os.path.join(out, f"study_{kind}_kernels"))


def save(fig, stem):
    """STEM.png for a look, STEM.pdf and STEM.svg (vector) for a paper; each written to a temporary
    and renamed, so a reader never sees half a file."""
    for ext in ("png", "pdf", "svg"):
        path = f"{stem}.{ext}"
        tmp = f"{path}.tmp-{os.getpid()}.{ext}"
        fig.savefig(tmp, dpi=110 if ext == "png" else None)
        os.replace(tmp, path)
    plt.close(fig)


def main():
    if len(sys.argv) == 2 and sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        with open(sys.argv[1], newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        print(f"plot_study: cannot read {sys.argv[1]}: {e.strerror}", file=sys.stderr)
        return 1
    out = sys.argv[2]
    colours = estimator_colours(rows)
    scenarios = sorted({r["scenario"] for r in rows}, key=lambda s: [r["scenario"] for r in rows].index(s))
    for sc in scenarios:
        sub = [r for r in rows if r["scenario"] == sc]
        if sc == "kernels":
            plot_kernels(sub, out)
            continue
        dims = sorted({int(r["dim"]) for r in sub})
        for kind in ("error", "mse"):
            fig, axes = plt.subplots(1, len(dims), figsize=(6 * len(dims), 4.5), squeeze=False)
            for ax, dim in zip(axes[0], dims):
                for est, col in colours.items():
                    rr = [r for r in sub if int(r["dim"]) == dim and r["estimator"] == est]
                    if not rr:
                        continue
                    k = [int(r["k"]) for r in rr]
                    if kind == "error":
                        y = [num(r["mean_rel_error"]) for r in rr]
                        e = [num(r["se_mean"]) for r in rr]
                        th = [num(r["theory_rel_error"]) for r in rr]
                        ax.errorbar(k, y, yerr=e, fmt="o", ms=3, color=col, capsize=2, label=f"{est} (measured)")
                    else:
                        y = [num(r["rel_mse"]) for r in rr]
                        e = [num(r["se_mse"]) for r in rr]
                        th = [num(r["theory_rel_mse"]) for r in rr]
                        ax.errorbar(k, y, yerr=e, fmt="o", ms=3, color=col, capsize=2, label=f"{est} (measured)")
                    kt = [kk for kk, t in zip(k, th) if math.isfinite(t)]
                    tt = [t for t in th if math.isfinite(t)]
                    if tt:
                        ax.plot(kt, tt, "-", color=col, lw=1, alpha=0.7, label=f"{est} (theory)")
                ax.set_xscale("log")
                if kind == "error":
                    ax.axhline(0.0, color="k", lw=0.5)
                    ax.set_ylabel("relative error  E[S]/truth - 1")
                    ax.set_ylim(-0.6, 1.1)
                else:
                    ax.set_yscale("log")
                    ax.set_ylabel("relative MSE")
                ax.set_xlabel("k")
                first = next((r for r in sub if int(r["dim"]) == dim), sub[0])   # n and trials of this panel
                what = {2: "beam estimate, 2D disc", 3: "point estimate, 3D"}[dim] if sc == "beam" else f"{dim}D"
                ax.set_title(f"{sc}, {what} (n = {first['n']}, {first['trials']} trials)")
                ax.grid(True, which="both", alpha=0.3)
                legend(ax, fontsize=7)
            fig.tight_layout()
            save(fig, os.path.join(out, f"study_{kind}_{sc}"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
