#!/usr/bin/env bash
# Starts a single-node Slurm cluster on this machine (Debian 12 packages slurm-wlm and munge), for
# trying vpm's job arrays without a real cluster. No systemd: munged, slurmctld and slurmd run as
# plain daemons with a generated slurm.conf and all state in one private folder; they listen on the
# loopback address only. No accounting (sacct is unavailable; squeue/scontrol work).
# Idempotent: when the cluster of --dir is already up it only prints how to use it.
# Stop it with scripts/slurm/stop_local_cluster.sh --dir DIR.
set -euo pipefail

usage() {
  cat <<EOF
Usage: $(basename "$0") [--dir DIR] [--port PORT] [--no-install] [--quiet]

Starts munged, slurmctld and slurmd (one node named localhost, CPUs = nproc, partition "debug")
with all state, logs and sockets under DIR, listening on 127.0.0.1 only.

  --dir DIR      state folder (default: \$VPM_SLURM_DIR or /tmp/vpm-slurm)
  --port PORT    slurmctld port; slurmd uses PORT+1 (default: 16817)
  --no-install   exit 3 instead of installing slurm-wlm/munge with apt-get when missing
  --quiet        print only errors
  -h, --help     this help

Then use the cluster with:  export SLURM_CONF=DIR/slurm.conf   (or: source DIR/env.sh)
Exit codes: 0 running, 1 failed to start (logs are printed), 2 usage error,
            3 Slurm cannot run here (not root, or packages missing with --no-install).
EOF
}

dir=${VPM_SLURM_DIR:-/tmp/vpm-slurm}
port=16817
install=1
quiet=0
while [ $# -gt 0 ]; do
  case "$1" in
    --dir) dir=${2:?--dir needs a value}; shift 2 ;;
    --port) port=${2:?--port needs a value}; shift 2 ;;
    --no-install) install=0; shift ;;
    --quiet) quiet=1; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "start_local_cluster: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[[ "$port" =~ ^[0-9]+$ ]] && [ "$port" -ge 1024 ] && [ "$port" -le 65534 ] ||
  { echo "start_local_cluster: --port must be an integer in 1024..65534, got '$port'" >&2; exit 2; }
say() { [ "$quiet" = 1 ] || echo "start_local_cluster: $*" >&2; }
die() { echo "start_local_cluster: error: $*" >&2; exit 1; }

here=$(cd "$(dirname "$0")" && pwd)
. "$here/cluster_lib.sh"

# --- Packages and privileges ---------------------------------------------------------------------
if [ "$(id -u)" -ne 0 ]; then
  echo "start_local_cluster: Slurm cannot run here: slurmd must run as root (it starts jobs as their user); run as root" >&2
  exit 3
fi
if ! slurm_binaries_present; then
  if [ "$install" = 0 ]; then
    echo "start_local_cluster: Slurm cannot run here: missing $(missing_binaries | tr '\n' ' ')(Debian packages slurm-wlm munge; run without --no-install or scripts/install-deps.sh)" >&2
    exit 3
  fi
  say "installing slurm-wlm munge with apt-get"
  export DEBIAN_FRONTEND=noninteractive
  if ! timeout 600 apt-get install -y -qq --no-install-recommends slurm-wlm munge >/dev/null; then
    timeout 300 apt-get update -qq || die "apt-get update failed"
    timeout 600 apt-get install -y -qq --no-install-recommends slurm-wlm munge >/dev/null ||
      die "apt-get install slurm-wlm munge failed"
  fi
  slurm_binaries_present || die "still missing after install: $(missing_binaries | tr '\n' ' ')"
fi

mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
export SLURM_CONF="$dir/slurm.conf"

# --- Already running? ----------------------------------------------------------------------------
if [ -f "$dir/slurm.conf" ] && all_daemons_alive "$dir" && cluster_ready "$dir"; then
  say "already running in $dir (port $(conf_port "$dir")): export SLURM_CONF=$dir/slurm.conf"
  exit 0
fi
if any_daemon_alive "$dir"; then
  say "some daemons of $dir are running but the cluster is not ready: restarting them"
  stop_daemons "$dir"
fi

# A stale cluster of this folder may have used another port: the port given now wins.
for p in "$port" $((port + 1)); do
  if port_in_use "$p"; then
    die "port $p on 127.0.0.1 is in use by another program; choose another with --port"
  fi
done

# --- munge: a private key and socket ---------------------------------------------------------------
mkdir -p "$dir/munge" "$dir/munge-key" "$dir/state" "$dir/spool" "$dir/log"
chmod 755 "$dir" "$dir/munge"          # munged wants its socket folder reachable by all
chmod 700 "$dir/munge-key"
if [ ! -s "$dir/munge-key/munge.key" ]; then
  head -c 1024 /dev/urandom > "$dir/munge-key/munge.key"
fi
chmod 400 "$dir/munge-key/munge.key"
rm -f "$dir/munge/munge.sock" "$dir/munge/munge.sock.lock"
munged --key-file="$dir/munge-key/munge.key" --socket="$dir/munge/munge.sock" \
  --pid-file="$dir/munge/munged.pid" --log-file="$dir/log/munged.log" \
  --seed-file="$dir/munge/munged.seed" ||
  { tail -n 5 "$dir/log/munged.log" >&2 2>/dev/null || true; die "munged did not start (log: $dir/log/munged.log)"; }
timeout 10 bash -c "until munge -n -S '$dir/munge/munge.sock' 2>/dev/null | unmunge -S '$dir/munge/munge.sock' >/dev/null 2>&1; do sleep 0.2; done" ||
  die "munged does not answer on $dir/munge/munge.sock (log: $dir/log/munged.log)"

# --- slurm.conf ----------------------------------------------------------------------------------
cat > "$dir/slurm.conf" <<EOF
# Generated by scripts/slurm/start_local_cluster.sh: a single-node cluster on loopback, no accounting.
ClusterName=vpmlocal
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
CommunicationParameters=NoInAddrAny,NoCtldInAddrAny
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.sock
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
SchedulerType=sched/backfill
SchedulerParameters=sched_interval=1
DependencyParameters=kill_invalid_depend
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
MinJobAge=600
KillWait=5
Waittime=0
NodeName=localhost NodeHostname=localhost NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=60 State=UP
EOF
printf 'export SLURM_CONF=%q\n' "$dir/slurm.conf" > "$dir/env.sh"

# --- slurmctld, slurmd ---------------------------------------------------------------------------
slurmctld -f "$dir/slurm.conf" ||
  { tail -n 20 "$dir/log/slurmctld.log" >&2 2>/dev/null || true; stop_daemons "$dir"; die "slurmctld did not start"; }
slurmd -f "$dir/slurm.conf" -N localhost ||
  { tail -n 20 "$dir/log/slurmd.log" >&2 2>/dev/null || true; stop_daemons "$dir"; die "slurmd did not start"; }

deadline=$((SECONDS + 30))
until cluster_ready "$dir"; do
  if [ $SECONDS -ge $deadline ]; then
    echo "--- slurmctld.log" >&2; tail -n 20 "$dir/log/slurmctld.log" >&2 2>/dev/null || true
    echo "--- slurmd.log" >&2; tail -n 20 "$dir/log/slurmd.log" >&2 2>/dev/null || true
    stop_daemons "$dir"
    die "the node did not become idle within 30 s (logs above, in $dir/log)"
  fi
  sleep 0.5
done
say "running in $dir: node localhost, $(nproc) CPUs, port $port/$((port + 1)) on 127.0.0.1"
say "use it with: export SLURM_CONF=$dir/slurm.conf   stop it with: $here/stop_local_cluster.sh --dir $dir"
