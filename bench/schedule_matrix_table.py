#!/usr/bin/env python3
"""The table of bench/schedule_matrix.sh's runs: per cell, fixed against progressive at equal time.

    bench/schedule_matrix_table.py OUT_DIR [OUT_DIR...]

Reads OUT_DIR/runs/CELL.{fixed,progressive}.passes.csv and .json (the sidecar names the reference,
whose .json beside it holds the reference's own relative noise, noise_rel_variance, removed here from
the squared error). Prints a Markdown table and the geometric mean of progressive's mean squared
error over fixed's (< 1: progressive better at equal time). No dependencies beyond Python 3.
"""
import csv
import glob
import json
import math
import os
import sys


def last_row(path):
    return list(csv.DictReader(open(path)))[-1]


def main():
    rows = []
    for d in sys.argv[1:]:
        for f in sorted(glob.glob(os.path.join(d, "runs", "*.fixed.passes.csv"))):
            stem = f[: -len(".fixed.passes.csv")]
            if not os.path.exists(stem + ".progressive.passes.csv"):
                continue
            side = json.load(open(stem + ".fixed.json"))
            ref = side["reference"]["file"]
            noise = json.load(open(ref[: -len(".exr")] + ".json"))["noise_rel_variance"]
            r = {"cell": os.path.basename(stem), "dir": d, "gather": side.get("gather_used", "?")}
            for s in ("fixed", "progressive"):
                last = last_row(f"{stem}.{s}.passes.csv")
                mse = max(0.0, float(last["rel_rmse"]) ** 2 - noise)
                r[s] = (int(last["pass"]), float(last["elapsed_s"]), mse, float(last["rel_mean_error"]))
            r["ratio"] = r["progressive"][2] / r["fixed"][2] if r["fixed"][2] > 0 else float("nan")
            rows.append(r)
    print("| cell | gather | fixed: passes, s, rel. RMSE, mean error | progressive: passes, s, rel. RMSE, mean error | MSE progressive / fixed |")
    print("|---|---|---|---|---|")
    for r in rows:
        cells = []
        for s in ("fixed", "progressive"):
            p, t, mse, me = r[s]
            cells.append(f"{p}, {t:.1f}, {math.sqrt(mse):.4f}, {me * 100:+.2f}%")
        print(f"| {r['cell']} | {r['gather']} | {cells[0]} | {cells[1]} | {r['ratio']:.3f} |")
    good = [r["ratio"] for r in rows if r["ratio"] > 0 and math.isfinite(r["ratio"])]
    if good:
        gm = math.exp(sum(math.log(x) for x in good) / len(good))
        print(f"\n{len(good)} cells: geometric mean of MSE progressive / fixed {gm:.3f}; "
              f"progressive better in {sum(x < 1 for x in good)}, worse in {sum(x > 1 for x in good)}; "
              f"range {min(good):.3f} .. {max(good):.3f}")


if __name__ == "__main__":
    main()
