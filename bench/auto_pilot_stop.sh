#!/usr/bin/env bash
# auto against the forced photon map on the caustic scenes, two vpm binaries (before and after a
# change to auto's plan), interleaved per (seed, scene): photon_map (AFTER's), auto with BEFORE, auto
# with AFTER, each under render.time_limit with photons.count and render.spp unset, 2 threads, nice 5,
# as bench/caustic_equal_time.sh renders them. Then that script's comparison (COMPARE_ONLY) in
# OUT/before and OUT/after, each holding the same photon_map runs, and bench/caustic_table.py's
# tables: auto / photon_map relMSE x CPU s paired by seed.
#
# Usage: bench/auto_pilot_stop.sh BEFORE_VPM AFTER_VPM [SECONDS] [OUT_DIR] [REFERENCES_DIR]
#   defaults: 8, out/auto_pilot_stop, bench/caustic_references; SCENES and SEEDS as caustic_equal_time.sh
#   (SEEDS defaults to 1 2 3 4 here).
set -euo pipefail
before="$1"
after="$2"
seconds="${3:-8}"
out="${4:-out/auto_pilot_stop}"
refs="${5:-bench/caustic_references}"
scenes="${SCENES:-water_caustics glass_bulb_smoke mirror_ball_haze smoke_glass_flask glass_sphere_fog smoke_in_glass_bottle}"
seeds="${SEEDS:-1 2 3 4}"
mkdir -p "$out/before" "$out/after"
render() {   # VPM DIR SCENE METHOD SEED
    local image="$2/${3}_${4}_${5}.exr"
    { /usr/bin/time -f "%e %U %S" nice -n 5 timeout $((seconds * 20 + 60)) "$1" render "configs/$3.toml" -q --threads 2 \
        --set render.integrator="$4" --set render.seed="$5" --set render.time_limit="$seconds" \
        --unset render.spp --unset photons.count -o "$image" ; } 2>&1 | tail -1 > "${image%.exr}.time"
}
for seed in $seeds; do
    for scene in $scenes; do
        render "$after" "$out/after" "$scene" photon_map "$seed"
        for f in exr json time; do cp "$out/after/${scene}_photon_map_${seed}.$f" "$out/before/"; done
        render "$before" "$out/before" "$scene" auto "$seed"
        render "$after" "$out/after" "$scene" auto "$seed"
    done
done
for side in before after; do
    COMPARE_ONLY=1 SCENES="$scenes" SEEDS="$seeds" METHODS="photon_map auto" \
        bench/caustic_equal_time.sh "$seconds" "$refs" "$out/$side" "$after"
    echo "## $side"
    python3 bench/caustic_table.py "$out/$side/runs.csv"
done
