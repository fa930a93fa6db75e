#!/usr/bin/env bash
# Path-traced references of the caustic scenes (issue 59, docs/studies/caustic_scenes.md): each
# scene rendered twice by vpm's path tracer on independent seeds (1001, 1002), so that `vpm compare
# --reference-halves A.exr B.exr IMAGE.exr` takes their mean as the reference and subtracts its noise
# (from their difference). One thread each, under a wall-clock limit per half; all eight halves run
# at once (nice 10).
#
# Usage: scripts/caustic_references.sh [SECONDS_PER_HALF] [OUT_DIR] [VPM]
#   defaults: 2700 s, bench/caustic_references, build/vpm. SCENES="a b" renders those scenes only.
# Where OUT_DIR already holds a half, it is extended: the passes after its last (render.first_pass,
# same seed) for SECONDS more, merged into it with `vpm merge` (exact: the mean by pass counts).
set -euo pipefail
seconds="${1:-2700}"
out="${2:-bench/caustic_references}"
vpm="${3:-build/vpm}"
mkdir -p "$out"
scenes="${SCENES:-water_caustics glass_bulb_smoke mirror_ball_haze smoke_glass_flask smoke_in_glass_bottle glass_sphere_fog}"
# shellcheck source=render_half.sh
source "$(dirname "${BASH_SOURCE[0]}")/render_half.sh"
half() {
    local scene="$1" half="$2" seed="$3"
    render_half "$vpm" "$out/${scene}_$half.exr" render "configs/$scene.toml" -q --threads 1 --set render.integrator=path \
        --set render.seed="$seed" --set render.time_limit="$seconds" --unset render.spp
}
for scene in $scenes; do
    half "$scene" a 1001 &
    half "$scene" b 1002 &
done
wait
