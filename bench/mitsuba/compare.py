#!/usr/bin/env python3
"""Tables for bench/mitsuba/equal_spp.sh's folder (docs/studies/path_tracer_vs_mitsuba.md).

    python3 bench/mitsuba/compare.py agree DIR [--scenes ...]
        Agreement: per scene and renderer, the image mean of luminance over the seeds +- its standard
        error (from the seeds' spread), and per region (a 4 x 4 grid of blocks) the difference
        Mitsuba - vpm over its standard error; the largest |z| and the count beyond 3.
    python3 bench/mitsuba/compare.py efficiency DIR [--refs bench/caustic_references] [--vpm build/vpm]
        Equal time: per scene, renderer and spp, relMSE (reference noise subtracted, `vpm compare
        --reference-halves`) and CPU seconds per seed; the time to equal relMSE, relMSE x CPU s,
        Mitsuba over vpm with a standard error from the per-seed products (a ratio > 1: vpm is faster).
        A scene without halves in --refs uses REFS/SCENE_{a,b}.exr if present, else DIR/../SCENE_{a,b}.exr.

The metrics come from `vpm compare`; the region means read the EXRs with Mitsuba's Bitmap (run it
with the Mitsuba venv's python) or else the `OpenEXR` module.
"""
import argparse
import glob
import json
import math
import os
import re
import subprocess
import sys


def read_exr(path):
    import numpy as np
    try:
        import mitsuba as mi
        mi.set_variant("scalar_rgb")
        a = np.array(mi.Bitmap(path), dtype=np.float64)
        return a[..., :3]
    except ImportError:
        pass
    try:
        import OpenEXR
        import Imath
        f = OpenEXR.InputFile(path)
        dw = f.header()["dataWindow"]
        w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
        pt = Imath.PixelType(Imath.PixelType.FLOAT)
        ch = [np.frombuffer(f.channel(c, pt), dtype=np.float32).reshape(h, w) for c in "RGB"]
        return np.stack(ch, axis=-1).astype(np.float64)
    except ImportError:
        sys.exit("compare.py: reading EXR needs mitsuba (run with the Mitsuba venv's python) or OpenEXR")


def luminance(a):
    return 0.2126 * a[..., 0] + 0.7152 * a[..., 1] + 0.0722 * a[..., 2]


def runs(folder):
    """{(scene, renderer, spp): {seed: basepath}}"""
    out = {}
    for t in glob.glob(os.path.join(folder, "*.time")):
        base = t[:-5]
        m = re.match(r"(.+)_(vpm|mitsuba)_(\d+)_(\d+)$", os.path.basename(base))
        if not m or not os.path.exists(base + ".exr"):
            continue
        out.setdefault((m.group(1), m.group(2), int(m.group(3))), {})[int(m.group(4))] = base
    return out


def mean_se(xs):
    n = len(xs)
    m = sum(xs) / n
    if n < 2:
        return m, float("nan")
    v = sum((x - m) ** 2 for x in xs) / (n - 1)
    return m, math.sqrt(v / n)


def agree(args):
    import numpy as np
    r = runs(args.dir)
    scenes = sorted({k[0] for k in r})
    if args.scenes:
        scenes = [s for s in scenes if s in args.scenes]
    g = args.grid
    print(f"| scene | spp x seeds (vpm / Mitsuba) | vpm mean | Mitsuba mean | Mitsuba / vpm - 1 | z | regions |z| > 3 of {g * g} | max |z| |")
    print("|---|---|---|---|---|---:|---:|---:|")
    for scene in scenes:
        sets = {}
        for ren in ("vpm", "mitsuba"):
            keys = [k for k in r if k[0] == scene and k[1] == ren]
            if not keys:
                break
            k = max(keys, key=lambda k: k[2])
            imgs = [luminance(read_exr(r[k][s] + ".exr")) for s in sorted(r[k])]
            sets[ren] = (k[2], np.stack(imgs))
        if len(sets) < 2:
            continue
        (sv, v), (sm, m) = sets["vpm"], sets["mitsuba"]
        mv, ev = mean_se([float(x.mean()) for x in v])
        mm, em = mean_se([float(x.mean()) for x in m])
        z = (mm - mv) / math.hypot(ev, em)
        h, w = v.shape[1:]
        zs = []
        for by in range(g):
            for bx in range(g):
                sl = (slice(None), slice(by * h // g, (by + 1) * h // g), slice(bx * w // g, (bx + 1) * w // g))
                a, ea = mean_se([float(x.mean()) for x in v[sl]])
                b, eb = mean_se([float(x.mean()) for x in m[sl]])
                se = math.hypot(ea, eb)
                zs.append((b - a) / se if se > 0 else 0.0)
        zs = np.array(zs)
        print(f"| {scene} | {sv} x {len(v)} / {sm} x {len(m)} | {mv:.5f} +- {ev:.5f} | {mm:.5f} +- {em:.5f} | "
              f"{mm / mv - 1:+.4f} +- {math.hypot(ev / mv, em / mm):.4f} | {z:+.2f} | {int((abs(zs) > 3).sum())} | "
              f"{abs(zs).max():.2f} |")


def halves(scene, args):
    for d in (args.refs, os.path.join(args.dir, "..")):
        a, b = os.path.join(d, f"{scene}_a.exr"), os.path.join(d, f"{scene}_b.exr")
        if os.path.exists(a) and os.path.exists(b):
            return a, b
    return None


def efficiency(args):
    r = runs(args.dir)
    scenes = sorted({k[0] for k in r})
    if args.scenes:
        scenes = [s for s in scenes if s in args.scenes]
    print("| scene | spp | seeds | vpm CPU s | vpm relMSE | Mitsuba CPU s | Mitsuba relMSE | vpm relRMSE | Mitsuba relRMSE | "
          "relMSE x CPU: Mitsuba / vpm |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for scene in scenes:
        ref = halves(scene, args)
        if not ref:
            print(f"| {scene} | (no reference halves) |")
            continue
        for spp in sorted({k[2] for k in r if k[0] == scene}):
            rows = {}
            for ren in ("vpm", "mitsuba"):
                per = r.get((scene, ren, spp), {})
                vals = []
                for seed in sorted(per):
                    base = per[seed]
                    t = json.load(open(base + ".time"))
                    m = json.loads(subprocess.check_output([args.vpm, "compare", "--json", "--reference-halves", ref[0],
                                                            ref[1], base + ".exr"]))
                    m = m.get("images", [m])[0]
                    vals.append((seed, t["cpu_s"], m["relmse"]["value"], m["relrmse"]["value"]))
                rows[ren] = vals
            if not rows["vpm"] or not rows["mitsuba"]:
                continue
            seeds = sorted(set(s for s, *_ in rows["vpm"]) & set(s for s, *_ in rows["mitsuba"]))

            def col(ren, i):
                return [v[i] for v in rows[ren] if v[0] in seeds]
            cv, em_v, rr_v = col("vpm", 1), col("vpm", 2), col("vpm", 3)
            cm, em_m, rr_m = col("mitsuba", 1), col("mitsuba", 2), col("mitsuba", 3)
            # Time to equal relMSE: mean relMSE x mean CPU s; the ratio's standard error from the
            # relMSE's spread over the seeds (CPU seconds vary little against it).
            mv, sv = mean_se(em_v)
            mm, sm = mean_se(em_m)
            tv, tm = sum(cv) / len(cv), sum(cm) / len(cm)
            ratio = (mm * tm) / (mv * tv)
            se = ratio * math.hypot(sv / mv if mv else 0, sm / mm if mm else 0)
            print(f"| {scene} | {spp} | {len(seeds)} | {tv:.2f} | {mv:.4g} +- {sv:.2g} | {tm:.2f} | {mm:.4g} +- {sm:.2g} | "
                  f"{sum(rr_v) / len(rr_v):.3g} | {sum(rr_m) / len(rr_m):.3g} | **{ratio:.2f} +- {se:.2f}** |")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mode", choices=["agree", "efficiency"])
    ap.add_argument("dir")
    ap.add_argument("--scenes", nargs="*")
    ap.add_argument("--grid", type=int, default=4)
    ap.add_argument("--refs", default="bench/caustic_references")
    ap.add_argument("--vpm", default="build/vpm")
    args = ap.parse_args()
    agree(args) if args.mode == "agree" else efficiency(args)


if __name__ == "__main__":
    main()
