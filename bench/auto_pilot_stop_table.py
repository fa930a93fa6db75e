#!/usr/bin/env python3
"""bench/auto_pilot_stop.sh's runs as one table: per scene, auto / the forced photon map paired by
seed (relMSE x CPU s, and CPU s alone) with the BEFORE and the AFTER binary, standard errors from the
seeds' spread; the seeds where auto's image equals the photon map's relMSE; the path tracer's pilot
samples per pixel (after), how often it stopped early, and the counted pilot work and pilot phase
wall seconds from the sidecars.

Usage: python3 bench/auto_pilot_stop_table.py OUT_DIR [OUT_DIR ...]   (each with before/ and after/)
"""
import csv
import json
import math
import sys
from collections import defaultdict


def mean_se(xs):
    m = sum(xs) / len(xs)
    if len(xs) < 2:
        return m, float("nan")
    return m, math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1) / len(xs))


def load(dirs, side):
    runs = defaultdict(dict)   # (scene, seed) -> method -> row (with the sidecar's auto figures)
    for d in dirs:
        for r in csv.DictReader(open(f"{d}/{side}/runs.csv")):
            side_json = json.load(open(f"{d}/{side}/{r['scene']}_{r['method']}_{r['seed']}.json"))
            r["auto"] = side_json.get("photons", {}).get("auto_gather", {})
            r["pilot_s"] = side_json.get("phases", {}).get("pilot", {}).get("seconds", 0.0)
            runs[(r["scene"], int(r["seed"]))][r["method"]] = r
    return runs


def main():
    dirs = sys.argv[1:]
    sides = {s: load(dirs, s) for s in ("before", "after")}
    scenes = sorted({k[0] for k in sides["after"]}, key=lambda s: list(dict.fromkeys(k[0] for k in sides["after"])).index(s))
    print("| scene | seeds | auto / photon_map, relMSE x CPU s: before | after | CPU s alone: before | after "
          "| same relMSE (before, after) | path pilot samples per pixel (after) | counted pilot s: before / after |")
    print("|---|---:|---:|---:|---:|---:|---|---|---|")
    for scene in scenes:
        cols = []
        same = []
        for side in ("before", "after"):
            ratio, cpu, eq = [], [], 0
            for (sc, seed), m in sorted(sides[side].items()):
                if sc != scene or "auto" not in m or "photon_map" not in m:
                    continue
                a, p = m["auto"], m["photon_map"]
                ratio.append(float(a["relmse"]) * float(a["cpu_s"]) / (float(p["relmse"]) * float(p["cpu_s"])))
                cpu.append(float(a["cpu_s"]) / float(p["cpu_s"]))
                eq += a["relmse"] == p["relmse"]
            cols.append((mean_se(ratio), mean_se(cpu), len(ratio)))
            same.append(eq)
        samples, stopped, work = [], 0, {"before": [], "after": []}
        for side in ("before", "after"):
            for (sc, seed), m in sorted(sides[side].items()):
                if sc == scene and "auto" in m:
                    work[side].append(float(m["auto"]["auto"].get("pilot_work", 0.0)) / 1e9)
                    if side == "after":
                        ag = m["auto"]["auto"]
                        samples.append(ag["pilot_samples"][-1])
                        stopped += bool(ag.get("stopped_early", [False])[-1])
        f = lambda ms: "%.3f +- %.3f" % ms
        print(f"| {scene} | {cols[1][2]} | {f(cols[0][0])} | **{f(cols[1][0])}** | {f(cols[0][1])} | {f(cols[1][1])} "
              f"| {same[0]}, {same[1]} of {cols[1][2]} | {' / '.join(map(str, samples))} ({stopped} stopped) "
              f"| {mean_se(work['before'])[0]:.3f} / {mean_se(work['after'])[0]:.3f} |")


if __name__ == "__main__":
    main()
