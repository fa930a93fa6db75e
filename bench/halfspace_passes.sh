#!/bin/bash
# The half-space's bias against the number of passes (issue 56): SEEDS independent runs (render.seed 1..SEEDS)
# of PASSES passes each through bench/halfspace_bias.sh, one directory per variant; the pass means of every run
# stay in OUT/NAME/sSEED.passes.csv for bench/halfspace_passes.py (prefixes of 64, 128, 256 passes: the
# progressive schedule depends on the pass index alone, so a run's first 64 passes are a 64-pass run). From the
# repository root:
#   bench/halfspace_passes.sh NAME [--set KEY=VALUE]...     (SEEDS, default 16; PASSES, default 256; OUT, default out/halfspace_passes)
# e.g. NAME = progressive with --set 'photons.schedule="progressive"' (a TOML string keeps its quotes)
set -e
[ $# -ge 1 ] || { echo "usage: bench/halfspace_passes.sh NAME [--set KEY=VALUE]..." >&2; exit 2; }
name=$1; shift
D=${OUT:-out/halfspace_passes}/$name; S=${SEEDS:-16}; mkdir -p "$D"
for s in $(seq 1 "$S"); do
    [ -f "$D/s$s.passes.csv" ] && continue   # a finished seed is kept: the loop resumes where it stopped
    OUT=$D PASSES=${PASSES:-256} bench/halfspace_bias.sh "s$s" --set render.seed="$s" "$@" | sed -n 1p   # the estimate cases line left out
done
