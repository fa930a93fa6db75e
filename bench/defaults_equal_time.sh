#!/bin/bash
# The photon map's neighbourhood and schedule defaults at equal CPU time (issue 56 item 5), from the
# repository root:
#   bench/defaults_equal_time.sh [SEED]...            (default seeds 1 2)
# SCENES (a list of config names) and PASSES (default 64) may be set in the environment.
# Candidates: photons.neighbours = "photons" | "walks" x photons.schedule = "fixed" | "progressive"
# (the corrected estimator, every other key the config's or its default). Scenes: SCENES below, each
# at 48x48 with render.integrator = "photon_map", PASSES passes of PHOTONS photons (DENSE_PHOTONS for
# the dense plume) and 4 spp each. References: the path tracer in two halves (render.first_pass 0 and
# 8, 8 passes each, REF_SPP samples per pixel in all), merged into OUT/SCENE/ref.exr; vpm compare
# --reference-halves subtracts their noise. The four candidates of one scene and seed run at once,
# one thread each, under nice, so that they see the same load; /usr/bin/time records each run's CPU
# seconds (OUT/SCENE/CAND.sSEED.time). relMSE's eps is 0.01 x the reference's mean luminance squared
# (OUT/SCENE/epsilon.txt; these scenes' pixels are far below 1). bench/defaults_equal_time_table.py OUT
# makes the table.
set -e
V=$(realpath "${VPM:-./build/vpm}"); D=${OUT:-out/defaults_equal_time}; mkdir -p "$D"
seeds=("$@"); [ ${#seeds[@]} -gt 0 ] || seeds=(1 2)
passes=${PASSES:-64}
read -r -a SCENES <<< "${SCENES:-thin_cube default_photon_map dense_plume cornell_smoke small_light_smoke homogeneous}"
declare -A ref_spp=([thin_cube]=16384 [default_photon_map]=8192 [dense_plume]=2048 [cornell_smoke]=4096
                    [small_light_smoke]=8192 [homogeneous]=16384)
small=(--set render.width=48 --set render.height=48)
for scene in "${SCENES[@]}"; do
  S=$D/$scene; mkdir -p "$S"
  if [ ! -f "$S/ref.exr" ]; then
    for first in 0 8; do
      [ -f "$S/ref_$first.exr" ] && continue
      nice "$V" render "configs/$scene.toml" -q -o "$S/ref_$first.exr" "${small[@]}" --set render.integrator=path \
          --set render.spp=$((${REF_SPP:-${ref_spp[$scene]}} / 2)) --set render.passes=8 --set render.first_pass=$first \
          --set render.seed=9001 --set render.threads=1 &
    done
    wait
    "$V" merge -q -o "$S/ref.exr" "$S/ref_0.exr" "$S/ref_8.exr"
  fi
  # relMSE's eps scaled with the image (docs/metrics.md): 0.01 times the reference's mean luminance squared
  [ -f "$S/epsilon.txt" ] || "$V" compare "$S/ref_0.exr" "$S/ref_8.exr" --json |
      python3 -c 'import json, sys; print("%.6g" % (0.01 * json.load(sys.stdin)["reference_mean"] ** 2))' > "$S/epsilon.txt"
done
for seed in "${seeds[@]}"; do
  for scene in "${SCENES[@]}"; do
    S=$D/$scene; count=${PHOTONS:-20000}; [ "$scene" = dense_plume ] && count=${DENSE_PHOTONS:-5000}
    for neighbours in photons walks; do
      for schedule in fixed progressive; do
        name=$neighbours.$schedule.s$seed
        /usr/bin/time -f "%U %S %e" -o "$S/$name.time" nice "$V" render "configs/$scene.toml" -q -o "$S/$name.exr" \
            "${small[@]}" --set render.integrator=photon_map --set photons.estimator=corrected \
            --set photons.neighbours=$neighbours --set photons.schedule=$schedule --set render.seed=$seed \
            --set photons.count=$count --set render.passes=$passes --set render.spp=$((4 * passes)) \
            --set render.threads=1 --reference "$S/ref.exr" --epsilon "$(cat "$S/epsilon.txt")" > "$S/$name.log" 2>&1 &
      done
    done
    wait
  done
done
