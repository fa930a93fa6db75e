#!/usr/bin/env bash
# The mean of a small region (a caustic spot) over independent seeds: a photon-map run per seed,
# rendering only the region (render.crop: the photon passes are traced in full, the camera pass
# covers the crop, its pixels read as in the whole image). Under render.time_limit with
# render.time_limit_passes pinned the plan sizes each pass from counts and the passes come from no
# clock, so a "T-second" run is reproducible (docs/studies/caustic_scenes.md, "The caustic spot").
#
# Usage: SEEDS="1 2 ..." bench/spot_mean.sh NAME OUT_DIR CONFIG CROP LIMIT PASSES [VPM] [-- --set ...]
#   then bench/spot_mean.py OUT_DIR REF_DIR CROP NAME...
set -euo pipefail
name="$1"; out="$2"; config="$3"; crop="$4"; limit="$5"; passes="$6"; shift 6
vpm="build/vpm"
if [ $# -gt 0 ] && [ "$1" != "--" ]; then vpm="$1"; shift; fi
[ $# -gt 0 ] && [ "$1" = "--" ] && shift
seeds="${SEEDS:-1 2 3 4 5 6 7 8}"
mkdir -p "$out/$name"
# The plan sizes what the command line leaves unset (an --unset would win over a --set of the key).
unsets=()
for key in render.spp photons.count; do
    case " $* " in *" $key="*) ;; *) unsets+=(--unset "$key") ;; esac
done
for seed in $seeds; do
    image="$out/$name/seed$seed.exr"
    [ -f "$image" ] && continue
    nice -n 5 "$vpm" render "$config" -q --threads "${THREADS:-2}" --set render.integrator=photon_map --set render.seed="$seed" \
        --set "render.crop=[$crop]" --set render.time_limit="$limit" --set render.time_limit_passes="$passes" \
        "${unsets[@]}" "$@" -o "$image"
done
