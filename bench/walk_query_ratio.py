#!/usr/bin/env python3
"""Walk / photon query cost ratios from one bench_walk_query JSON run with repetitions.

usage: python3 bench/walk_query_ratio.py out.json
Prints, per k, the mean CPU time per query of each form over the repetitions (with its standard
error) and the ratio walks / photons of the means, its standard error by the delta method, and
the ratio of the least times.
"""
import json
import math
import statistics
import sys
from collections import defaultdict


def main(path):
    with open(path) as f:
        runs = json.load(f)["benchmarks"]
    times = defaultdict(list)   # (k, walks) -> per-repetition us per query
    for r in runs:
        if r.get("run_type") != "iteration":
            continue
        name = r["run_name"] if "run_name" in r else r["name"]
        parts = dict(p.split(":") for p in name.split("/")[1:] if ":" in p)
        times[(int(parts["k"]), int(parts["walks"]))].append(r["us/query"])
    print("k     photons us (SE)     walks us (SE)      walks/photons (SE)   least/least  reps")
    for k in sorted({k for k, _ in times}):
        p, w = times[(k, 0)], times[(k, 1)]
        if not p or not w:
            continue
        mp, mw = statistics.mean(p), statistics.mean(w)
        sp = statistics.stdev(p) / math.sqrt(len(p)) if len(p) > 1 else float("nan")
        sw = statistics.stdev(w) / math.sqrt(len(w)) if len(w) > 1 else float("nan")
        ratio = mw / mp
        se = ratio * math.sqrt((sp / mp) ** 2 + (sw / mw) ** 2)
        print(f"{k:<5d} {mp:8.2f} ({sp:5.2f})    {mw:8.2f} ({sw:5.2f})    {ratio:6.3f} ({se:5.3f})       "
              f"{min(w) / min(p):6.3f}     {len(p)}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
