#!/usr/bin/env python3
"""The caustic study's equal-time table from bench/caustic_equal_time.sh's runs.csv
(docs/studies/caustic_scenes.md).

Per scene and method, each seed's figures (seed 1 / seed 2): what ran, wall and CPU seconds, relMSE
(the references' noise floor subtracted, docs/metrics.md), relRMSE (linear: sqrt(mean (I - R)^2) /
mean R, its floor subtracted too) and relative bias; and the cost ratio, the mean relMSE x mean CPU
seconds over the path tracer's.

Usage: python3 bench/caustic_table.py out/caustic_equal_time/runs.csv
"""
import csv
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


if __name__ == "__main__":
    main()
