#!/usr/bin/env python3
"""The half-space's bias split into its parts (issue 56 item 4), from bench_halfspace_split --dump.

  ./build/bench_halfspace_split --maps 1200 --k 32 --dump out/split_k32.csv > out/split_k32.txt
  python3 bench/halfspace_split.py out/split_k32.csv K [DEPTH_STEP] [MOVED_TRUTH] [SCALE]

For every column of the dump, the camera's integral sum_j albedo exp(-z_j) dz v(z_j) is formed per map
and divided by the same integral of the map's own depth histogram (truth_mid; MOVED_TRUTH names the
moved maps' column, truth_mid unless given); the figures are ratios of means over maps, minus 1, with paired
delta-method standard errors. "pred" is the derivation for independent points: at each depth the
fixed-radius mean F(r) at the radius whose mean count C(r) is T ~ Gamma(k - 1, 1), averaged over T
(F and C from the moved maps, interpolated in r; depths whose count grid does not reach T's 0.999
quantile keep the measured "moved" value and are reported); with SCALE, pred is for SCALE times the
photons per map (C scaled, F unchanged). Then the same by depth, every DEPTH_STEP-th depth (default 5).
"""
import math
import sys

import numpy as np
from scipy import stats


def influence(num, den):
    """mean(num) / mean(den) - 1 and each map's influence on it (delta method; rows = maps)."""
    r = num.mean() / den.mean()
    return r - 1.0, (num - r * den) / den.mean()


def ratio(num, den):
    """mean(num) / mean(den) - 1 with its standard error over maps."""
    e, d = influence(num, den)
    return e, d.std(ddof=1) / math.sqrt(len(num))


def difference(a, ta, b, tb):
    """(mean(a) / mean(ta)) - (mean(b) / mean(tb)) with its paired standard error over maps."""
    ea, da = influence(a, ta)
    eb, db = influence(b, tb)
    return ea - eb, (da - db).std(ddof=1) / math.sqrt(len(a))


def main():
    path, k = sys.argv[1], int(sys.argv[2])
    step = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    mt = sys.argv[4] if len(sys.argv) > 4 else "truth_mid"   # the moved maps' truth
    # pred at SCALE times the photons (the count C(r) scaled, the power density F(r) unchanged)
    scale = float(sys.argv[5]) if len(sys.argv) > 5 else 1.0
    with open(path) as f:
        names = f.readline().strip().split(",")
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    column = {n: i for i, n in enumerate(names)}
    depths = np.unique(table[:, column["depth"]])
    nd = len(depths)
    nm = len(table) // nd   # complete maps only
    table = table[: nm * nd]
    radii = np.array([float(n[1:]) for n in names if n.startswith("F")])

    def grid(name):   # (maps, depths)
        return table[:, column[name]].reshape(nm, nd)

    cols = {n: grid(n) for n in ("photons", "walks", "moved", "fixed", "fixed_m", "truth_mid", "truth_all", "rk_moved", "rk_photons")}
    Fr = np.stack([grid(f"F{r:.2f}") for r in radii], axis=2)   # (maps, depths, radii)
    Cr = np.stack([grid(f"C{r:.2f}") for r in radii], axis=2)
    Fm, Cm = Fr.mean(axis=0), scale * Cr.mean(axis=0)   # the fixed-radius mean and count at each depth

    # The Gamma(k - 1) mixture of F over radii, per map's F (the mean count C from all maps): paired
    # with the other columns map by map.
    u = (np.arange(4000) + 0.5) / 4000
    T = stats.gamma.ppf(u, k - 1)
    top = stats.gamma.ppf(0.999, k - 1)
    def mixture(counts, fallback):
        """Per map and depth: F averaged over the radius at which `counts` (mean over maps) is T."""
        out, done = fallback.copy(), []
        for j in range(nd):
            if counts[j, -1] < top or counts[j, 0] > T[0]:
                continue
            done.append(j)
            r_of_T = np.interp(T, counts[j], radii)
            for m in range(nm):
                out[m, j] = np.interp(r_of_T, radii, Fr[m, j]).mean()
        return out, done

    pred, covered = mixture(Cm, cols["moved"])
    has_walks = "W0.20" in column
    if has_walks:   # the walk form: the same mixture over the walks met within r
        Wm = np.stack([grid(f"W{r:.2f}") for r in radii], axis=2).mean(axis=0)
        pred_walks, covered_walks = mixture(Wm, cols["walks"])
    z = depths
    w = 0.5 * np.exp(-z) * (z[1] - z[0])
    cam = {n: (v * w).sum(axis=1) for n, v in cols.items()}
    cam["pred"] = (pred * w).sum(axis=1)
    if has_walks:
        cam["pred_walks"] = (pred_walks * w).sum(axis=1)
    print(f"{path}: {nm} maps, k {k}; pred from F, C at depths {z[covered[0]]:.2f}..{z[covered[-1]]:.2f} "
          f"(camera weight covered {w[covered].sum() / w.sum() * 100:.1f}% of sum exp(-z) dz; the rest measured)")
    print(f"camera integral of truth_mid {cam['truth_mid'].mean():.6g}, truth_all {cam['truth_all'].mean():.6g} "
          f"(closed form 0.0311476 over z in 0..{z[-1] + (z[1] - z[0]) / 2:g})")
    lines = [("photons (renderer default)", "photons", "truth_mid"), ("walks", "walks", "truth_mid"),
             ("fixed r0 (tracer's photons)", "fixed", "truth_mid"), ("moved (independent), kNN", "moved", mt),
             ("pred: Gamma(k-1) mix of F", "pred", mt), ("fixed r0 (moved)", "fixed_m", mt)]
    if has_walks:
        lines.append(("pred_walks: walks' Gamma(k-1) mix", "pred_walks", "truth_mid"))
        print(f"  (pred_walks from F, W at depths {z[covered_walks[0]]:.2f}..{z[covered_walks[-1]]:.2f}; "
              f"camera weight covered {w[covered_walks].sum() / w.sum() * 100:.1f}%, the rest measured)")
    for label, a, b in lines:
        e, s = ratio(cam[a], cam[b])
        print(f"  {label:32s} {100 * e:+.2f}% +- {100 * s:.2f}%")
    truth_of = {"photons": "truth_mid", "walks": "truth_mid", "fixed": "truth_mid", "moved": mt, "pred": mt,
                "fixed_m": mt, "pred_walks": "truth_mid"}
    print("  paired differences of the relative errors:")
    for label, a, b in (("photons - moved (clustering)", "photons", "moved"), ("walks - moved", "walks", "moved"),
                        ("photons - walks", "photons", "walks"), ("moved - pred", "moved", "pred"),
                        ("moved - fixed_m", "moved", "fixed_m"), ("fixed - fixed_m", "fixed", "fixed_m")) + \
            ((("walks - pred_walks", "walks", "pred_walks"),) if has_walks else ()):
        e, se = difference(cam[a], cam[truth_of[a]], cam[b], cam[truth_of[b]])
        print(f"  {label:32s} {100 * e:+.2f}% +- {100 * se:.2f}%")
    print("depth, r_k (tracer's photons), r_k (moved), photons, walks, moved, pred, fixed(r0), fixed_m(r0)"
          + (", pred_walks" if has_walks else "") + ": % against the histogram, +- SE")
    for j in range(0, nd, step):
        row = [f"{z[j]:.2f}", f"{cols['rk_photons'][:, j].mean():.3f}", f"{cols['rk_moved'][:, j].mean():.3f}"]
        for a, b in (("photons", "truth_mid"), ("walks", "truth_mid"), ("moved", mt), ("pred", mt),
                     ("fixed", "truth_mid"), ("fixed_m", mt)) + ((("pred_walks", "truth_mid"),) if has_walks else ()):
            if (a == "pred" and j not in covered) or (a == "pred_walks" and j not in covered_walks):
                row.append("-")
                continue
            num = pred[:, j] if a == "pred" else pred_walks[:, j] if a == "pred_walks" else cols[a][:, j]
            e, s = ratio(num, cols[b][:, j])
            row.append(f"{100 * e:+.2f} +- {100 * s:.2f}")
        print(" | ".join(row))


if __name__ == "__main__":
    main()
