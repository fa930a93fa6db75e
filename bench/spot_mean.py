#!/usr/bin/python3
"""The mean luminance of a region (a caustic spot) per run against a two-half reference.

usage: /usr/bin/python3 bench/spot_mean.py OUT_DIR REF_DIR X0,Y0,X1,Y1 NAME...
  OUT_DIR/NAME/seed*.exr: one run per seed (bench/spot_mean.sh); REF_DIR/spot_a.exr, spot_b.exr: the
  halves (bench/spot_reference.sh). Prints per NAME the region's mean over seeds +- its standard error
  (the spread over seeds), the seeds, and the mean against the reference's, whose standard error comes
  from the halves' per-pixel difference (pixels are independent: var of the region's mean of the
  halves' mean = sum_p ((a_p - b_p) / 2)^2 / n^2, n - 1 degrees of freedom of sorts: one per pixel).
"""
import glob, os, re, sys
import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))

def read_exr(path):
    import importlib.util
    spec = importlib.util.spec_from_file_location("mc", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts", "metric_crosscheck.py"))
    src = open(spec.origin).read().split("\nY = lambda")[0]   # the reader only, not the script's main
    ns = {}
    exec(compile(src, spec.origin, "exec"), ns)
    return ns["read_exr"](path)

Y = lambda a: 0.2126 * a[..., 0] + 0.7152 * a[..., 1] + 0.0722 * a[..., 2]

def region(path, box):
    x0, y0, x1, y1 = box
    return Y(read_exr(path))[y0:y1, x0:x1]

def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    out, ref_dir, box = sys.argv[1], sys.argv[2], [int(v) for v in sys.argv[3].split(",")]
    a, b = region(os.path.join(ref_dir, "spot_a.exr"), box), region(os.path.join(ref_dir, "spot_b.exr"), box)
    n = a.size
    ref = 0.5 * (a.mean() + b.mean())
    ref_se = np.sqrt(np.sum(((a - b) / 2) ** 2)) / n
    print("reference: %.5f +- %.5f (%.2f%%), halves %.5f / %.5f" % (ref, ref_se, 100 * ref_se / ref, a.mean(), b.mean()))
    print("| run | seeds | region mean +- SE | against the reference +- SE (both SEs) |")
    print("|---|---:|---|---|")
    for name in sys.argv[4:]:
        files = sorted(glob.glob(os.path.join(out, name, "seed*.exr")), key=lambda f: int(re.findall(r"seed(\d+)", f)[0]))
        m = np.array([region(f, box).mean() for f in files])
        if len(m) < 2:
            print("| %s | %d | - | - |" % (name, len(m)))
            continue
        se = m.std(ddof=1) / np.sqrt(len(m))
        rel, rel_se = m.mean() / ref - 1, np.sqrt((se / ref) ** 2 + (m.mean() * ref_se / ref ** 2) ** 2)
        print("| %s | %d | %.5f +- %.5f | %+.2f%% +- %.2f%% |" % (name, len(m), m.mean(), se, 100 * rel, 100 * rel_se))

main()
