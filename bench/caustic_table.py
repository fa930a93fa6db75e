#!/usr/bin/env python3
"""The caustic study's equal-time table from bench/caustic_equal_time.sh's runs.csv
(docs/studies/caustic_scenes.md).

Per scene and method: each seed's wall and CPU seconds, relMSE (the references' noise floor
subtracted, docs/metrics.md), relRMSE (linear: sqrt(mean (I - R)^2) / mean R, its floor subtracted
too) and relative bias, and the cost ratio relMSE x CPU seconds over the path tracer's of the same
seed. The last column: the mean of the two seeds' ratios.

Usage: python3 bench/caustic_table.py out/caustic_equal_time/runs.csv
"""
import csv
import sys
from collections import defaultdict


def main():
    rows = list(csv.DictReader(open(sys.argv[1])))
    by = defaultdict(dict)
    for r in rows:
        by[(r["scene"], r["seed"])][r["method"]] = r
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    methods = ["path", "photon_map", "auto", "point_beam", "photon_beams"]
    for scene in scenes:
        seeds = sorted({r["seed"] for r in rows if r["scene"] == scene})
        floors = [float(by[(scene, s)][m]["relmse_floor"]) for s in seeds for m in by[(scene, s)]]
        print("\n### %s (relMSE noise floor of the reference %.4g)\n" % (scene, max(floors) if floors else 0.0))
        print("| method | seed | chose | wall s | CPU s | relMSE | relRMSE | rel. bias | relMSE x CPU / path |")
        print("|---|---|---|---:|---:|---:|---:|---:|---:|")
        for m in methods:
            ratios = []
            for s in seeds:
                r = by[(scene, s)].get(m)
                if r is None:
                    continue
                path = by[(scene, s)].get("path")
                ratio = ""
                if path and float(path["relmse"]) > 0 and float(path["cpu_s"]) > 0:
                    x = float(r["relmse"]) * float(r["cpu_s"]) / (float(path["relmse"]) * float(path["cpu_s"]))
                    ratios.append(x)
                    ratio = "%.3g" % x
                chose = r["integrator_used"] + ("" if r["integrator_used"] == "path" else ", " + r["gather_used"])
                print("| %s | %s | %s | %.1f | %.2f | %.4g | %.4g | %+.3f | %s |" % (
                    m, s, chose, float(r["wall_s"]), float(r["cpu_s"]), float(r["relmse"]), float(r["relrmse"]),
                    float(r["relative_bias"]), ratio))
            if len(ratios) > 1:
                print("| %s | mean | | | | | | | %.3g |" % (m, sum(ratios) / len(ratios)))


if __name__ == "__main__":
    main()
