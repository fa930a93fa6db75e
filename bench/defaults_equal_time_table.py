#!/usr/bin/env python3
"""The table of bench/defaults_equal_time.sh: relMSE per pixel at equal CPU time.

    bench/defaults_equal_time_table.py OUT [VPM] [--skip SCENE,SCENE]

For every scene, seed and candidate (OUT/SCENE/CAND.sSEED.*): the run's CPU seconds (user + system,
from /usr/bin/time), its error after every pass (CAND.sSEED.passes.csv, against the merged reference),
and the final image's relMSE with the reference halves' noise subtracted (vpm compare
--reference-halves). The noise floor the halves give is subtracted from every pass's relMSE too (the
same reference, so the same floor). A pass's CPU time is the run's CPU seconds times its share of
the run's wall time (the candidates run at once, so the load scales them alike). Equal time: each
candidate's relMSE interpolated at T, the least CPU time of the four runs of that scene and seed.
Ratios are against photons.fixed (today's default) of the same scene and seed; the summary is the
geometric mean over scenes and seeds, +- one standard error of the mean log ratio.
"""
import csv
import json
import math
import os
import subprocess
import sys

CANDIDATES = ["photons.fixed", "walks.fixed", "photons.progressive", "walks.progressive"]
BASE = "photons.fixed"


def cpu_seconds(path):
    for line in open(path):
        parts = line.split()
        if len(parts) == 3:
            try:
                return float(parts[0]) + float(parts[1])
            except ValueError:
                pass
    raise SystemExit(f"{path}: no CPU times (did the run fail?)")


def compare(vpm, scene_dir, image, epsilon):
    out = subprocess.run([vpm, "compare", "--reference-halves", os.path.join(scene_dir, "ref_0.exr"),
                          os.path.join(scene_dir, "ref_8.exr"), image, "--epsilon", epsilon, "--json"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def run(vpm, scene_dir, name, epsilon):
    stem = os.path.join(scene_dir, name)
    rows = list(csv.DictReader(open(stem + ".passes.csv")))
    final = compare(vpm, scene_dir, stem + ".exr", epsilon)
    floor = final["relmse"]["noise_floor"]
    cpu = cpu_seconds(stem + ".time")
    wall = float(rows[-1]["elapsed_s"])
    curve = [(cpu * float(r["elapsed_s"]) / wall, float(r["relMSE"]) - floor) for r in rows]
    return {"cpu": cpu, "curve": curve, "final": final["relmse"]["value"], "floor": floor,
            "bias": final["relative_bias"], "passes": len(rows)}


def at_time(curve, t):
    for (t0, e0), (t1, e1) in zip(curve, curve[1:]):
        if t0 <= t <= t1:
            return e0 + (e1 - e0) * (t - t0) / (t1 - t0) if t1 > t0 else e1
    return curve[-1][1] if t >= curve[-1][0] else curve[0][1]


def main():
    args = sys.argv[1:]
    skip = set()
    if "--skip" in args:
        i = args.index("--skip")
        skip = set(args[i + 1].split(","))
        del args[i:i + 2]
    out = args[0]
    vpm = args[1] if len(args) > 1 else "./build/vpm"
    scenes = sorted(d for d in os.listdir(out)
                    if os.path.isfile(os.path.join(out, d, "epsilon.txt")) and d not in skip)
    logs = {c: [] for c in CANDIDATES}
    per_scene = {}   # scene -> candidate -> log ratios
    same_passes = {c: [] for c in CANDIDATES}   # log ratios of the final images (equal passes)
    print("| scene | seed | T (CPU s) | " + " | ".join(f"{c}: relMSE at T (ratio), bias, CPU s" for c in CANDIDATES) + " |")
    print("|---|---|---|" + "---|" * len(CANDIDATES))
    for scene in scenes:
        d = os.path.join(out, scene)
        eps = open(os.path.join(d, "epsilon.txt")).read().strip()
        seeds = sorted({f.split(".s")[-1].split(".")[0] for f in os.listdir(d) if f.endswith(".time")})
        for seed in seeds:
            runs = {}
            for c in CANDIDATES:
                if os.path.exists(os.path.join(d, f"{c}.s{seed}.passes.csv")):
                    runs[c] = run(vpm, d, f"{c}.s{seed}", eps)
            if len(runs) < len(CANDIDATES):
                continue
            t = min(r["cpu"] for r in runs.values())
            err = {c: at_time(runs[c]["curve"], t) for c in CANDIDATES}
            cells = []
            for c in CANDIDATES:
                ratio = err[c] / err[BASE]
                if c != BASE:
                    logs[c].append(math.log(ratio))
                    per_scene.setdefault(scene, {}).setdefault(c, []).append(math.log(ratio))
                    same_passes[c].append(math.log(runs[c]["final"] / runs[BASE]["final"]))
                cells.append(f"{err[c]:.3g} ({ratio:.3f}), {100 * runs[c]['bias']:+.2f}%, {runs[c]['cpu']:.1f}")
            print(f"| {scene} | {seed} | {t:.1f} | " + " | ".join(cells) + " |")
    print()
    print("| scene | " + " | ".join(f"{c} / {BASE}" for c in CANDIDATES[1:]) + " |")
    print("|---|" + "---|" * (len(CANDIDATES) - 1))
    for scene, by in per_scene.items():
        print(f"| {scene} | " + " | ".join(f"{math.exp(sum(by[c]) / len(by[c])):.3f}" for c in CANDIDATES[1:]) + " |")
    print()
    print("At equal CPU time:")
    print()
    summary(logs)
    print()
    print("At equal passes (the final images, whatever their CPU time):")
    print()
    summary(same_passes)


def summary(logs):
    print("| candidate | relMSE / photons.fixed, geometric mean | +- SE (factor) | better / worse | pairs |")
    print("|---|---|---|---|---|")
    for c in CANDIDATES[1:]:
        v = logs[c]
        if not v:
            continue
        m = sum(v) / len(v)
        se = math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1) / len(v)) if len(v) > 1 else float("nan")
        better = sum(1 for x in v if x < 0)
        print(f"| {c} | {math.exp(m):.3f} | x/ {math.exp(se):.3f} | {better} / {len(v) - better} | {len(v)} |")


if __name__ == "__main__":
    main()
