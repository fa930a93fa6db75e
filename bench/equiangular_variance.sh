#!/bin/bash
# render.equiangular off and on, interleaved (per repeat: an off pair of seeds, then an on pair) on
# configs/inside_large_sphere.toml: the per-pixel variance (RMSE^2 / 2 between the two seeds of a
# pair, no reference needed) and the mean wall time per run (docs/studies/equiangular.md).
# usage: bench/equiangular_variance.sh INTEGRATOR [--set ...]   (from the repository root, ./build/vpm)
set -u
bin=${VPM:-./build/vpm}; integ=$1; shift
out=$(mktemp -d)
for rep in 1 2 3; do
 for eq in false true; do
  tt=0
  for k in a b; do
      [ $k = a ] && s=$((rep*10+1)) || s=$((rep*10+2))
   /usr/bin/time -f "%e" -o $out/t nice $bin render configs/inside_large_sphere.toml --quiet --threads 2 --set render.integrator="\"$integ\"" "$@" --set render.seed=$s --set render.equiangular=$eq -o $out/$integ.$eq.$k.exr > /dev/null 2>&1
   tt=$(python3 -c "print($tt + $(cat $out/t))")
  done
  r=$($bin compare $out/$integ.$eq.a.exr $out/$integ.$eq.b.exr | sed 's/.*: rmse \([^,]*\),.*/\1/')
  echo "$integ rep $rep equiangular $eq pixel_var $(python3 -c "print($r**2/2)") time_per_run $(python3 -c "print($tt/2)") load $(cut -d' ' -f1 /proc/loadavg)"
 done
done
