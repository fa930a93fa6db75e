#!/bin/bash
# The cube at optical depth 2.5 (docs/progressive.md section 5's thick cube, at 8x8 pixels so that runs of
# 256 passes are cheap) against the number of passes: a path-traced reference (OUT/ref, 32 passes of
# 16384 spp, seed 9001: its passes give the reference mean's standard error), then SEEDS independent
# photon-map runs (render.seed 1..SEEDS) of PASSES passes of 16 spp each, one directory per variant,
# for bench/halfspace_passes.py OUT --reference OUT/ref.passes.csv. From the repository root:
#   bench/cube_passes.sh NAME [--set KEY=VALUE]...     (SEEDS, default 16; PASSES, default 256; OUT, default out/cube_passes)
set -e
[ $# -ge 1 ] || { echo "usage: bench/cube_passes.sh NAME [--set KEY=VALUE]..." >&2; exit 2; }
name=$1; shift
V=${VPM:-./build/vpm}; O=${OUT:-out/cube_passes}; D=$O/$name; S=${SEEDS:-16}; P=${PASSES:-256}; mkdir -p "$D"
cube=(--set media.0.sigma_t_scale=2.5 --set render.width=8 --set render.height=8 --set photons.count=10000
      --set photons.k=128 --set photons.gather=march --set render.threads=1)
[ -f "$O/ref.passes.csv" ] || $V render configs/thin_cube.toml -q -o "$O/ref.exr" "${cube[@]}" \
    --set render.integrator=path --set render.passes=32 --set render.spp=$((32 * 16384)) --set render.seed=9001
for s in $(seq 1 "$S"); do
    [ -f "$D/s$s.passes.csv" ] && continue   # a finished seed is kept: the loop resumes where it stopped
    $V render configs/thin_cube.toml -q -o "$D/s$s.exr" "${cube[@]}" --set render.integrator=photon_map \
        --set render.passes=$P --set render.spp=$((16 * P)) --set render.seed="$s" "$@"
done
