#!/usr/bin/env python3
"""Error against time of bench/progressive_convergence.sh's runs: a log-log SVG and fitted slopes.

    bench/progressive_plot.py OUT_DIR TITLE SVG [--closed-form VALUE] [--fit-from SECONDS]

OUT_DIR holds fixed.passes.csv and progressive.passes.csv. With --closed-form the error after each
pass is |running mean of the pass image means / VALUE - 1| (the half-space); else the rel_rmse
column (the run's --reference) with the reference's own noise (OUT_DIR/ref_noise.txt, a relative
variance, when present) subtracted from its square. Slopes are least-squares fits of log error on
log elapsed time, and on log passes, over the passes from --fit-from seconds on (default 2); the
overtaking time is the first elapsed time from which progressive's error stays below fixed's (fixed's
curve interpolated in log-log). No dependencies beyond Python 3.
"""
import argparse
import csv
import math
import os


def curve(path, closed_form, noise):
    t, e, n_passes = [], [], []
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
                err = float(row["rel_rmse"]) ** 2 - noise
                err = math.sqrt(err) if err > 0 else 0.0
            if elapsed > 0 and err > 0:
                t.append(elapsed)
                e.append(err)
                n_passes.append(int(row["pass"]) + 1)
    return t, e, n_passes


def overtakes(fixed, progressive):
    """First elapsed time from which progressive's error stays below fixed's (None: never)."""
    ft, fe = [math.log(x) for x in fixed[0]], [math.log(x) for x in fixed[1]]

    def fixed_at(lt):
        if lt <= ft[0]:
            return fe[0]
        for i in range(1, len(ft)):
            if lt <= ft[i]:
                w = (lt - ft[i - 1]) / max(1e-12, ft[i] - ft[i - 1])
                return fe[i - 1] + w * (fe[i] - fe[i - 1])
        return fe[-1]

    since = None
    for t, e in zip(progressive[0], progressive[1]):
        if math.log(e) < fixed_at(math.log(t)):
            since = t if since is None else since
        else:
            since = None
    return since


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
    out.append(f'<text x="{w / 2}" y="{h - 12}" text-anchor="middle">wall time (1 thread each, both at once, loaded machine); error: see docs/progressive.md</text>')
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
    noise_file = os.path.join(o.dir, "ref_noise.txt")
    noise = float(open(noise_file).read()) if o.closed_form is None and os.path.exists(noise_file) else 0.0
    curves, raw = {}, {}
    for name in ("fixed", "progressive"):
        t, e, n = curve(os.path.join(o.dir, name + ".passes.csv"), o.closed_form, noise)
        raw[name] = (t, e)
        curves[name] = (t, e, slope(t, e, o.fit_from))
        lo = next((p for p, x in zip(n, t) if x >= o.fit_from), 1)
        per_pass = slope(n, e, lo)
        last = e[-1] if e else float("nan")
        print(f"{o.dir} {name}: {n[-1] if n else 0} passes, {t[-1]:.1f} s, last error {last:.5f}, "
              f"slope from {o.fit_from:g} s {curves[name][2]:+.3f} (per pass {per_pass:+.3f})")
    since = overtakes(raw["fixed"], raw["progressive"])
    print(f"{o.dir}: reference noise (relative variance) {noise:.3g}; progressive below fixed from "
          + (f"{since:.1f} s on" if since is not None else "no time on"))
    svg(curves, o.title, o.svg)


if __name__ == "__main__":
    main()
