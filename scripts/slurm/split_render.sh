#!/usr/bin/env bash
# A render and a sweep split across a Slurm job array, merged, and checked against one machine:
#  1. render: `sbatch --array=0-(N-1)` of render_passes.sbatch, task i rendering passes i*P..i*P+P-1
#     of a small photon-map scene; `vpm merge` of the N pass sets; `vpm compare` against a
#     single-machine run of all N*P passes: relative RMSE must be < 1e-6 (float rounding only).
#  2. sweep: a references job, `sbatch --array` of sweep_shard.sbatch (--shard i/N) after it, a
#     `vpm sweep merge` job after that; the merged runs.csv and points.csv must equal an unsharded
#     run of the same sweep file in every column but the timing ones, and its images byte for byte.
# Prints the number of array tasks, wall times and the differences; exits 1 on any mismatch.
# Used by the ctest test Slurm.SplitRenderAndShardedSweep (with --own-cluster --no-install).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)

usage() {
  cat <<EOF
Usage: $(basename "$0") [options]

  --vpm PATH            vpm binary (default: $repo/build/vpm)
  --tasks N             array tasks for both parts (default: 4)
  --passes-per-task P   passes each render task renders (default: 2)
  --spp-per-pass S      samples per pixel per pass (default: 2)
  --config FILE         scene (default: configs/homogeneous.toml with the photon map at 32x32)
  --sweep FILE          sweep file (default: scripts/slurm/tiny_sweep.toml)
  --work DIR            work folder, shared by the jobs (default: a new folder under /tmp)
  --keep                keep the work folder (default: deleted on success)
  --cluster DIR         use (and start if needed, then leave running) the local cluster in DIR
                        (default: \$VPM_SLURM_DIR or /tmp/vpm-slurm); ignored with --own-cluster
  --own-cluster         start a fresh local cluster in a temporary folder on a free port and
                        stop and delete it on exit (what the ctest test does)
  --use-slurm-conf      use the cluster of \$SLURM_CONF as it is (a real cluster: --work must be
                        on a file system the nodes share, --vpm a binary they can run)
  --no-install          do not apt-get install slurm-wlm/munge when missing: exit 77 (skip)
  --timeout SECONDS     longest wait for each group of jobs (default: 240)
  --max-seconds S       the whole script's limit: then SIGTERM, cleanup, exit (default: 900)
  -h, --help            this help

Exit codes: 0 all equal, 1 mismatch or failure, 2 usage error,
            77 Slurm cannot run here (not root, packages missing with --no-install): skipped.
EOF
}

orig_args=("$@")
vpm="$repo/build/vpm"
tasks=4
ppt=2
spp_per_pass=2
config="$repo/configs/homogeneous.toml"
config_sets=(--set render.width=32 --set render.height=32 --set render.integrator=photon_map
             --set photons.count=20000)
sweep="$here/tiny_sweep.toml"
work=""
keep=0
cluster_dir=${VPM_SLURM_DIR:-/tmp/vpm-slurm}
mode=shared
install_flag=()
wait_timeout=240
max_seconds=900
while [ $# -gt 0 ]; do
  case "$1" in
    --vpm) vpm=${2:?--vpm needs a value}; shift 2 ;;
    --tasks) tasks=${2:?--tasks needs a value}; shift 2 ;;
    --passes-per-task) ppt=${2:?--passes-per-task needs a value}; shift 2 ;;
    --spp-per-pass) spp_per_pass=${2:?--spp-per-pass needs a value}; shift 2 ;;
    --config) config=${2:?--config needs a value}; config_sets=(); shift 2 ;;
    --sweep) sweep=${2:?--sweep needs a value}; shift 2 ;;
    --work) work=${2:?--work needs a value}; shift 2 ;;
    --keep) keep=1; shift ;;
    --cluster) cluster_dir=${2:?--cluster needs a value}; shift 2 ;;
    --own-cluster) mode=own; shift ;;
    --use-slurm-conf) mode=conf; shift ;;
    --no-install) install_flag=(--no-install); shift ;;
    --timeout) wait_timeout=${2:?--timeout needs a value}; shift 2 ;;
    --max-seconds) max_seconds=${2:?--max-seconds needs a value}; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "split_render: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
for v in tasks ppt spp_per_pass wait_timeout max_seconds; do
  [[ "${!v}" =~ ^[1-9][0-9]*$ ]] || { echo "split_render: --${v//_/-} must be a positive integer, got '${!v}'" >&2; exit 2; }
done
# The whole run under one limit: timeout sends SIGTERM to this script's process group (our
# renders and Slurm clients; the daemons run in their own sessions), the EXIT trap cleans up.
if [ -z "${VPM_SPLIT_RENDER_LIMITED:-}" ]; then
  export VPM_SPLIT_RENDER_LIMITED=1
  exec timeout --kill-after=120 "$max_seconds" "$0" "${orig_args[@]}"
fi
say() { echo "split_render: $*" >&2; }
die() { echo "split_render: error: $*" >&2; exit 1; }
[ -x "$vpm" ] || die "no vpm binary at $vpm (build it: cmake --build build --target vpm, or pass --vpm)"
vpm=$(cd "$(dirname "$vpm")" && pwd)/$(basename "$vpm")
[ -f "$config" ] || die "no scene config $config"
[ -f "$sweep" ] || die "no sweep file $sweep"
command -v python3 >/dev/null || die "python3 is needed to compare the sweep tables"
. "$here/cluster_lib.sh"

# --- Cleanup: cancel our jobs, stop our own cluster, delete the work folder ----------------------
jobs_submitted=()
own_cluster_dir=""
ok=0
cleanup() {
  local rc=$?
  set +e
  if [ ${#jobs_submitted[@]} -gt 0 ] && [ "$ok" != 1 ]; then
    timeout 10 scancel "${jobs_submitted[@]}" >/dev/null 2>&1
  fi
  if [ -n "$own_cluster_dir" ]; then
    timeout 60 "$here/stop_local_cluster.sh" --dir "$own_cluster_dir" --purge >/dev/null 2>&1 ||
      echo "split_render: could not stop the cluster in $own_cluster_dir: stop it with $here/stop_local_cluster.sh --dir $own_cluster_dir" >&2
    rmdir "$own_cluster_dir" 2>/dev/null
  fi
  if [ -n "$work" ] && [ -d "$work" ]; then
    if [ "$keep" = 1 ] || [ "$ok" != 1 ]; then
      echo "split_render: work folder kept: $work" >&2
    else
      rm -rf -- "$work"
    fi
  fi
  exit $rc
}
trap cleanup EXIT
trap 'say "interrupted"; exit 130' INT
trap 'say "terminated (the limit is --max-seconds $max_seconds)"; exit 143' TERM

# --- The cluster ---------------------------------------------------------------------------------
start_rc=0
case "$mode" in
  own)
    # a random free port pair (runs in several checkouts at once must not collide); a port taken
    # between the check and the bind makes the start fail: then try another, 3 times in all
    own_cluster_dir=$(mktemp -d /tmp/vpm-slurm-test.XXXXXX)
    for attempt in 1 2 3; do
      port=""
      for i in $(seq 1 50); do
        p=$((20000 + 2 * (RANDOM % 5000)))
        if ! port_in_use "$p" && ! port_in_use $((p + 1)); then port=$p; break; fi
      done
      [ -n "$port" ] || die "no free port pair found on 127.0.0.1 in 20000..29999"
      start_rc=0
      timeout 180 "$here/start_local_cluster.sh" --dir "$own_cluster_dir" --port "$port" --quiet "${install_flag[@]}" || start_rc=$?
      [ "$start_rc" = 1 ] || break
      say "the cluster did not start on port $port (attempt $attempt of 3)"
      "$here/stop_local_cluster.sh" --dir "$own_cluster_dir" >/dev/null 2>&1 || true
    done
    export SLURM_CONF="$own_cluster_dir/slurm.conf"
    ;;
  shared)
    timeout 900 "$here/start_local_cluster.sh" --dir "$cluster_dir" --quiet "${install_flag[@]}" || start_rc=$?
    export SLURM_CONF="$cluster_dir/slurm.conf"
    ;;
  conf)
    [ -n "${SLURM_CONF:-}" ] || die "--use-slurm-conf: SLURM_CONF is not set"
    command -v sbatch >/dev/null || die "--use-slurm-conf: no sbatch on PATH"
    ;;
esac
if [ "$start_rc" = 3 ]; then
  say "SKIPPED: Slurm cannot run here (see the line above)"
  exit 77
elif [ "$start_rc" != 0 ]; then
  die "the local Slurm cluster did not start (exit $start_rc)"
fi

[ -n "$work" ] || work=$(mktemp -d /tmp/vpm-slurm-split.XXXXXX)
mkdir -p "$work/logs"
work=$(cd "$work" && pwd)

# submit ARGS...: sbatch --parsable; sets $job and records it for cleanup (not in a subshell).
job=""
submit() {
  local out
  out=$(timeout 30 sbatch --parsable --chdir="$work" "$@") || die "sbatch $* failed"
  job=${out%%;*}
  jobs_submitted+=("$job")
}

# wait_jobs ID...: until none is pending or running (at most --timeout s), then every task of
# every job must have ended COMPLETED; on failure prints the states and the tasks' logs.
wait_jobs() {
  local ids deadline left states bad misses=0
  ids=$(IFS=,; echo "$*")
  deadline=$((SECONDS + wait_timeout))
  while :; do
    if left=$(timeout 15 squeue -h -j "$ids" -o %i 2>/dev/null); then
      misses=0
      [ -z "$left" ] && break
    else
      misses=$((misses + 1))
      [ "$misses" -ge 5 ] && die "squeue failed 5 times in a row: is slurmctld down? ($SLURM_CONF)"
    fi
    if [ $SECONDS -ge $deadline ]; then
      timeout 15 squeue -j "$ids" >&2 || true
      die "jobs $ids still not done after $wait_timeout s (raise --timeout?)"
    fi
    sleep 0.5
  done
  states=$(for id in "$@"; do timeout 15 scontrol -o show job "$id"; done 2>&1 |
           sed -n 's/.*JobId=\([0-9]*\).*ArrayTaskId=\([0-9]*\).*JobState=\([A-Z_]*\).*ExitCode=\([0-9:]*\).*/\1_\2 \3 \4/p;
                   /ArrayTaskId=/!s/.*JobId=\([0-9]*\).*JobState=\([A-Z_]*\).*ExitCode=\([0-9:]*\).*/\1 \2 \3/p')
  [ -n "$states" ] || die "scontrol knows none of the jobs $ids"
  bad=$(echo "$states" | awk '$2 != "COMPLETED" || $3 != "0:0"')
  if [ -n "$bad" ]; then
    echo "$bad" | sed 's/^/  failed: /' >&2
    for f in "$work"/logs/*; do echo "--- $f" >&2; tail -n 20 "$f" >&2; done
    die "some jobs of $ids did not complete"
  fi
}

now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }

say "cluster: $SLURM_CONF; work folder: $work"
say "$(timeout 15 sinfo -h -o '%P %D nodes, %c CPUs per node, %t' | head -n 1)"
failures=0

# --- 1. Split render -----------------------------------------------------------------------------
total_passes=$((tasks * ppt))
say "render: $tasks array tasks x $ppt passes ($total_passes passes, $spp_per_pass spp per pass)"
t0=$(now)
submit --array=0-$((tasks - 1)) --output="$work/logs/render_%A_%a.out" \
  "$here/render_passes.sbatch" "$vpm" "$config" "$ppt" "$spp_per_pass" "$work/render" "${config_sets[@]}"
jid=$job
wait_jobs "$jid"
parts=("$work"/render/part_*.exr)
[ ${#parts[@]} -eq "$tasks" ] || die "expected $tasks pass sets in $work/render, found ${#parts[@]}"
timeout 120 "$vpm" merge -q "${parts[@]}" -o "$work/merged.exr" || die "vpm merge failed"
t1=$(now)
render_wall=$(elapsed "$t0" "$t1")
timeout 120 "$vpm" render "$config" -q "${config_sets[@]}" --set render.passes="$total_passes" \
  --set render.spp=$((total_passes * spp_per_pass)) --threads 0 -o "$work/single.exr" ||
  die "the single-machine render failed"
t2=$(now)
single_wall=$(elapsed "$t1" "$t2")
cmp_json=$(timeout 60 "$vpm" compare --json "$work/merged.exr" "$work/single.exr") || die "vpm compare failed"
rel_rmse=$(echo "$cmp_json" | python3 -c 'import json,sys; print("%.3g" % json.load(sys.stdin)["relative_rmse"])')
max_abs=$(echo "$cmp_json" | python3 -c 'import json,sys; print("%.3g" % json.load(sys.stdin)["rmse"])')
bytes_equal=no
cmp -s "$work/merged.exr" "$work/single.exr" && bytes_equal=yes
render_ok=$(awk -v r="$rel_rmse" 'BEGIN { print (r < 1e-6) ? "yes" : "no" }')
[ "$render_ok" = yes ] || failures=$((failures + 1))

# --- 2. Sharded sweep ----------------------------------------------------------------------------
say "sweep: references job, $tasks-task shard array after it, merge job after that"
t3=$(now)
submit --output="$work/logs/sweep_refs_%j.out" --job-name=vpm-sweep-refs --cpus-per-task=1 --time=10 \
  --wrap "exec '$vpm' sweep '$sweep' --out '$work/sweep' --references-only --threads 1 --no-plots --quiet"
ref=$job
submit --dependency=afterok:"$ref" --array=0-$((tasks - 1)) --output="$work/logs/sweep_%A_%a.out" \
  "$here/sweep_shard.sbatch" "$vpm" "$sweep" "$work/sweep"
arr=$job
submit --dependency=afterok:"$arr" --output="$work/logs/sweep_merge_%j.out" --job-name=vpm-sweep-merge \
  --cpus-per-task=1 --time=10 --wrap "exec '$vpm' sweep merge '$work/sweep' --no-plots --quiet"
mrg=$job
wait_jobs "$ref" "$arr" "$mrg"
t4=$(now)
sweep_wall=$(elapsed "$t3" "$t4")
shard_files=$(ls "$work"/sweep/runs.shard-*-of-"$tasks".csv 2>/dev/null | wc -l)
timeout 120 "$vpm" sweep "$sweep" --out "$work/sweep_single" --threads 0 --no-plots --quiet >"$work/logs/sweep_single.log" 2>&1 ||
  die "the unsharded sweep failed"
sweep_report=$(python3 - "$work/sweep" "$work/sweep_single" <<'PY'
import csv, filecmp, os, sys
timing = {"trace_s", "build_s", "render_s", "total_s", "run_s", "peak_rss_bytes"}
def table(path, key):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {r[key]: {k: v for k, v in r.items() if k not in timing} for r in rows}
sharded, single = sys.argv[1], sys.argv[2]
problems = []
counts = []
for name, key in (("runs.csv", "hash"), ("points.csv", "point")):
    a, b = table(os.path.join(sharded, name), key), table(os.path.join(single, name), key)
    counts.append("%d %s rows" % (len(b), name))
    if set(a) != set(b):
        problems.append("%s: rows %s only sharded, %s only single" % (name, sorted(set(a) - set(b)), sorted(set(b) - set(a))))
    for k in sorted(set(a) & set(b)):
        for col in b[k]:
            if a[k].get(col) != b[k][col]:
                problems.append("%s %s: %s = %s sharded, %s single" % (name, k, col, a[k].get(col), b[k][col]))
runs = table(os.path.join(single, "runs.csv"), "hash")
same_images = 0
for k, r in runs.items():
    for col in ("image", "reference"):
        pa, pb = os.path.join(sharded, r[col]), os.path.join(single, r[col])
        if not os.path.exists(pa) or not filecmp.cmp(pa, pb, shallow=False):
            problems.append("%s differs or is missing: %s" % (col, r[col]))
        elif col == "image":
            same_images += 1
print("; ".join(counts) + ", %d/%d images byte-identical" % (same_images, len(runs)))
for p in problems[:20]:
    print("MISMATCH " + p)
PY
) || die "comparing the sweep tables failed"
sweep_ok=yes
if echo "$sweep_report" | grep -q '^MISMATCH'; then sweep_ok=no; failures=$((failures + 1)); fi

# --- Report --------------------------------------------------------------------------------------
cat <<EOF
Slurm split render ($(basename "$config"), $(echo "${config_sets[@]}" | sed 's/--set //g')):
  array tasks: $tasks x $ppt passes = $total_passes passes, $spp_per_pass spp per pass
  wall time: $render_wall s (sbatch to merged image); single-machine run of all passes: $single_wall s
  merged vs single-machine: relative RMSE $rel_rmse, RMSE $max_abs, bytes identical: $bytes_equal -> $( [ "$render_ok" = yes ] && echo "EQUAL (< 1e-6)" || echo "MISMATCH (>= 1e-6)")
Slurm sharded sweep ($(basename "$sweep")):
  array tasks: $tasks shards ($shard_files shard tables) + 1 references job + 1 merge job
  wall time: $sweep_wall s (sbatch to merged report)
  merged vs unsharded: $(echo "$sweep_report" | head -n 1) -> $( [ "$sweep_ok" = yes ] && echo "EQUAL (all columns but the timing ones)" || echo "MISMATCH")
EOF
echo "$sweep_report" | grep '^MISMATCH' | sed 's/^/  /' || true
if [ "$failures" -gt 0 ]; then
  die "$failures of 2 checks failed"
fi
ok=1
