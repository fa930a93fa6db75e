#!/usr/bin/env bash
# Stops the single-node Slurm cluster started by scripts/slurm/start_local_cluster.sh: cancels its
# jobs, then stops slurmd, slurmctld and munged (by the pids in its state folder, never by name).
# Idempotent: nothing running is not an error.
set -euo pipefail

usage() {
  cat <<EOF
Usage: $(basename "$0") [--dir DIR] [--purge]

  --dir DIR   the cluster's state folder (default: \$VPM_SLURM_DIR or /tmp/vpm-slurm)
  --purge     also delete DIR (state, logs, munge key)
  -h, --help  this help
EOF
}

dir=${VPM_SLURM_DIR:-/tmp/vpm-slurm}
purge=0
while [ $# -gt 0 ]; do
  case "$1" in
    --dir) dir=${2:?--dir needs a value}; shift 2 ;;
    --purge) purge=1; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "stop_local_cluster: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
if [ ! -d "$dir" ]; then
  echo "stop_local_cluster: no cluster folder $dir: nothing to stop" >&2
  exit 0
fi
dir=$(cd "$dir" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
. "$here/cluster_lib.sh"

stop_daemons "$dir"
if any_daemon_alive "$dir"; then
  echo "stop_local_cluster: error: some daemons of $dir are still alive" >&2
  exit 1
fi
if [ "$purge" = 1 ]; then
  # only a folder this script family created: it holds our slurm.conf or munge key
  if [ -f "$dir/slurm.conf" ] || [ -d "$dir/munge-key" ]; then
    rm -rf -- "$dir"
  else
    echo "stop_local_cluster: not purging $dir: it does not look like a cluster folder" >&2
  fi
fi
echo "stop_local_cluster: stopped ($dir)" >&2
