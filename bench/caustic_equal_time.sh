#!/usr/bin/env bash
# Equal-time comparison on the caustic scenes (issue 59, docs/studies/caustic_scenes.md): path,
# photon_map, auto, point_beam and photon_beams, each under render.time_limit with photons.count and
# render.spp unset (the automatic sizes), seeds 1 and 2, interleaved (seed, scene, method), 2 threads.
# METHODS may also name photon_beams_WIDTHS (photons.beam_widths = WIDTHS: balloon, sample_point, density).
# Wall and CPU (user + system) seconds from /usr/bin/time; relMSE, relRMSE and relative bias from
# `vpm compare --json --reference-halves` against scripts/caustic_references.sh's halves.
#
# Usage: bench/caustic_equal_time.sh [SECONDS] [REFERENCES_DIR] [OUT_DIR] [VPM]
#   defaults: 8, bench/caustic_references, out/caustic_equal_time, build/vpm.
# Writes OUT_DIR/runs.csv (one row per run); bench/caustic_table.py turns it into the study's table.
# COMPARE_ONLY=1 skips the renders and compares the images already in OUT_DIR again.
set -euo pipefail
seconds="${1:-8}"
refs="${2:-bench/caustic_references}"
out="${3:-out/caustic_equal_time}"
vpm="${4:-build/vpm}"
scenes="${SCENES:-water_caustics glass_bulb_smoke mirror_ball_haze smoke_glass_flask glass_sphere_fog smoke_in_glass_bottle}"
methods="${METHODS:-path photon_map auto point_beam photon_beams}"
seeds="${SEEDS:-1 2}"
mkdir -p "$out"
# Renders (skipped with COMPARE_ONLY=1): each image with its timing beside it (IMAGE.time: wall user sys).
if [ -z "${COMPARE_ONLY:-}" ]; then
for seed in $seeds; do
    for scene in $scenes; do
        for method in $methods; do
            case "$method" in
                path) args=(--set render.integrator=path) ;;
                photon_map) args=(--set render.integrator=photon_map) ;;
                auto) args=(--set render.integrator=auto) ;;
                point_beam) args=(--set render.integrator=photon_map --set 'photons.gather="point_beam"') ;;
                photon_beams) args=(--set render.integrator=photon_map --set 'photons.gather="photon_beams"') ;;
                photon_beams_*) args=(--set render.integrator=photon_map --set 'photons.gather="photon_beams"'
                                      --set "photons.beam_widths=\"${method#photon_beams_}\"") ;;
            esac
            image="$out/${scene}_${method}_${seed}.exr"
            { /usr/bin/time -f "%e %U %S" nice -n 5 timeout $((seconds * 20 + 60)) "$vpm" render \
                "configs/$scene.toml" -q --threads 2 "${args[@]}" --set render.seed="$seed" \
                --set render.time_limit="$seconds" --unset render.spp --unset photons.count -o "$image" ; } \
                2>&1 | tail -1 > "${image%.exr}.time"
        done
    done
done
fi
# Comparisons against the references as they are now (rerun with COMPARE_ONLY=1 after extending them).
csv="$out/runs.csv"
echo "scene,method,seed,time_limit,wall_s,cpu_s,relmse,relmse_floor,relrmse,relrmse_floor,relative_bias,mean,reference_mean,integrator_used,gather_used" > "$csv"
for seed in $seeds; do
    for scene in $scenes; do
        for method in $methods; do
            image="$out/${scene}_${method}_${seed}.exr"
            [ -f "$image" ] || continue
            read -r wall user sys < "${image%.exr}.time"
            metrics=$("$vpm" compare --json --reference-halves "$refs/${scene}_a.exr" "$refs/${scene}_b.exr" "$image")
            python3 - "$scene" "$method" "$seed" "$seconds" "$wall" "$user" "$sys" "$image" "$metrics" >> "$csv" <<'PY'
import json, sys
scene, method, seed, limit, wall, user, sys_s, image, metrics = sys.argv[1:]
m = json.loads(metrics)
if "images" in m:
    m = m["images"][0]
run = json.load(open(image[:-4] + ".json"))
print(",".join(str(x) for x in [scene, method, seed, limit, wall, float(user) + float(sys_s), m["relmse"]["value"],
                                m["relmse"]["noise_floor"], m["relrmse"]["value"], m["relrmse"]["noise_floor"],
                                m["relative_bias"], m["mean"], m["reference_mean"], run.get("integrator_used", ""),
                                run.get("gather_used", "")]))
PY
        done
    done
done
