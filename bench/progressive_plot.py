#!/usr/bin/env python3
"""Error against time of bench/progressive_convergence.sh's runs: a log-log SVG and fitted slopes.

    bench/progressive_plot.py OUT_DIR TITLE SVG [--closed-form VALUE] [--fit-from SECONDS]

OUT_DIR holds fixed.passes.csv and progressive.passes.csv. With --closed-form the error after each
pass is |running mean of the pass image means / VALUE - 1| (the half-space); else the rel_rmse
column (the run's --reference). Slopes are least-squares fits of log error on log elapsed time over
the passes from --fit-from seconds on (default 2). No dependencies beyond Python 3.
"""
import argparse
import csv
import math
import os


def curve(path, closed_form):
    t, e = [], []
    total, n = 0.0, 0
    with open(path) as f:
        for row in csv.DictReader(f):
            elapsed = float(row["elapsed_s"])
            if closed_form is not None:
                passes = int(row["passes"])
                total += float(row["image_mean"]) * passes
                n += passes
                err = abs(total / n / closed_form - 1.0)
            else:
                err = float(row["rel_rmse"])
            if elapsed > 0 and err > 0:
                t.append(elapsed)
                e.append(err)
    return t, e


def slope(t, e, lo):
    pts = [(math.log(a), math.log(b)) for a, b in zip(t, e) if a >= lo]
    if len(pts) < 3:
        return float("nan")
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx if sxx > 0 else float("nan")


def svg(curves, title, path):
    w, h, m = 560, 380, 60
    ts = [x for c in curves.values() for x in c[0]]
    es = [x for c in curves.values() for x in c[1]]
    lt0, lt1 = math.floor(math.log10(min(ts))), math.ceil(math.log10(max(ts)))
    le0, le1 = math.floor(math.log10(min(es))), math.ceil(math.log10(max(es)))
    X = lambda t: m + (math.log10(t) - lt0) / max(1e-9, lt1 - lt0) * (w - 1.5 * m)
    Y = lambda e: h - m + -(math.log10(e) - le0) / max(1e-9, le1 - le0) * (h - 1.7 * m)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">',
           f'<rect width="{w}" height="{h}" fill="white"/>',
           f'<text x="{w / 2}" y="20" text-anchor="middle" font-size="14">{title}</text>']
    for d in range(lt0, lt1 + 1):
        out.append(f'<line x1="{X(10 ** d):.1f}" y1="{Y(10 ** le0):.1f}" x2="{X(10 ** d):.1f}" y2="{Y(10 ** le1):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{X(10 ** d):.1f}" y="{h - m + 18}" text-anchor="middle">{10 ** d:g} s</text>')
    for d in range(le0, le1 + 1):
        out.append(f'<line x1="{X(10 ** lt0):.1f}" y1="{Y(10 ** d):.1f}" x2="{X(10 ** lt1):.1f}" y2="{Y(10 ** d):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{m - 6}" y="{Y(10 ** d) + 4:.1f}" text-anchor="end">1e{d}</text>')
    colours = {"fixed": "#c0392b", "progressive": "#2166ac"}
    for i, (name, (t, e, s)) in enumerate(curves.items()):
        pts = " ".join(f"{X(a):.1f},{Y(b):.1f}" for a, b in zip(t, e))
        out.append(f'<polyline fill="none" stroke="{colours.get(name, "black")}" stroke-width="1.5" points="{pts}"/>')
        out.append(f'<text x="{w - 1.5 * m + 5}" y="{60 + 18 * i}" fill="{colours.get(name, "black")}">{name} ({s:+.2f})</text>')
    out.append(f'<text x="{w / 2}" y="{h - 12}" text-anchor="middle">wall time (2 threads, loaded machine); error: see docs/progressive.md</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    a = argparse.ArgumentParser()
    a.add_argument("dir")
    a.add_argument("title")
    a.add_argument("svg")
    a.add_argument("--closed-form", type=float)
    a.add_argument("--fit-from", type=float, default=2.0)
    o = a.parse_args()
    curves = {}
    for name in ("fixed", "progressive"):
        t, e = curve(os.path.join(o.dir, name + ".passes.csv"), o.closed_form)
        curves[name] = (t, e, slope(t, e, o.fit_from))
        last = e[-1] if e else float("nan")
        print(f"{o.dir} {name}: {len(t)} passes, {t[-1]:.1f} s, last error {last:.5f}, slope from {o.fit_from:g} s {curves[name][2]:+.3f}")
    svg(curves, o.title, o.svg)


if __name__ == "__main__":
    main()
