#!/usr/bin/env bash
# A path-traced reference of a small region only (render.crop): two halves on independent seeds
# (1001, 1002), one thread each, at nice 10, under render.time_limit per half, so that
# `vpm compare --reference-halves A.exr B.exr IMAGE.exr --crop ...` and bench/spot_mean.py read the
# region against their mean with its noise from their difference. Run again on the same folder, each
# half is extended by the passes after its last (render.first_pass, same seed) and merged (vpm merge).
#
# Usage: bench/spot_reference.sh SECONDS OUT_DIR CONFIG CROP [VPM] [-- --set ...]
#   e.g. bench/spot_reference.sh 1800 bench/spot_reference configs/glass_sphere_fog.toml 28,48,36,52 build/vpm \
#          -- --set render.width=64 --set render.height=64
set -euo pipefail
seconds="$1"; out="$2"; config="$3"; crop="$4"; shift 4
vpm="build/vpm"
if [ $# -gt 0 ] && [ "$1" != "--" ]; then vpm="$1"; shift; fi
[ $# -gt 0 ] && [ "$1" = "--" ] && shift
extra=("$@")
mkdir -p "$out"
# shellcheck source=../scripts/render_half.sh
source "$(dirname "${BASH_SOURCE[0]}")/../scripts/render_half.sh"
half() {
    local name="$1" seed="$2"
    render_half "$vpm" "$out/spot_$name.exr" render "$config" -q --threads 1 --set render.integrator=path \
        --set render.seed="$seed" --set "render.crop=[$crop]" --set render.time_limit="$seconds" --unset render.spp "${extra[@]}"
}
half a 1001 &
half b 1002 &
wait
