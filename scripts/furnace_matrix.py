#!/usr/bin/env python3
"""The furnace matrix (issue 57, item 4): cells whose exact image mean is known, each measured over
independent photon maps (the passes of `vpm render` runs, each pass its own map), with the deviation
from the exact answer in standard errors. docs/furnace_matrix.md has the table and the derivations.

Geometries (all non-absorbing, under a constant sky, every collision stored: direct = "photon_map"):
  fog       configs/uniform_furnace.toml: the camera at the centre of a fog sphere of optical radius
            3.6, sky 0.5 (the cells of the structured photon samplers).
  ball      a fog sphere (radius 1.5, sigma_t 1, g 0.5), sky 1, the camera outside at fov 20 (every
            pixel looks through the fog). An estimate (1 + b) L shows as (1 + F b) L, F = 1 - the mean
            transmittance of the camera rays (ball_estimated_share: 0.93683): the rest of each ray's
            weight is the sky seen through the fog. Classic b = 1/(k-1), corrected 0, mse_optimal
            -1/(k-1); point_beam has no k-1 factor (docs/beam_estimate.md).
  glass, touching, mirror, white_box
            the same with a clear glass sphere (radius 1, ior 1.5), two touching glass spheres, a
            two-sided mirror quad, or a closed Lambertian box of reflectance 1 in the fog. Exact 1
            (corrected): the radiance is 1 everywhere outside glass.
  camera_in_glass
            the glass sphere with the camera inside it: exact eta^2 = 2.25 (corrected).
  interior, interior_camera_in_glass
            the fog inside the glass sphere only (`interior_medium = 0`, docs/interior_medium.md),
            seen from outside (exact 1) and from inside the glass (exact 2.25).

Usage:
  scripts/furnace_matrix.py --vpm build/vpm [--target-se 0.003] [--only SUBSTRING ...] [--out PATH]
      every cell sized by a pilot: --pilot maps, then as many maps as make the standard error
      --target-se of the exact answer (at most --max-maps), measured on fresh seeds.
  scripts/furnace_matrix.py --vpm build/vpm --ci GROUP
      the CI-sized cells of GROUP (ctest label "furnace"), each with the map count recorded in CI_MAPS
      (from the pilot), fixed seeds; exits 1 unless every cell is within 3 standard errors.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

FOG = """[render]
width = 16
height = 16
integrator = "photon_map"
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
"""
CAMERA_OUTSIDE = """[camera]
position = [0, 0, 4]
look_at = [0, 0, 0]
fov = 20
"""
CAMERA_IN_GLASS = """[camera]
position = [0, 0, 0.3]
look_at = [0, 0, -1]
fov = 90
"""


def glass_sphere(x, radius):
    return f"""[[shapes]]
type = "sphere"
center = [{x}, 0, 0]
radius = {radius}
material = "dielectric"
ior = 1.5
"""


MIRROR = """[[shapes]]
type = "quad"
center = [0, 0, 0]
u = [0.8, 0, 0]
v = [0, 0.5, 0.5]
material = "mirror"
reflectance = 1.0
"""
WHITE_BOX = """[[shapes]]
type = "box"
min = [-0.5, -0.4, -0.6]
max = [0.6, 0.5, 0.4]
material = "lambertian"
reflectance = 1.0
"""

def ball_estimated_share(distance=4.0, radius=1.5, fov_degrees=20.0, n=600):
    """1 - the mean transmittance exp(-chord) of the camera rays through the unit-extinction ball, over
    the image plane (camera samples are uniform over it; midpoint rule, error below 1e-6)."""
    t = math.tan(math.radians(0.5 * fov_degrees))
    seen = 0.0
    for i in range(n):
        for j in range(n):
            x, y = (2 * (i + 0.5) / n - 1) * t, (2 * (j + 0.5) / n - 1) * t
            d2 = distance * distance * (x * x + y * y) / (1 + x * x + y * y)   # ray-centre distance squared
            seen += math.exp(-2 * math.sqrt(radius * radius - d2)) if d2 < radius * radius else 1.0
    return 1.0 - seen / (n * n)


# name -> (config text or path, exact image mean of an unbiased estimate, share of the image estimated
# (None: not derived, only "corrected" is a cell there)).
GEOMETRIES = {
    "fog": (os.path.join(REPO, "configs", "uniform_furnace.toml"), 0.5, 1.0 - math.exp(-0.6 * 6.0)),
    "ball": (CAMERA_OUTSIDE + FOG, 1.0, ball_estimated_share()),
    "glass": (CAMERA_OUTSIDE + FOG + glass_sphere(0, 1.0), 1.0, None),
    "camera_in_glass": (CAMERA_IN_GLASS + FOG + glass_sphere(0, 1.0), 2.25, None),
    "interior": (CAMERA_OUTSIDE + FOG + glass_sphere(0, 1.0) + "interior_medium = 0\n", 1.0, None),
    "interior_camera_in_glass": (CAMERA_IN_GLASS + FOG + glass_sphere(0, 1.0) + "interior_medium = 0\n", 2.25, None),
    "touching": (CAMERA_OUTSIDE + FOG + glass_sphere(-0.6, 0.6) + glass_sphere(0.6, 0.6), 1.0, None),
    "mirror": (CAMERA_OUTSIDE + FOG + MIRROR, 1.0, None),
    "white_box": (CAMERA_OUTSIDE + FOG + WHITE_BOX, 1.0, None),
}

GATHERS = ("collision", "march", "point_beam", "photon_beams")


ESTIMATE_FACTOR = {"classic": lambda k: k / (k - 1), "corrected": lambda k: 1.0, "mse_optimal": lambda k: (k - 2) / (k - 1)}

# The estimators each gather takes: point_beam's estimate is the same whatever photons.estimator says
# (a sample-point estimate, no k-1 factor: docs/beam_estimate.md), photon_beams refuses mse_optimal.
ESTIMATORS = {"collision": ("classic", "corrected", "mse_optimal"), "march": ("classic", "corrected", "mse_optimal"),
              "point_beam": ("corrected",), "photon_beams": ("classic", "corrected")}
POINT_GATHERS = ("collision", "march")
GLASS_GEOMETRIES = ("glass", "camera_in_glass", "touching", "interior", "interior_camera_in_glass")


def known_deviation(geometry, gather):
    """Why a cell's deviation is measured rather than asserted (docs/furnace_matrix.md), or None."""
    if geometry in GLASS_GEOMETRIES and gather not in POINT_GATHERS:
        return "the segment gathers' discs and beams are not split by region (the run warns)"
    if geometry == "white_box":
        return "kNN balls at the opaque box count its inside's extinction, where no photon is"
    return None


class Cell:
    """One cell and its verdict. An unpaired cell has an exact image mean. A paired cell is rendered on
    the same seeds, hence the same maps and camera samples, as its partner (`pair`), and checked per
    map against it:
      - classic or mse_optimal against corrected photon neighbours: given the k-th neighbour's radius
        the k-th photon's weight has the mean of the nearer ones', so in expectation each estimate is
        the corrected one times f = k/(k-1) or (k-2)/(k-1), and v - S = f (u - S) in the mean, S the
        map's sky part (shared); E[S] = T = truth (1 - F) makes d = v - T - f (u - T) of mean 0 exactly,
        whatever the walks' clustering adds to both;
      - corrected photon neighbours against walk neighbours: the clustering term (docs/walk_correlation.md,
        positive, measured: reported, not asserted)."""

    def __init__(self, geometry, gather, estimator, k, sampler="independent", neighbours=None, photons=None, pair=None,
                 extinction=None, widths=None):
        self.geometry, self.gather, self.estimator, self.k, self.sampler = geometry, gather, estimator, k, sampler
        self.widths = widths
        # The point gathers count walks unless named: exact for any k however one walk's photons cluster.
        self.neighbours = neighbours or ("walks" if gather in POINT_GATHERS and estimator == "corrected" else "photons")
        _, self.truth, self.share = GEOMETRIES[geometry]
        self.exact = self.truth
        self.pair = pair
        self.known = known_deviation(geometry, gather)
        if estimator != "corrected" and gather != "point_beam":
            assert pair is not None and self.share is not None, "a biased estimator is checked against its corrected twin"
        # point_beam's widths come from beam_k (photons.k does not enter it).
        self.sets = [f"photons.beam_k={k}" if gather == "point_beam" else f"photons.k={k}", f'photons.gather="{gather}"',
                     f'photons.estimator="{estimator}"', f'photons.sampler="{sampler}"', "render.width=16", "render.height=16"]
        if gather in POINT_GATHERS:
            self.sets.append(f'photons.neighbours="{self.neighbours}"')
        if photons:
            self.sets.append(f"photons.count={photons}")
        if extinction:
            self.sets.append(f'photons.extinction="{extinction}"')
        if widths:   # photon_beams' beam widths (photons.beam_widths)
            self.sets.append(f'photons.beam_widths="{widths}"')
        self.name = (f"{geometry} {gather} {estimator} k{k} {sampler}" + (" walks" if self.neighbours == "walks" else "") +
                     (f" {extinction}-extinction" if extinction else "") + (f" {widths}-widths" if widths else ""))

    def verdict(self, v, partner):
        """(mean, exact, se of the checked difference, z, asserted) for this cell's per-map means v."""
        m = sum(v) / len(v)
        if self.pair is None:
            _, se, _ = mean_se(v)
            return m, self.exact, se, (m - self.exact) / se, self.known is None
        if self.estimator == "corrected":   # photons against walks: the clustering term
            d = [a - b for a, b in zip(v, partner)]
            md, se, _ = mean_se(d)
            return m, m - md, se, md / se, False
        f, t = ESTIMATE_FACTOR[self.estimator](self.k), self.truth * (1.0 - self.share)
        d = [a - t - f * (b - t) for a, b in zip(v, partner)]
        md, se, _ = mean_se(d)
        return m, m - md, se, md / se, True


def ball_estimators(gather, maps, ci=False):
    """The estimator cells of one gather in the ball, (cell, maps). The asserted k-4 cells of the point
    gathers and every paired cell divide by the ball's mean extinction, which every estimator shares
    and which is exact in the furnace (the radiance is uniform): the default linear extinction weighs
    the photons by the estimator's own sums (docs/dense_bias.md) and reads high at k 4
    (docs/furnace_matrix.md), a measured cell of the full matrix."""
    if gather == "point_beam":
        return [(Cell("ball", gather, "corrected", k), maps) for k in (4, 32)]
    out = []
    if gather in POINT_GATHERS:
        walks = Cell("ball", gather, "corrected", 4, extinction="ball")
        out += [(walks, 2 * maps), (Cell("ball", gather, "corrected", 32), maps)]
        if not ci:
            out.append((Cell("ball", gather, "corrected", 4, pair=walks.name), 2 * maps))
        photons = Cell("ball", gather, "corrected", 4, neighbours="photons", pair=walks.name, extinction="ball")
        out.append((photons, 2 * maps))
    else:
        # photon_beams' balloon widths (the k nearest beams: the estimators' k - 1 factor applies) and its
        # density widths (fixed per beam: no estimator factor). The corrected balloon at k 4 scatters by
        # ~18% per map (a heavy tail): CI checks k 32.
        photons = Cell("ball", gather, "corrected", 32 if ci else 4, widths="balloon")
        out += [(photons, maps), (Cell("ball", gather, "corrected", 32, widths="density"), 2 * maps)]
        out += [] if ci else [(Cell("ball", gather, "corrected", 32, widths="balloon"), maps)]
    for estimator in ESTIMATORS[gather]:
        if estimator != "corrected":
            out.append((Cell("ball", gather, estimator, photons.k, pair=photons.name,
                             extinction="ball" if gather in POINT_GATHERS else None,
                             widths=photons.widths if gather == "photon_beams" else None), dict(out)[photons]))
    return out


def cells():
    """The full matrix: (cell, None), each cell sized by its pilot."""
    out = []
    for gather in GATHERS:
        out += [(c, None) for c, _ in ball_estimators(gather, 0)]
        if gather in POINT_GATHERS:
            out.append((Cell("ball", gather, "corrected", 8), None))
    for geometry in ("glass", "camera_in_glass", "touching", "interior", "interior_camera_in_glass", "mirror", "white_box"):
        out += [(Cell(geometry, gather, "corrected", 32), None) for gather in GATHERS]
    for sampler in ("independent", "stratified", "sobol"):   # issue 57, item 3
        for k in (4, 8):
            out += [(Cell("ball", "collision", "corrected", k, sampler), None),
                    (Cell("ball", "collision", "corrected", k, sampler, neighbours="photons"), None)]
    return out


# The CI-sized cells (ctest label "furnace"): group -> [(cell, maps)], fixed seeds. Map counts from
# the pilots (docs/furnace_matrix.md): one map of 50,000 photons scatters by 2-5% in the ball (the
# point gathers at k 4 the most), 7% seen from inside the glass; a beam map costs ~10x a point map.
POINT_MAPS, BEAM_MAPS = 64, 16
CI_GEOMETRIES = {"glass": ("glass", "touching", "camera_in_glass", "interior"), "surfaces": ("mirror", "white_box")}


def ci_cells(group):
    if group == "estimators":
        return [cm for g in GATHERS for cm in ball_estimators(g, POINT_MAPS if g in POINT_GATHERS else BEAM_MAPS, ci=True)]
    if group == "samplers":
        return [(Cell("ball", "collision", "corrected", k, sampler), 2 * POINT_MAPS) for k in (4, 8)
                for sampler in ("independent", "stratified", "sobol")]
    if group in CI_GEOMETRIES:   # the known deviations are measured by the full matrix, not in CI
        return [(Cell(geo, g, "corrected", 32), (POINT_MAPS if g in POINT_GATHERS else BEAM_MAPS) * (2 if geo == "camera_in_glass" else 1))
                for geo in CI_GEOMETRIES[group] for g in GATHERS if known_deviation(geo, g) is None]
    sys.exit(f"--ci: unknown group {group!r} (estimators, samplers, {', '.join(CI_GEOMETRIES)})")


def run_maps(vpm, cell, maps, seed, workdir, threads, extra=(), spp_per_pass=2):
    """Image means of `maps` independent photon maps: runs of at most 256 passes (the sidecar's limit),
    each its own seed."""
    text, _, _ = GEOMETRIES[cell.geometry]
    if text.endswith(".toml"):
        path = text
    else:
        path = os.path.join(workdir, "cell.toml")
        with open(path, "w") as f:
            f.write(text)
    out = os.path.join(workdir, "cell.exr")
    means = []
    run = 0
    while len(means) < maps:
        passes = min(256, maps - len(means))
        if passes < 2:
            passes = 2
        cmd = [vpm, "render", "-q", path, "-o", out, "--threads", str(threads),
               "--set", f"render.passes={passes}", "--set", f"render.spp={passes * spp_per_pass}",
               "--set", f"render.seed={seed + 1000 * run}"]
        for s in cell.sets + list(extra):
            cmd += ["--set", s]
        subprocess.run(cmd, check=True)
        with open(out[:-4] + ".json") as f:
            means += json.load(f)["passes"]["image_mean"]
        run += 1
    return means[:max(maps, 2)]


def mean_se(v):
    n = len(v)
    m = sum(v) / n
    sd = math.sqrt(sum((x - m) ** 2 for x in v) / (n - 1))
    return m, sd / math.sqrt(n), sd


def row(cell, v, partner):
    m, exact, se, z, asserted = cell.verdict(v, partner)
    note = "" if asserted else " (measured)"
    return z, asserted, (f"| {cell.name}{' vs ' + cell.pair if cell.pair else ''} | {len(v)} | {m:.5f} | {se:.5f} | "
                         f"{100 * se / exact:.2f}% | {exact:.5f}{note} | {100 * (m / exact - 1):+.2f}% | {z:+.2f} |")


HEADER = ["| cell | maps | mean | SE | SE/exact | exact | deviation | z |", "|---|---|---|---|---|---|---|---|"]
SEED_STRIDE = 500000   # the measurement's seeds after the pilot's


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--vpm", default=os.path.join(REPO, "build", "vpm"))
    ap.add_argument("--ci", metavar="GROUP", help="the CI-sized cells of GROUP; exit 1 unless all within 3 SE")
    ap.add_argument("--maps", type=int, help="with --ci: this many maps per cell instead of the recorded count")
    ap.add_argument("--pilot", type=int, default=16, help="pilot maps per cell (sizes the measurement)")
    ap.add_argument("--target-se", type=float, default=0.003, help="relative standard error each cell aims at")
    ap.add_argument("--max-maps", type=int, default=2048, help="at most this many maps per cell")
    ap.add_argument("--seed", type=int, default=57, help="first seed (the pilot's; the measurement's differ)")
    ap.add_argument("--threads", type=int, default=0, help="vpm --threads (0: all cores)")
    ap.add_argument("--set", action="append", default=[], help="a config override added to every cell (vpm --set)")
    ap.add_argument("--only", action="append", default=[], help="keep the cells whose name holds every SUBSTRING")
    ap.add_argument("--out", help="write the markdown table here too")
    ap.add_argument("--values", help="write every cell's per-map image means here (JSON: name -> list)")
    a = ap.parse_args()
    rows = list(HEADER)
    failed = []
    values = {}
    with tempfile.TemporaryDirectory() as work:
        todo = ci_cells(a.ci) if a.ci else cells()
        todo = [(c, a.maps or n) for c, n in todo if all(s in c.name for s in a.only) or any(c.name == p.pair for p, _ in todo
                                                                                          if all(s in p.name for s in a.only))]
        sized = {}
        for cell, maps in todo:
            if cell.pair in sized:   # a paired cell: its partner's maps and seeds
                maps = sized[cell.pair]
            elif maps is None:
                sd = mean_se(run_maps(a.vpm, cell, a.pilot, a.seed, work, a.threads, a.set))[2]
                maps = min(a.max_maps, max(a.pilot, math.ceil((sd / (a.target_se * cell.exact)) ** 2)))
            sized[cell.name] = maps
            v = run_maps(a.vpm, cell, maps, a.seed + (0 if a.ci else SEED_STRIDE), work, a.threads, a.set)
            values[cell.name] = v
            z, asserted, line = row(cell, v, values.get(cell.pair))
            print(line, flush=True)
            rows.append(line)
            if asserted and abs(z) > 3.0:
                failed.append(cell.name)
    if a.out:
        with open(a.out, "w") as f:
            f.write("\n".join(rows) + "\n")
    if a.values:
        with open(a.values, "w") as f:
            json.dump(values, f)
    if a.ci and failed:
        sys.exit("outside 3 standard errors: " + ", ".join(failed))


if __name__ == "__main__":
    main()
