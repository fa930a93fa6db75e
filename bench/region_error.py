#!/usr/bin/python3
"""Error per region: the pixels where the camera sees an area light (straight or through mirrors and
glass: vpm compare --exclude-lights) against the rest, from two `vpm compare --json` runs per image
(all pixels; lights excluded), the reference's noise floor subtracted in each.

usage: python3 bench/region_error.py VPM CONFIG REF_A.exr REF_B.exr IMAGE.exr...
Prints per image: relMSE over the rest and over the lights' pixels, the linear relRMSE (relative to
the whole image's reference mean) of the rest and of the lights' pixels, and the lights' share of the
image's linear squared error.
"""
import json, subprocess, sys

def compare(vpm, ref_a, ref_b, image, extra):
    out = subprocess.run([vpm, "compare", "--json", "--reference-halves", ref_a, ref_b, image] + extra,
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)

def main():
    if len(sys.argv) < 6:
        sys.exit(__doc__)
    vpm, config, ref_a, ref_b = sys.argv[1:5]
    print("| image | lights' pixels | relMSE rest | relMSE lights | relRMSE rest | relRMSE lights | lights' share of linear SE |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for image in sys.argv[5:]:
        a = compare(vpm, ref_a, ref_b, image, [])
        r = compare(vpm, ref_a, ref_b, image, ["--exclude-lights", config])
        n, m = a["pixels"], r["pixels"]
        # relMSE and the linear squared error as sums over pixels, floors subtracted, then split.
        rel_all, rel_rest = a["relmse"]["value"] * n, r["relmse"]["value"] * m
        lin = lambda c: (c["relrmse"]["raw"] ** 2 - c["relrmse"]["noise_floor"] ** 2) * (c["reference_mean"] ** 2) * c["pixels"]
        se_all, se_rest = lin(a), lin(r)
        mean_all = a["reference_mean"]
        k = n - m
        rr = lambda s, count: (1 if s >= 0 else -1) * (abs(s) / count) ** 0.5 / mean_all
        print("| %s | %d | %.4g | %.4g | %.3g | %.3g | %.2f |" % (
            image, k, rel_rest / m, (rel_all - rel_rest) / k if k else float("nan"), rr(se_rest, n), rr(se_all - se_rest, n),
            (se_all - se_rest) / se_all if se_all > 0 else float("nan")))

main()
