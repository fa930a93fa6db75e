#!/usr/bin/env python3
"""The caustic study's equal-time table from bench/caustic_equal_time.sh's runs.csv
(docs/studies/caustic_scenes.md).

Per scene and method, each seed's figures (seed 1 / seed 2): what ran, wall and CPU seconds, relMSE
(the references' noise floor subtracted, docs/metrics.md), relRMSE (linear: sqrt(mean (I - R)^2) /
mean R, its floor subtracted too) and relative bias; and the cost ratio, the mean relMSE x mean CPU
seconds over the path tracer's. After each scene: auto's relMSE x CPU over the best forced method's
(standard error from the seeds' spread) and, paired by seed, over the forced photon_map's.

Usage: python3 bench/caustic_table.py out/caustic_equal_time/runs.csv
"""
import csv
import math
import sys
from collections import defaultdict


def main():
    rows = list(csv.DictReader(open(sys.argv[1])))
    by = defaultdict(dict)
    for r in rows:
        by[r["scene"]].setdefault(r["method"], []).append(r)
    methods = ["path", "photon_map", "auto", "point_beam", "photon_beams"]
    for scene, runs in by.items():
        floor = max(float(r["relmse_floor"]) for rs in runs.values() for r in rs)
        linear_floor = max(float(r["relrmse_floor"]) for rs in runs.values() for r in rs)
        print("\n### %s (the references' noise floors, subtracted: relMSE %.4g, relRMSE %.3g)\n" % (scene, floor, linear_floor))
        print("| method | chose | wall s | CPU s | relMSE | relRMSE | rel. bias | relMSE x CPU / path |")
        print("|---|---|---|---|---|---|---|---:|")
        mean = lambda rs, key: sum(float(r[key]) for r in rs) / len(rs)
        path = runs.get("path")
        for m in methods:
            rs = sorted(runs.get(m, []), key=lambda r: r["seed"])
            if not rs:
                continue
            join = lambda key, fmt: " / ".join(fmt % float(r[key]) for r in rs)
            chose = " / ".join(r["integrator_used"] + ("" if r["integrator_used"] == "path" else " " + r["gather_used"])
                               for r in rs)
            ratio = ""
            if path and mean(path, "relmse") > 0:
                ratio = "%.3g" % (mean(rs, "relmse") * mean(rs, "cpu_s") / (mean(path, "relmse") * mean(path, "cpu_s")))
            print("| %s | %s | %s | %s | %s | %s | %s | %s |" % (
                m, chose, join("wall_s", "%.1f"), join("cpu_s", "%.2f"), join("relmse", "%.4g"),
                join("relrmse", "%.3g"), join("relative_bias", "%+.3f"), ratio))
        auto_line(runs)


def cost(rs):
    """Mean relMSE x mean CPU seconds over the seeds, and its standard error from their spread."""
    n = len(rs)
    e = [float(r["relmse"]) for r in rs]
    t = [float(r["cpu_s"]) for r in rs]
    me, mt = sum(e) / n, sum(t) / n
    se = lambda xs, m: math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1) / n) if n > 1 else float("nan")
    return me * mt, me * mt * math.hypot(se(e, me) / me, se(t, mt) / mt)


def auto_line(runs):
    """auto against the best forced method (least mean relMSE x mean CPU), and paired per seed
    against the forced photon_map (both sizes and images often agree: the ratio's spread is then the
    pilot's and the load's alone)."""
    if "auto" not in runs:
        return
    forced = {m: cost(rs) for m, rs in runs.items() if m != "auto" and rs}
    if not forced:
        return
    best = min(forced, key=lambda m: forced[m][0])
    a, b = cost(runs["auto"]), forced[best]
    ratio = a[0] / b[0]
    line = "\nauto / best forced (%s), relMSE x CPU s: %.3g +- %.2g" % (best, ratio, ratio * math.hypot(a[1] / a[0], b[1] / b[0]))
    pm = {r["seed"]: r for r in runs.get("photon_map", [])}
    paired = [float(r["relmse"]) * float(r["cpu_s"]) / (float(pm[r["seed"]]["relmse"]) * float(pm[r["seed"]]["cpu_s"]))
              for r in runs["auto"] if r["seed"] in pm]
    if len(paired) > 1:
        m = sum(paired) / len(paired)
        se = math.sqrt(sum((x - m) ** 2 for x in paired) / (len(paired) - 1) / len(paired))
        line += "; auto / photon_map paired by seed: %.3g +- %.2g (%d seeds)" % (m, se, len(paired))
    print(line)


if __name__ == "__main__":
    main()
