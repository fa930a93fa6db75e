#!/usr/bin/env bash
# photon_beams under render.time_limit on every shipped config (docs/photon_beams.md, "Density
# widths"): each config rendered with the photon map and photons.gather = "photon_beams" at LIMIT
# seconds, photons.count and render.spp unset where the config sets them (the limit sizes them),
# 2 threads; prints wall and CPU (user + system) seconds and whether the wall time is within
# 1.2 x LIMIT + 1 s.
#
# Usage: bench/beam_time_limits.sh [LIMIT] [VPM] [OUT_DIR]    (defaults: 8, build/vpm, out/beam_time_limits)
# EXTRA="--set photons.beam_widths=\"balloon\"" adds keys to every run; CONFIGS="configs/a.toml ..." picks configs.
set -euo pipefail
limit="${1:-8}"
vpm="${2:-build/vpm}"
out="${3:-out/beam_time_limits}"
mkdir -p "$out"
echo "config,wall_s,cpu_s,within"
for config in ${CONFIGS:-configs/*.toml}; do
    name=$(basename "$config" .toml)
    args=(--set render.integrator=photon_map --set 'photons.gather="photon_beams"' --set render.time_limit="$limit")
    # The config and its base (base = "FILE"): where either sets a size, the limit sizes it instead.
    files=("$config")
    base=$(sed -n 's/^base *= *"\(.*\)"/\1/p' "$config")
    [ -n "$base" ] && files+=("configs/$base")
    grep -q '^count *=' "${files[@]}" && args+=(--unset photons.count)
    grep -q '^spp *=' "${files[@]}" && args+=(--unset render.spp)
    grep -q '^passes *=' "${files[@]}" && args+=(--unset render.passes)
    # shellcheck disable=SC2086
    if ! /usr/bin/time -o "$out/$name.time" -f "%e %U %S" nice -n 5 timeout $((limit * 20 + 60)) "$vpm" render "$config" \
            -q --threads 2 "${args[@]}" ${EXTRA:-} -o "$out/$name.exr" 2> "$out/$name.log"; then
        echo "$name,,,failed: $(grep -v '^Command' "$out/$name.log" | tail -n1)"; continue
    fi
    read -r wall user sys < <(tail -n1 "$out/$name.time")
    python3 -c "import sys; w, c, l = float('$wall'), float('$user') + float('$sys'), float('$limit'); print('$name,%.1f,%.2f,%s' % (w, c, 'yes' if w <= 1.2 * l + 1 else 'NO'))"
done
