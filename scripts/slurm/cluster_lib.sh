# Shared by start_local_cluster.sh, stop_local_cluster.sh and split_render.sh (sourced, not run).
# A daemon counts as ours only if its pid file's process has the daemon's name and DIR on its
# command line, so a recycled pid is never signalled.

slurm_needed_binaries=(munged munge unmunge slurmctld slurmd sbatch squeue scontrol scancel sinfo)

missing_binaries() {
  local b
  for b in "${slurm_needed_binaries[@]}"; do
    command -v "$b" >/dev/null 2>&1 || [ -x "/usr/sbin/$b" ] || echo "$b"
  done
}
slurm_binaries_present() { [ -z "$(missing_binaries)" ]; }
case ":$PATH:" in *:/usr/sbin:*) ;; *) PATH="$PATH:/usr/sbin" ;; esac

# daemon_pidfile DIR NAME
daemon_pidfile() {
  case "$2" in
    munged) echo "$1/munge/munged.pid" ;;
    *) echo "$1/$2.pid" ;;
  esac
}

# daemon_pid DIR NAME: prints the pid if that daemon of DIR is alive, else fails.
daemon_pid() {
  local f pid
  f=$(daemon_pidfile "$1" "$2")
  [ -s "$f" ] || return 1
  pid=$(tr -dc '0-9' < "$f")
  [ -n "$pid" ] && [ -r "/proc/$pid/comm" ] || return 1
  [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = "$2" ] || return 1
  tr '\0' ' ' < "/proc/$pid/cmdline" 2>/dev/null | grep -qF -- "$1/" || return 1
  echo "$pid"
}

all_daemons_alive() {
  local d
  for d in munged slurmctld slurmd; do daemon_pid "$1" "$d" >/dev/null || return 1; done
}
any_daemon_alive() {
  local d
  for d in munged slurmctld slurmd; do daemon_pid "$1" "$d" >/dev/null && return 0; done
  return 1
}

# cluster_ready DIR: the controller answers and the node is usable (idle, mixed or allocated).
cluster_ready() {
  local state
  state=$(SLURM_CONF="$1/slurm.conf" timeout 10 sinfo -h -n localhost -o %t 2>/dev/null | head -n 1) || return 1
  case "$state" in idle*|mix*|alloc*) return 0 ;; *) return 1 ;; esac
}

conf_port() { sed -n 's/^SlurmctldPort=//p' "$1/slurm.conf" 2>/dev/null; }

port_in_use() { timeout 2 bash -c ": <>/dev/tcp/127.0.0.1/$1" 2>/dev/null; }

# stop_one DIR NAME: SIGTERM, up to 15 s, then SIGKILL.
stop_one() {
  local pid i
  pid=$(daemon_pid "$1" "$2") || return 0
  kill -TERM "$pid" 2>/dev/null || return 0
  for i in $(seq 1 75); do
    [ -d "/proc/$pid" ] || return 0
    sleep 0.2
  done
  echo "stop: $2 (pid $pid) ignored SIGTERM for 15 s; sending SIGKILL" >&2
  kill -KILL "$pid" 2>/dev/null || true
}

# stop_daemons DIR: cancels every job of the cluster, then stops slurmd, slurmctld, munged.
stop_daemons() {
  local i
  if daemon_pid "$1" slurmctld >/dev/null; then
    SLURM_CONF="$1/slurm.conf" timeout 10 scancel --partition=debug >/dev/null 2>&1 || true
    for i in $(seq 1 50); do
      [ -z "$(SLURM_CONF="$1/slurm.conf" timeout 10 squeue -h -t R,CG 2>/dev/null)" ] && break
      sleep 0.2
    done
  fi
  stop_one "$1" slurmd
  stop_one "$1" slurmctld
  stop_one "$1" munged
}
