#!/usr/bin/env bash
# Renders every shipped config small with two vpm binaries, and every gather, extinction, clustering
# and schedule on two of them (also a run from pass 1, and the plan under a time limit, whose passes
# are compared as far as both runs went), and compares the EXR files byte for byte: the check that a
# refactoring (file moves, a registry change) left every image as it was.
#
# usage: scripts/images_identical.sh OLD_VPM NEW_VPM [OUT_DIR]      (exit 1 if any image differs)
set -euo pipefail
old=$1 new=$2 out=${3:-$(mktemp -d)}
root=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out/old" "$out/new"
small=(--threads 2 --quiet --set render.width=24 --set render.height=24 --set render.spp=2
       --set render.time_limit=0 --set photons.count=20000)
differ=0 same=0 skipped=0
for config in "$root"/configs/*.toml "$root"/configs/stress/*.toml; do
  name=$(basename "$config" .toml)
  for side in old new; do
    bin=$old; [ "$side" = new ] && bin=$new
    if ! (cd "$root" && "$bin" render "$config" "${small[@]}" -o "$out/$side/$name.exr" 2>"$out/$side-$name.log"); then
      skipped=$((skipped + 1)); echo "skip  $name ($side: $(tail -n1 "$out/$side-$name.log"))"; continue 2
    fi
  done
  if cmp -s "$out/old/$name.exr" "$out/new/$name.exr"; then same=$((same + 1)); echo "same  $name"
  else differ=$((differ + 1)); echo "DIFF  $name"; fi
done
# Every gather, extinction, clustering and schedule once, on a grid scene and on a glass scene.
variants=('photons.gather="collision"' 'photons.gather="march"' 'photons.gather="threshold"' 'photons.gather="pilot"'
          'photons.gather="point_beam"' 'photons.gather="photon_beams"' 'photons.extinction="point"'
          'photons.extinction="ball"' 'photons.clustering="leave_group_out"' 'photons.schedule="progressive"'
          'render.integrator="auto"' 'render.first_pass=1' 'render.time_limit=3')
for config in "$root"/configs/thin_cube.toml "$root"/configs/glass_sphere_fog.toml; do
  for v in "${variants[@]}"; do
    name="$(basename "$config" .toml)-$(echo "$v" | tr -c 'a-z_\n' '_')"
    for side in old new; do
      bin=$old; [ "$side" = new ] && bin=$new
      if ! (cd "$root" && "$bin" render "$config" "${small[@]}" --set "$v" --set render.passes=2 -o "$out/$side/$name.exr" 2>"$out/$side-$name.log"); then
        skipped=$((skipped + 1)); echo "skip  $name ($side: $(tail -n1 "$out/$side-$name.log"))"; continue 2
      fi
    done
    if [[ $v == render.time_limit* ]]; then
      # The limit's pass count follows the clock: the passes both runs made must match, image by image.
      if python3 - "$out/old/$name.json" "$out/new/$name.json" <<'PY'
import json, sys
a, b = (json.load(open(p))["passes"]["image_mean"] for p in sys.argv[1:])
n = min(len(a), len(b))
sys.exit(0 if n > 0 and a[:n] == b[:n] else 1)
PY
      then same=$((same + 1)); echo "same  $name (the passes both made)"
      else differ=$((differ + 1)); echo "DIFF  $name"; fi
    elif cmp -s "$out/old/$name.exr" "$out/new/$name.exr"; then same=$((same + 1)); echo "same  $name"
    else differ=$((differ + 1)); echo "DIFF  $name"; fi
  done
done
echo "images_identical: $same identical, $differ different, $skipped not rendered (outputs in $out)"
[ "$differ" -eq 0 ]
