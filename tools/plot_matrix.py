#!/usr/bin/python3
"""Heat map for `vpm bench matrix`; every number comes from matrix.csv (written by the C++ tool).

usage: /usr/bin/python3 tools/plot_matrix.py OUT_DIR/matrix.csv
writes OUT_DIR/matrix.png: one row per cell, one column per photon-map setting (defaults, collision
and march forced, the pilot's choice, the beam gather), colour = log10 of its time to equal error over the path tracer's
(error^2 x seconds ratio; blue < 1: the photon map is faster), the ratio printed in each square.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import TwoSlopeNorm  # noqa: E402

COLUMNS = [("photon_map_over_path", "photon map\n(defaults)"), ("pm_collision_over_path", "collision\nforced"),
           ("pm_march_over_path", "march\nforced"), ("pm_pilot_over_path", "pilot"),
           ("pm_beam_over_path", "beam\nforced")]


def num(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return float("nan")


def main():
    if len(sys.argv) == 2 and sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return
    if len(sys.argv) != 2:
        sys.exit("usage: plot_matrix.py OUT_DIR/matrix.csv")
    path = sys.argv[1]
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit("plot_matrix.py: cannot read %s: %s" % (path, e.strerror))
    if not rows:
        sys.exit("plot_matrix.py: " + path + " has no rows")
    labels = ["%s | %s" % (r["group"], r["cell"]) for r in rows]
    data = []
    for r in rows:
        line = []
        for key, _ in COLUMNS:
            v = num(r.get(key))
            line.append(math.log10(v) if v > 0 and math.isfinite(v) else float("nan"))
        data.append(line)
    finite = [abs(v) for line in data for v in line if math.isfinite(v)]
    lim = max(1.0, max(finite) if finite else 1.0)
    fig, ax = plt.subplots(figsize=(6.5, 1.2 + 0.24 * len(rows)))
    im = ax.imshow(data, cmap="RdBu_r", norm=TwoSlopeNorm(vmin=-lim, vcenter=0.0, vmax=lim), aspect="auto")
    ax.set_xticks(range(len(COLUMNS)))
    ax.set_xticklabels([c[1] for c in COLUMNS], fontsize=8)
    ax.xaxis.tick_top()
    ax.set_yticks(range(len(rows)))
    ax.set_yticklabels(labels, fontsize=6)
    for i, line in enumerate(data):
        for j, v in enumerate(line):
            text = "%.2g" % (10 ** v) if math.isfinite(v) else "n/a"
            ax.text(j, i, text, ha="center", va="center", fontsize=6, color="black")
    cb = fig.colorbar(im, ax=ax, fraction=0.05, pad=0.02)
    cb.set_label("log10 time to equal error / path tracer", fontsize=7)
    fig.tight_layout()
    out = os.path.join(os.path.dirname(os.path.abspath(path)), "matrix")
    for ext in ("png", "pdf", "svg"):   # PNG for a look, PDF and SVG (vector) for a paper
        fig.savefig(f"{out}.{ext}", dpi=130 if ext == "png" else None)
    print("plot_matrix.py: wrote " + out + ".png, .pdf, .svg")


if __name__ == "__main__":
    main()
