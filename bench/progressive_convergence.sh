#!/bin/bash
# Error against time, photons.schedule = "fixed" against "progressive" (docs/progressive.md), from the
# repository root:
#   bench/progressive_convergence.sh SCENE SECONDS [--set KEY=VALUE]...
# SCENE: halfspace (Chandrasekhar's closed form: the error of the running image mean, no reference
# needed) | thick_cube (configs/thin_cube.toml at sigma_t 2.5, optical depth 2.5-4.3: the issue's
# cube; a path-traced reference at REF_SPP, default 65536, is rendered once into OUT) | any config
# file (REF_SPP path-traced reference). One time-limited run per schedule, interleaved, with the
# running mean's error after every pass (OUT.passes.csv); bench/progressive_plot.py plots and fits.
# OUT defaults to out/progressive/SCENE.
set -e
scene=$1; seconds=$2; shift 2
V=${VPM:-./build/vpm}; D=${OUT:-out/progressive/$scene}; mkdir -p "$D"
case $scene in
  halfspace)
    C=configs/semi_infinite.toml
    common=(--set media.0.albedo=0.5 --set "media.0.min=[-10, -10, -10]" --set "media.0.max=[10, 0, 10]"
            --set "camera.position=[0, 200, 0]" --set render.width=8 --set render.height=8 --set render.spp=8
            --set render.integrator=photon_map --set photons.gather=collision --set photons.direct=photon_map
            --set photons.count=8000 --set photons.k=32) ;;
  thick_cube)
    C=configs/thin_cube.toml
    common=(--set media.0.sigma_t_scale=2.5 --set render.width=32 --set render.height=32 --set render.spp=16
            --set photons.count=10000 --set photons.k=128 --set photons.gather=march) ;;
  *)
    C=$scene; scene=$(basename "$scene" .toml); common=() ;;
esac
ref=()
if [ "$scene" != halfspace ]; then
  [ -f "$D/ref.exr" ] || $V render "$C" -q -o "$D/ref.exr" "${common[@]}" "$@" --set render.integrator=path \
      --set render.spp=${REF_SPP:-65536} --set render.passes=16 --set render.seed=9001
  ref=(--reference "$D/ref.exr")
fi
for schedule in fixed progressive; do
  $V render "$C" -q -o "$D/$schedule.exr" "${common[@]}" "$@" --set photons.schedule=$schedule \
      --set render.time_limit=$seconds "${ref[@]}"
done
echo "$D"
