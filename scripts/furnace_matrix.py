#!/usr/bin/env python3
"""The furnace matrix (issue 57, item 4): cells whose exact image mean is known, each measured over
independent photon maps (the passes of one `vpm render` run, each pass its own map), with the
deviation from the exact answer in standard errors.

Geometries (all non-absorbing, under a constant sky):
  fog    configs/uniform_furnace.toml: the camera inside a fog sphere of optical radius 3.6, sky 0.5.
         An estimate (1 + b) L shows as (1 + (1 - e^-3.6) b) L (tests/support/furnace.h):
         classic b = 1/(k-1), corrected 0, mse_optimal -1/(k-1).
  glass  a fog sphere (radius 1.5, g 0.5) around a clear glass sphere (radius 1, photons.ior), sky 1,
         the camera outside at fov 20 so every pixel looks through the glass: exact 1 (corrected).

Usage: scripts/furnace_matrix.py --vpm build/vpm [--passes 64] [--only SUBSTRING ...] [--out PATH]
Each cell prints a line as it finishes; the table goes to --out (markdown) and stdout.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SKY_SHARE_FOG = math.exp(-0.6 * 6.0)   # camera rays of the fog furnace that see the sky itself

GLASS = """[render]
width = 16
height = 16
integrator = "photon_map"
[camera]
position = [0, 0, 4]
look_at = [0, 0, 0]
fov = 20
[photons]
count = 50000
k = 32
direct = "photon_map"
[[lights]]
type = "environment"
radiance = 1.0
[[media]]
type = "homogeneous"
shape = "sphere"
radius = 1.5
sigma_t_scale = 1.0
albedo = 1.0
g = 0.5
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1.0
material = "dielectric"
ior = IOR
"""

ESTIMATE_BIAS = {"classic": lambda k: 1.0 / (k - 1), "corrected": lambda k: 0.0, "mse_optimal": lambda k: -1.0 / (k - 1)}


def cells():
    """(name, config path or glass ior, --set list, exact image mean)."""
    out = []
    for gather in ("collision", "march", "point_beam", "photon_beams"):
        # The beam gathers' widths come from their own neighbours (beam_k): only "corrected" has an
        # exact answer stated for them here.
        estimators = ("classic", "corrected", "mse_optimal") if gather in ("collision", "march") else ("corrected",)
        for estimator in estimators:
            for k in (4, 8, 32):
                for sampler in ("independent", "stratified", "sobol"):
                    exact = 0.5 * (1.0 + (1.0 - SKY_SHARE_FOG) * ESTIMATE_BIAS[estimator](k))
                    sets = ["render.width=16", "render.height=16", "photons.count=40000", f"photons.k={k}",
                            f'photons.gather="{gather}"', f'photons.estimator="{estimator}"', f'photons.sampler="{sampler}"']
                    out.append((f"fog {gather} {estimator} k{k} {sampler}", "fog", sets, exact))
    for ior in ("1.0001", "1.5", "3.9"):
        out.append((f"glass ior {ior} collision corrected k32 independent", ior,
                    ['photons.gather="collision"', 'photons.estimator="corrected"'], 1.0))
    return out


def measure(vpm, config, sets, passes, spp_per_pass, workdir):
    if config == "fog":
        path = os.path.join(REPO, "configs", "uniform_furnace.toml")
    else:
        path = os.path.join(workdir, "glass.toml")
        with open(path, "w") as f:
            f.write(GLASS.replace("IOR", config))
    out = os.path.join(workdir, "cell.exr")
    cmd = [vpm, "render", "-q", path, "-o", out, "--set", f"render.passes={passes}",
           "--set", f"render.spp={passes * spp_per_pass}"]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True)
    with open(out[:-4] + ".json") as f:
        v = json.load(f)["passes"]["image_mean"]
    n = len(v)
    m = sum(v) / n
    se = math.sqrt(sum((x - m) ** 2 for x in v) / (n - 1) / n)
    return m, se, n


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--vpm", default=os.path.join(REPO, "build", "vpm"))
    ap.add_argument("--passes", type=int, default=64, help="independent photon maps per cell (<= 256)")
    ap.add_argument("--spp", type=int, default=2, help="camera samples per pixel and pass")
    ap.add_argument("--only", action="append", default=[], help="keep the cells whose name holds every SUBSTRING")
    ap.add_argument("--out", help="write the markdown table here too")
    a = ap.parse_args()
    if not 2 <= a.passes <= 256:
        sys.exit("--passes: 2 .. 256 (the sidecar records at most 256 passes)")
    rows = ["| cell | maps | mean | SE | exact | deviation | z |", "|---|---|---|---|---|---|---|"]
    with tempfile.TemporaryDirectory() as work:
        for name, config, sets, exact in cells():
            if not all(s in name for s in a.only):
                continue
            m, se, n = measure(a.vpm, config, sets, a.passes, a.spp, work)
            z = (m - exact) / se if se > 0 else float("inf")
            row = f"| {name} | {n} | {m:.5f} | {se:.5f} | {exact:.5f} | {100 * (m / exact - 1):+.2f}% | {z:+.2f} |"
            print(row, flush=True)
            rows.append(row)
    if a.out:
        with open(a.out, "w") as f:
            f.write("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
