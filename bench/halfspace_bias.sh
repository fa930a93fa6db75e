#!/bin/bash
# The half-space's photon-map bias (docs/progressive.md section 6): the image mean of PASSES passes
# against Chandrasekhar's closed form (albedo 0.5, mu = mu0 = 1: 0.0311476), with its standard
# error over passes. From the repository root:
#   bench/halfspace_bias.sh NAME [--set KEY=VALUE]...      (PASSES, default 4000; OUT, default out/halfspace_bias)
# e.g. NAME = fixed_radius with --set photons.max_radius_mfp=0 --set photons.k=8000 --set photons.max_radius=0.5
# (k at most the ~13700 photons a pass stores: a larger k starves the map and every camera path is path
# traced instead; the last line prints the estimate cases, where a fixed radius shows as fixed_radius)
set -e
[ $# -ge 1 ] || { echo "usage: bench/halfspace_bias.sh NAME [--set KEY=VALUE]..." >&2; exit 2; }
name=$1; shift
V=${VPM:-./build/vpm}; D=${OUT:-out/halfspace_bias}; P=${PASSES:-4000}; mkdir -p "$D"
$V render configs/semi_infinite.toml -q -o "$D/$name.exr" --set media.0.albedo=0.5 \
    --set "media.0.min=[-10, -10, -10]" --set "media.0.max=[10, 0, 10]" --set "camera.position=[0, 200, 0]" \
    --set render.width=8 --set render.height=8 --set render.passes=$P --set render.spp=$((8 * P)) \
    --set render.integrator=photon_map --set photons.gather=collision --set photons.direct=photon_map \
    --set photons.count=8000 --set photons.k=32 --set render.threads=1 "$@"
python3 - "$D/$name.passes.csv" "$name" "$D/$name.json" <<'PY'
import csv, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
x = [float(r["image_mean"]) for r in rows]; w = [int(r["passes"]) for r in rows]
n = sum(w); mean = sum(a * b for a, b in zip(x, w)) / n
var = sum(b * (a - mean) ** 2 for a, b in zip(x, w)) / (n - 1)   # per pass (rows are groups of passes)
closed = 0.031147627
se = math.sqrt(var / n * (n / len(x))) if len(x) > 1 else float("nan")   # rows' spread, groups counted once
print(f"{sys.argv[2]}: {n} passes, image mean / closed form - 1 = {(mean / closed - 1) * 100:+.2f}% +- {se / closed * 100:.2f}%")
p = json.load(open(sys.argv[3]))["photons"]
cases = {k: v for k, v in p["estimate_cases"].items() if v}
print(f"  estimate cases {cases or 'none (no estimate: every path traced)'}, continued paths {p['continued_paths']}")
PY
