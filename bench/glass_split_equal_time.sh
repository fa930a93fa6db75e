#!/usr/bin/env bash
# The photon map's camera paths at glass (photons.glass_splits, render/photon_map/camera_path.h):
# equal-time runs of an old vpm and of this one at glass_splits 0, 1, 2 on the glass scenes,
# interleaved (seed, scene, variant), 2 threads, under render.time_limit with photons.count and
# render.spp unset. Wall and CPU seconds from /usr/bin/time; then relMSE, linear relRMSE and the
# error per region (bench/region_error.py: the pixels where the camera sees a lamp, and the rest).
#
# usage: bench/glass_split_equal_time.sh OLD_VPM NEW_VPM [SECONDS] [OUT_DIR]
#   SCENES, SEEDS, SPLITS, EXTRA (more --set arguments for every run; with render.spp in it the
#   plan sizes the photons for those samples per pass) from the environment.
# Writes OUT_DIR/runs.csv and OUT_DIR/regions.md; COMPARE_ONLY=1 compares the images already there.
set -euo pipefail
old=$1 new=$2 seconds=${3:-8} out=${4:-out/glass_split}
scenes="${SCENES:-smoke_glass_flask glass_bulb_smoke glass_sphere_fog water_caustics}"
seeds="${SEEDS:-1 2}"
splits="${SPLITS:-0 1 2}"
refs=bench/caustic_references
mkdir -p "$out"
variants="old $(for s in $splits; do echo -n "s$s "; done)"
for seed in $seeds; do
  [ -n "${COMPARE_ONLY:-}" ] && break
  for scene in $scenes; do
    for v in $variants; do
      bin=$new; args=()
      if [ "$v" = old ]; then bin=$old; else args=(--set "photons.glass_splits=${v#s}"); fi
      image="$out/${scene}_${v}_${seed}.exr"
      unset_spp=(--unset render.spp); case "${EXTRA:-}" in *render.spp=*) unset_spp=() ;; esac
      { /usr/bin/time -f "%e %U %S" nice -n 5 timeout $((seconds * 20 + 60)) "$bin" render "configs/$scene.toml" -q \
          --threads 2 "${args[@]}" ${EXTRA:-} --set render.integrator=photon_map --set render.seed="$seed" \
          --set render.time_limit="$seconds" "${unset_spp[@]}" --unset photons.count -o "$image"; } 2>&1 | tail -1 > "${image%.exr}.time"
    done
  done
done
csv="$out/runs.csv"
echo "scene,variant,seed,wall_s,cpu_s,relmse,relrmse,spp,passes" > "$csv"
: > "$out/regions.md"
for scene in $scenes; do
  for seed in $seeds; do
    for v in $variants; do
      image="$out/${scene}_${v}_${seed}.exr"
      read -r wall user sys < "${image%.exr}.time"
      m=$("$new" compare --json --reference-halves "$refs/${scene}_a.exr" "$refs/${scene}_b.exr" "$image")
      python3 - "$scene" "$v" "$seed" "$wall" "$user" "$sys" "$image" "$m" >> "$csv" <<'PY'
import json, sys
scene, v, seed, wall, user, sys_s, image, m = sys.argv[1:]
m = json.loads(m)
m = m["images"][0] if "images" in m else m
run = json.load(open(image[:-4] + ".json"))
p = run.get("passes", {})
print(",".join(str(x) for x in [scene, v, seed, wall, float(user) + float(sys_s), m["relmse"]["value"], m["relrmse"]["value"],
                                run.get("render", {}).get("samples", ""), p.get("count", "")]))
PY
    done
  done
  /usr/bin/python3 bench/region_error.py "$new" "configs/$scene.toml" "$refs/${scene}_a.exr" "$refs/${scene}_b.exr" \
      $(for seed in $seeds; do for v in $variants; do echo "$out/${scene}_${v}_${seed}.exr"; done; done) >> "$out/regions.md"
done
cat "$csv"
