#!/usr/bin/python3
"""Table of bench/glass_split_equal_time.sh's runs.csv files: per scene and variant the relMSE, the
linear relRMSE and CPU seconds per seed, and relMSE x CPU s over the old binary's, paired by seed
(mean +- standard error over the seeds).

usage: python3 bench/glass_split_table.py RUNS.csv...
"""
import csv, math, sys
from collections import defaultdict

def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    rows = defaultdict(dict)   # (scene, variant) -> seed -> row
    for path in sys.argv[1:]:
        for r in csv.DictReader(open(path)):
            rows[(r["scene"], r["variant"])][r["seed"]] = r
    scenes = sorted({s for s, _ in rows}, key=lambda s: s)
    print("| scene | variant | seeds | relMSE | linear relRMSE | CPU s | relMSE x CPU s / old, paired |")
    print("|---|---|---|---|---|---|---:|")
    for scene in scenes:
        old = rows.get((scene, "old"), {})
        for variant in sorted(v for s, v in rows if s == scene):
            runs = rows[(scene, variant)]
            seeds = sorted(runs)
            col = lambda k, f: " / ".join(f % float(runs[s][k]) for s in seeds)
            ratios = [float(runs[s]["relmse"]) * float(runs[s]["cpu_s"]) /
                      (float(old[s]["relmse"]) * float(old[s]["cpu_s"])) for s in seeds if s in old]
            if variant == "old" or not ratios:
                ratio = "1"
            else:
                m = sum(ratios) / len(ratios)
                se = math.sqrt(sum((x - m) ** 2 for x in ratios) / (len(ratios) - 1) / len(ratios)) if len(ratios) > 1 else float("nan")
                ratio = "%.2f +- %.2f" % (m, se)
            print("| %s | %s | %s | %s | %s | %s | %s |" % (scene, variant, " ".join(seeds), col("relmse", "%.4f"),
                                                         col("relrmse", "%.3f"), col("cpu_s", "%.2f"), ratio))

main()
