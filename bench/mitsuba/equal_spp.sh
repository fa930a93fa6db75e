#!/usr/bin/env bash
# vpm's path tracer against Mitsuba 3's volpath on the caustic scenes, interleaved in one run
# (docs/studies/path_tracer_vs_mitsuba.md). For each seed, scene and samples-per-pixel count, vpm
# (render.integrator = "path") and Mitsuba (bench/mitsuba/vpm_scene.py, scalar_rgb) render the same
# scene at the same size, spp and thread count, one after the other; the CPU seconds (user + system)
# are vpm's whole process (its scene load is milliseconds) and Mitsuba's render call alone.
# bench/mitsuba/compare.py turns the folder into the agreement and equal-time tables.
#
# Needs Mitsuba 3 in a virtual environment (not a dependency of vpm; CI does not run this):
#   /usr/bin/python3 -m venv /work/venv-mitsuba && /work/venv-mitsuba/bin/pip install mitsuba numpy
# Usage: bench/mitsuba/equal_spp.sh OUT_DIR
#   env: SCENES (glass_sphere_fog water_caustics glass_bulb_smoke smoke_glass_flask), SPPS (64 256),
#        SEEDS (1 2), SIZE (64x64), THREADS (2), VPM (build/vpm), MITSUBA_PYTHON (/work/venv-mitsuba/bin/python),
#        SETS (extra KEY=VALUE settings for both, space-separated), RENDERERS (vpm mitsuba; "vpm0" is a
#        second vpm binary, VPM0, e.g. the main branch's, run the same way for a before/after ratio)
set -euo pipefail
out="${1:?usage: bench/mitsuba/equal_spp.sh OUT_DIR}"
scenes="${SCENES:-glass_sphere_fog water_caustics glass_bulb_smoke smoke_glass_flask}"
spps="${SPPS:-64 256}"
seeds="${SEEDS:-1 2}"
size="${SIZE:-64x64}"
threads="${THREADS:-2}"
vpm="${VPM:-build/vpm}"
mpy="${MITSUBA_PYTHON:-/work/venv-mitsuba/bin/python}"
renderers="${RENDERERS:-vpm mitsuba}"
extra=()
for kv in ${SETS:-}; do extra+=(--set "$kv"); done
w="${size%x*}"
h="${size#*x}"
mkdir -p "$out"
here="$(cd "$(dirname "$0")" && pwd)"
for seed in $seeds; do
    for spp in $spps; do
        for scene in $scenes; do
            for r in $renderers; do
                base="$out/${scene}_${r}_${spp}_${seed}"
                [ -f "$base.time" ] && continue
                if [ "$r" = vpm ] || [ "$r" = vpm0 ]; then
                    bin="$vpm"
                    [ "$r" = vpm0 ] && bin="${VPM0:?RENDERERS has vpm0: set VPM0 to its binary}"
                    { /usr/bin/time -f "%e %U %S" nice -n 5 "$bin" render "configs/$scene.toml" -q \
                        --threads "$threads" --set render.integrator=path --set render.spp="$spp" \
                        --set render.width="$w" --set render.height="$h" --set render.seed="$seed" \
                        "${extra[@]}" -o "$base.exr" ; } 2>&1 | tail -1 > "$base.time.tmp"
                    read -r wall user sys < "$base.time.tmp"
                    python3 -c "import json,sys; print(json.dumps({'wall_s': float(sys.argv[1]), 'cpu_s': float(sys.argv[2]) + float(sys.argv[3])}))" \
                        "$wall" "$user" "$sys" > "$base.time"
                    rm -f "$base.time.tmp"
                else
                    nice -n 5 "$mpy" "$here/vpm_scene.py" "configs/$scene.toml" --spp "$spp" --seed "$seed" \
                        --threads "$threads" --size "$size" "${extra[@]}" -o "$base.exr" > "$base.time.tmp"
                    mv "$base.time.tmp" "$base.time"
                fi
            done
        done
    done
done
