# Sourced by the reference scripts (scripts/caustic_references.sh, bench/spot_reference.sh).
# render_half VPM IMAGE RENDER_ARGS...: `VPM RENDER_ARGS... -o IMAGE` at nice 10. Where IMAGE already
# exists it is extended: the passes after its last (render.first_pass, same seed) are rendered and
# merged into it with `vpm merge` (exact: the mean by pass counts).
render_half() {
    local vpm="$1" image="$2"; shift 2
    if [ ! -f "$image" ]; then
        nice -n 10 "$vpm" "$@" -o "$image"
        return
    fi
    local dir base first
    dir=$(dirname "$image"); base=$(basename "$image" .exr)
    local more="$dir/.more_$base.exr" merged="$dir/.merged_$base.exr"
    first=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['passes']['count'])" "${image%.exr}.json")
    nice -n 10 "$vpm" "$@" --set render.first_pass="$first" -o "$more"
    "$vpm" merge -q "$image" "$more" -o "$merged"
    for ext in exr json png; do mv "${merged%.exr}.$ext" "${image%.exr}.$ext"; done
    rm -f "$more" "${more%.exr}.json" "${more%.exr}.png" "${more%.exr}.passes.csv"
}
