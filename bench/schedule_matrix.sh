#!/bin/bash
# photons.schedule = "fixed" against "progressive" on cells of the scene matrix, at equal time
# (issue 44 item 2: the default by measurement). From the repository root:
#   bench/schedule_matrix.sh SECONDS [CELL_ID_PART]... [-- --set KEY=VALUE ...]
# For each cell (default: CELLS below, one or more per matrix group) `vpm bench matrix --only ID`
# writes the cell's scene and its cached path-traced reference into OUT (default out/schedule_matrix;
# REF_SECONDS, default 16, path-tracer seconds per reference; its methods run at a 0.01 s budget and
# are not used). Then the photon map's defaults (render.integrator = "photon_map") run with each
# schedule at the same time, one thread each, render.time_limit = SECONDS, against the reference.
# OUT/schedules.md: bench/schedule_matrix_table.py's table (passes, seconds, relative RMSE with the
# reference's noise removed, mean error; progressive's mean squared error over fixed's).
set -e
[ $# -ge 1 ] || { echo "usage: bench/schedule_matrix.sh SECONDS [CELL_ID_PART]... [-- --set KEY=VALUE ...]" >&2; exit 2; }
seconds=$1; shift
cells=(); sets=()
while [ $# -gt 0 ]; do
  if [ "$1" = "--" ]; then shift; sets=("$@"); break; fi
  cells+=("$1"); shift
done
[ ${#cells[@]} -gt 0 ] || cells=(
  box-tau1-a0.9-g0-point-s1 box-tau10-a0.9-g0-point-s1 box-tau100-a0.9-g0-point-s1
  sphere-tau1-a0.9-g0-point-s1 sphere-tau10-a0.9-g0-point-s1 sphere-tau100-a0.9-g0-point-s1
  blob-tau1-a0.9-g0-point-s1 blob-tau10-a0.9-g0-point-s1 blob-tau100-a0.9-g0-point-s1
  plume-tau1-a0.9-g0-point-s1 plume-tau10-a0.9-g0-point-s1 plume-tau100-a0.9-g0-point-s1
  box-tau10-a0.99-g0-point-s1 plume-tau10-a0.5-g0-point-s1 blob-tau1000-a0.99-g0-point-s1
  box-tau10-a0.9-g0.8-point-s1 sphere-tau1-a0.9-g0-spot-s1 blob-tau100-a0.9-g0-quad-s1
  blob-tau1-a0.9-g0-environment-s1 box-tau10-a0.9-g0-point-s1000)
V=${VPM:-./build/vpm}; D=${OUT:-out/schedule_matrix}; mkdir -p "$D/runs"
for cell in "${cells[@]}"; do
  $V bench matrix --out "$D" --size 32 --only "$cell" --budget 0.01 --reference-seconds "${REF_SECONDS:-16}" \
      --no-plot > "$D/runs/$cell.matrix.log" 2>&1
  # the reference this cell's scene is compared with (the cache's, by scene hash)
  ref=$(python3 -c 'import csv, sys
print(next(r["reference"] for r in csv.DictReader(open(sys.argv[1])) if r["cell"] == sys.argv[2]))' "$D/matrix.csv" "$cell")
  for schedule in fixed progressive; do
    $V render "$D/scenes/$cell.toml" -q -o "$D/runs/$cell.$schedule.exr" --set render.integrator=photon_map \
        --set photons.schedule=$schedule --set render.threads=1 --set render.time_limit="$seconds" \
        --reference "$D/references/$ref.exr" "${sets[@]}" > "$D/runs/$cell.$schedule.log" 2>&1 &
  done
  wait
done
bench/schedule_matrix_table.py "$D" | tee "$D/schedules.md"
