#!/bin/bash
# Error against time, photons.schedule = "fixed" against "progressive" (docs/progressive.md), from the
# repository root:
#   bench/progressive_convergence.sh SCENE SECONDS [--set KEY=VALUE]...
# SCENE: halfspace (Chandrasekhar's closed form: the error of the running image mean, no reference
# needed) | thick_cube (configs/thin_cube.toml at sigma_t 2.5, optical depth 2.5-4.3: the issue's
# cube) | default (configs/default_photon_map.toml) | dense (configs/dense_plume.toml) | any config
# file. Every scene but the half-space is rendered at 32x32 with small passes (1e4-1e5 photons,
# 4-16 spp) so that a run holds many of them, against a path-traced reference of REF_SPP (default
# 65536) samples per pixel rendered once into OUT as two halves of 8 passes (render.first_pass 0 and
# 8, merged by vpm merge); the halves' difference gives the reference's own noise (OUT/ref_noise.txt,
# relative variance of the merged mean), which bench/progressive_plot.py subtracts.
# The two schedules run at the same time, one thread each (THREADS to change), so that both see the
# same machine load; each writes the running mean's error after every pass (OUT/SCHEDULE.passes.csv).
# OUT defaults to out/progressive/SCENE.
set -e
[ $# -ge 2 ] || { echo "usage: bench/progressive_convergence.sh SCENE SECONDS [--set KEY=VALUE]..." >&2; exit 2; }
scene=$1; seconds=$2; shift 2
V=${VPM:-./build/vpm}; D=${OUT:-out/progressive/$scene}; mkdir -p "$D"
small=(--set render.width=32 --set render.height=32)
case $scene in
  halfspace)
    C=configs/semi_infinite.toml
    common=(--set media.0.albedo=0.5 --set "media.0.min=[-10, -10, -10]" --set "media.0.max=[10, 0, 10]"
            --set "camera.position=[0, 200, 0]" --set render.width=8 --set render.height=8 --set render.spp=8
            --set render.integrator=photon_map --set photons.gather=collision --set photons.direct=photon_map
            --set photons.count=8000 --set photons.k=32) ;;
  thick_cube)
    C=configs/thin_cube.toml
    common=(--set media.0.sigma_t_scale=2.5 "${small[@]}" --set render.spp=16
            --set photons.count=10000 --set photons.k=128 --set photons.gather=march) ;;
  default)
    C=configs/default_photon_map.toml
    common=("${small[@]}" --set render.spp=4 --set photons.count=100000 --set photons.gather=march) ;;
  dense)
    C=configs/dense_plume.toml
    common=("${small[@]}" --set render.spp=4 --set photons.count=100000 --set photons.gather=collision) ;;
  *)
    C=$scene; scene=$(basename "$scene" .toml); common=() ;;
esac
ref=()
if [ "$scene" != halfspace ]; then
  if [ ! -f "$D/ref.exr" ]; then
    spp=$(( ${REF_SPP:-65536} / 16 ))
    for first in 0 8; do
      $V render "$C" -q -o "$D/ref_$first.exr" "${common[@]}" "$@" --set render.integrator=path \
          --set render.spp=$((spp * 8)) --set render.passes=8 --set render.first_pass=$first --set render.seed=9001
    done
    $V merge -q -o "$D/ref.exr" "$D/ref_0.exr" "$D/ref_8.exr"
    # relative variance of the merged mean: E|a - b|^2 / 4 over the reference's scale squared
    $V compare "$D/ref_0.exr" "$D/ref_8.exr" --json |
      python3 -c 'import json, sys; print(json.load(sys.stdin)["relative_rmse"] ** 2 / 4)' > "$D/ref_noise.txt"
  fi
  ref=(--reference "$D/ref.exr")
fi
for schedule in fixed progressive; do
  $V render "$C" -q -o "$D/$schedule.exr" "${common[@]}" "$@" --set photons.schedule=$schedule \
      --set render.integrator=photon_map --set render.passes=1 \
      --set render.threads=${THREADS:-1} --set render.time_limit=$seconds "${ref[@]}" &
done
wait
echo "$D"
