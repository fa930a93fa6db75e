#!/usr/bin/env bash
# Path-traced references of the caustic scenes (issue 59, docs/studies/caustic_scenes.md): each
# scene rendered twice by vpm's path tracer on independent seeds (1001, 1002), so that `vpm compare
# --reference-halves A.exr B.exr IMAGE.exr` takes their mean as the reference and subtracts its noise
# (from their difference). One thread each, under a wall-clock limit per half.
#
# Usage: scripts/caustic_references.sh [SECONDS_PER_HALF] [OUT_DIR] [VPM]
#   defaults: 2700 s, bench/caustic_references, build/vpm. All eight halves run at once (nice 10).
set -euo pipefail
seconds="${1:-2700}"
out="${2:-bench/caustic_references}"
vpm="${3:-build/vpm}"
mkdir -p "$out"
scenes="water_caustics glass_bulb_smoke mirror_ball_haze smoke_glass_flask"
for scene in $scenes; do
    for half in a b; do
        seed=1001
        [ "$half" = b ] && seed=1002
        nice -n 10 "$vpm" render "configs/$scene.toml" -q --threads 1 --set render.integrator=path \
            --set render.seed=$seed --set render.time_limit="$seconds" --unset render.spp --variance \
            -o "$out/${scene}_$half.exr" &
    done
done
wait
