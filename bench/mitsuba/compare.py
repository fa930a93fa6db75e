#!/usr/bin/env python3
"""Tables for bench/mitsuba/equal_spp.sh's folder (docs/studies/path_tracer_vs_mitsuba.md).

    python3 bench/mitsuba/compare.py agree DIR [--scenes ...]
        Agreement: per scene and renderer, the image mean of luminance over the seeds +- its standard
        error (from the seeds' spread), and per region (a 4 x 4 grid of blocks) the difference
        Mitsuba - vpm over its standard error; the largest |z| and the count beyond 3.
    python3 bench/mitsuba/compare.py efficiency DIR [--refs bench/caustic_references] [--vpm build/vpm]
        Equal time: per scene, renderer (vpm, "vpm before" = vpm0, Mitsuba) and spp, relMSE (reference
        noise subtracted, `vpm compare --reference-halves`) and CPU seconds over the seeds all ran;
        the time to equal relMSE, relMSE x CPU s, over vpm's (a ratio > 1: vpm is faster), its
        standard error from the relMSE's spread over the seeds.
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
        m = re.match(r"(.+)_(vpm0|vpm|mitsuba)_(\d+)_(\d+)$", os.path.basename(base))
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
    names = {"vpm0": "vpm before", "vpm": "vpm", "mitsuba": "Mitsuba"}
    print("| scene | spp | renderer | seeds | CPU s | relMSE | relRMSE | relMSE x CPU s | / vpm's |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|")
    for scene in scenes:
        ref = halves(scene, args)
        if not ref:
            print(f"| {scene} | | (no reference halves) | | | | | | |")
            continue
        for spp in sorted({k[2] for k in r if k[0] == scene}):
            rows = {}
            for ren in ("vpm0", "vpm", "mitsuba"):
                per = r.get((scene, ren, spp), {})
                vals = {}
                for seed in sorted(per):
                    base = per[seed]
                    t = json.load(open(base + ".time"))
                    m = json.loads(subprocess.check_output([args.vpm, "compare", "--json", "--reference-halves", ref[0],
                                                            ref[1], base + ".exr"]))
                    m = m.get("images", [m])[0]
                    vals[seed] = (t["cpu_s"], m["relmse"]["value"], m["relrmse"]["value"])
                if vals:
                    rows[ren] = vals
            if "vpm" not in rows:
                continue
            seeds = sorted(set.intersection(*(set(v) for v in rows.values())))
            # Time to equal relMSE: mean relMSE x mean CPU s; its standard error from the relMSE's
            # spread over the seeds (CPU seconds vary little against it).
            eff = {}
            for ren, vals in rows.items():
                cpu = sum(vals[s][0] for s in seeds) / len(seeds)
                mse, se = mean_se([vals[s][1] for s in seeds])
                rr = sum(vals[s][2] for s in seeds) / len(seeds)
                eff[ren] = (cpu, mse, se, rr)
            cv, mv, sv, _ = eff["vpm"]
            for ren in ("vpm0", "vpm", "mitsuba"):
                if ren not in eff:
                    continue
                cpu, mse, se, rr = eff[ren]
                ratio = (mse * cpu) / (mv * cv)
                rse = 0.0 if ren == "vpm" else ratio * math.hypot(sv / mv, se / mse)
                print(f"| {scene} | {spp} | {names[ren]} | {len(seeds)} | {cpu:.2f} | {mse:.4g} +- {se:.2g} | {rr:.3g} | "
                      f"{mse * cpu:.4g} | {ratio:.2f} +- {rse:.2f} |")


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
