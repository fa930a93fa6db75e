#!/usr/bin/env python3
"""The half-space's kNN bias split into walk clustering and the adaptive radius (issue 56 item 4).

The half-space of bench/halfspace_bias.sh (albedo 0.5, sigma_t 1, box [-10,10]x[-10,0]x[-10,10],
a directional light straight down, 8000 photons a map). Its photon density depends on depth alone
away from the side faces, so moving every photon sideways by an independent offset, uniform in a
disc of radius D, keeps the density where the camera looks (|x|, |z| <= 3) and makes the photons
independent points (siblings end up ~D apart, far beyond a kNN ball). On the same maps:

  real      the tracer's photons, photon-neighbour corrected (k)   walk clustering + adaptive radius
  walks     the tracer's photons, walk-neighbour corrected (k)     adaptive radius, clustering removed
  shuffled  the moved photons, photon-neighbour corrected (k)      adaptive radius alone
  fixed     the tracer's photons, a count in a ball of radius r0   the reference (smoothing only)

Each estimate is divided by the part of its ball inside the medium (photons.extinction = "ball" for
sigma_t = 1: vpm.PhotonMap.estimate has no "linear" extinction, the renderer's default, so these are
the "ball" estimator's figures, and near the lit face its clipped balls read low for all four alike), at depth points y_j on a grid under 49 lateral points, and the camera's
integral sum_j albedo S(y_j) exp(y_j) dy is formed per map; the figures are the ratios of the
map-mean integrals to the fixed-radius one, with standard errors over maps (paired).
usage: PYTHONPATH=build/python python3 bench/halfspace_shuffle.py MAPS K [D=2] [R0=0.9]
"""
import math
import sys

import numpy as np

import vpm

ALBEDO = 0.5


def cap_fraction(depth, r):
    """Share of a ball of radius r centred `depth` below the plane y = 0 that lies below it."""
    h = np.clip(r - depth, 0.0, 2 * r)   # height of the cap above the plane
    cap = math.pi * h * h * (3 * r - h) / 3.0
    return 1.0 - cap / (4.0 / 3.0 * math.pi * r ** 3)


def main():
    maps, k = int(sys.argv[1]), int(sys.argv[2])
    D = float(sys.argv[3]) if len(sys.argv) > 3 else 2.0
    r0 = float(sys.argv[4]) if len(sys.argv) > 4 else 0.9
    config = vpm.load_config("configs/semi_infinite.toml", overrides={
        "media.0.albedo": ALBEDO, "media.0.min": [-10, -10, -10], "media.0.max": [10, 0, 10],
        "photons.count": 8000, "photons.k": k, "render.integrator": "photon_map", "photons.gather": "collision",
        "photons.direct": "photon_map"})
    lateral = np.array([(x, z) for x in np.linspace(-3, 3, 7) for z in np.linspace(-3, 3, 7)])
    dy = 0.1
    depths = np.arange(dy / 2, 8.0, dy)   # midpoints; exp(-8) of the integral left out, common to all
    pts = np.array([(x, -d, z) for (x, z) in lateral for d in depths])
    depth_of = -pts[:, 1]
    wo = np.tile([0.0, 1.0, 0.0], (len(pts), 1))
    weight = ALBEDO * np.exp(-depth_of) * dy / len(lateral)
    rng = np.random.default_rng(56)
    rows = []
    for m in range(maps):
        real = vpm.trace_photons(config, stream_offset=m, threads=1)
        pos, pw, di = real.positions, real.powers, real.directions
        a = rng.uniform(0, 2 * math.pi, len(pos))
        rr = D * np.sqrt(rng.uniform(0, 1, len(pos)))
        moved = pos.copy()
        moved[:, 0] += rr * np.cos(a)
        moved[:, 2] += rr * np.sin(a)
        shuffled = vpm.PhotonMap(moved, pw, di)
        out = []
        for mp, hood in ((real, "photons"), (real, "walks"), (shuffled, "photons")):
            v, r = mp.estimate(pts, wo, estimator="corrected", k=k, g=0.0, neighbours=hood, return_radius=True)
            out.append(np.sum(weight * v[:, 0] / cap_fraction(depth_of, r)))
        v = real.estimate(pts, wo, estimator="classic", k=len(real), g=0.0, max_radius=r0)
        out.append(np.sum(weight * v[:, 0] / cap_fraction(depth_of, r0)))
        rows.append(out)
        if (m + 1) % 50 == 0:
            report(np.array(rows), k, D, r0)
    report(np.array(rows), k, D, r0)


def report(x, k, D, r0):
    n = len(x)
    ref = x[:, 3].mean()
    print(f"maps {n}, k {k}, D {D}, r0 {r0}: fixed-radius integral {ref:.6g} +- {x[:, 3].std(ddof=1) / math.sqrt(n):.2g}")
    for j, name in enumerate(("real (photons)", "walks", "shuffled (photons)")):
        # ratio of means with a paired delta-method SE
        ratio = x[:, j].mean() / ref
        d = x[:, j] / ref - ratio * x[:, 3] / ref
        print(f"  {name:20s} {100 * (ratio - 1):+.2f}% +- {100 * d.std(ddof=1) / math.sqrt(n):.2f}%")
    for a, b, name in ((0, 2, "real - shuffled (walk clustering)"), (0, 1, "real - walks")):
        d = (x[:, a] - x[:, b]) / ref
        print(f"  {name:36s} {100 * d.mean():+.2f}% +- {100 * d.std(ddof=1) / math.sqrt(n):.2f}%")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
