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
half() {
    local name="$1" seed="$2" image="$out/spot_$1.exr"
    local args=(render "$config" -q --threads 1 --set render.integrator=path --set render.seed="$seed"
                --set "render.crop=[$crop]" --set render.time_limit="$seconds" --unset render.spp "${extra[@]}")
    if [ ! -f "$image" ]; then
        nice -n 10 "$vpm" "${args[@]}" -o "$image"
        return
    fi
    local first more="$out/.more_$name.exr" merged="$out/.merged_$name.exr"
    first=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['passes']['count'])" "${image%.exr}.json")
    nice -n 10 "$vpm" "${args[@]}" --set render.first_pass="$first" -o "$more"
    "$vpm" merge -q "$image" "$more" -o "$merged"
    for ext in exr json png; do mv "${merged%.exr}.$ext" "${image%.exr}.$ext"; done
    rm -f "$more" "${more%.exr}.json" "${more%.exr}.png" "${more%.exr}.passes.csv"
}
half a 1001 &
half b 1002 &
wait
