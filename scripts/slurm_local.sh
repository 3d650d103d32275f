#!/usr/bin/env bash
# A single-node Slurm cluster on localhost, for the cluster test and for trying
# `arcs slurm` without a cluster (Debian's slurm-wlm 22.05 and munge; installed
# by scripts/install_deps.sh). Needs root (slurmd runs jobs as their user).
#
#   scripts/slurm_local.sh start [DIR]   # munged (unless one answers), slurmctld, slurmd
#   export SLURM_CONF=DIR/slurm.conf     # point sbatch/squeue/sinfo at it
#   scripts/slurm_local.sh stop [DIR]    # stops the daemons this script started, by pid
#   scripts/slurm_local.sh status [DIR]
#
# DIR defaults to $ARCS_SLURM_DIR or /tmp/arcs-slurm-local; everything (config,
# state, logs, pid files) lives there. Ports: $ARCS_SLURM_PORT (slurmctld,
# default 6817) and the next one (slurmd). Exit status of start: 0 up,
# 3 not root, 4 packages missing, 5 a daemon did not start (the reason is printed).
set -uo pipefail

cmd=${1:-}
DIR=${2:-${ARCS_SLURM_DIR:-/tmp/arcs-slurm-local}}
PORT=${ARCS_SLURM_PORT:-6817}

say() { echo "slurm_local: $*" >&2; }

# Stops one daemon by the pid file we own, checking the pid is still that program.
stop_pid() {
  local name=$1 pidfile=$2
  [ -f "$pidfile" ] || return 0
  local pid
  pid=$(cat "$pidfile" 2>/dev/null)
  if [ -n "$pid" ] && [ -d "/proc/$pid" ] && grep -q "$name" "/proc/$pid/comm" 2>/dev/null; then
    kill -TERM "$pid" 2>/dev/null
    for _ in $(seq 1 50); do [ -d "/proc/$pid" ] || break; sleep 0.2; done
    if [ -d "/proc/$pid" ]; then kill -KILL "$pid" 2>/dev/null; say "$name ($pid) killed"; else say "$name ($pid) stopped"; fi
  fi
  rm -f "$pidfile"
}

do_stop() {
  [ -f "$DIR/started" ] || { say "nothing started from $DIR"; return 0; }
  # slurmd, then slurmctld, then munged (only those this script started).
  for d in slurmd slurmctld munged; do
    grep -qx "$d" "$DIR/started" && stop_pid "$d" "$DIR/$d.pid"
  done
  rm -f "$DIR/started"
}

port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }

do_start() {
  [ "$(id -u)" -eq 0 ] || { say "needs root (slurmd runs the jobs); not starting"; return 3; }
  local missing=()
  for c in slurmctld slurmd sbatch squeue sinfo munged munge unmunge runuser; do
    command -v "$c" >/dev/null 2>&1 || [ -x "/usr/sbin/$c" ] || missing+=("$c")
  done
  [ ${#missing[@]} -eq 0 ] || { say "not installed: ${missing[*]} (scripts/install_deps.sh installs slurm-wlm and munge)"; return 4; }
  [ -f "$DIR/started" ] && { say "$DIR: already started (stop it first)"; return 5; }
  mkdir -p "$DIR/log" "$DIR/spool"
  rm -rf "$DIR/state" && mkdir -p "$DIR/state"
  : > "$DIR/started"

  # munge: use one that already answers, else start ours.
  if ! (munge -n | unmunge) >/dev/null 2>&1; then
    mkdir -p /run/munge /var/log/munge /var/lib/munge /etc/munge "$DIR/munge"
    if [ ! -s /etc/munge/munge.key ]; then
      if command -v mungekey >/dev/null 2>&1; then mungekey --create >/dev/null 2>&1
      else dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 2>/dev/null; fi
    fi
    chown munge:munge /run/munge /var/log/munge /var/lib/munge /etc/munge /etc/munge/munge.key "$DIR/munge"
    chmod 0700 /etc/munge /var/lib/munge /var/log/munge && chmod 0400 /etc/munge/munge.key && chmod 0755 /run/munge
    if ! runuser -u munge -- /usr/sbin/munged --pid-file="$DIR/munge/munged.pid" >"$DIR/log/munged.out" 2>&1; then
      say "munged did not start: $(tail -3 "$DIR/log/munged.out" | tr '\n' ' ')"; do_stop; return 5
    fi
    for _ in $(seq 1 50); do [ -s "$DIR/munge/munged.pid" ] && break; sleep 0.1; done
    cp "$DIR/munge/munged.pid" "$DIR/munged.pid" 2>/dev/null && echo munged >> "$DIR/started"
    for _ in $(seq 1 30); do (munge -n | unmunge) >/dev/null 2>&1 && break; sleep 0.2; done
    (munge -n | unmunge) >/dev/null 2>&1 || { say "munge does not answer after starting munged"; do_stop; return 5; }
  fi

  local host cpus
  host=$(hostname -s)
  cpus=$(nproc --all)
  for p in "$PORT" $((PORT + 1)); do
    port_free "$p" || { say "port $p is in use (set ARCS_SLURM_PORT to another one)"; do_stop; return 5; }
  done
  cat > "$DIR/slurm.conf" <<EOF
# Written by scripts/slurm_local.sh: a single-node cluster on localhost.
ClusterName=arcslocal
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$PORT
SlurmdPort=$((PORT + 1))
AuthType=auth/munge
CredType=cred/munge
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$DIR/slurmctld.pid
SlurmdPidFile=$DIR/slurmd.pid
SlurmctldLogFile=$DIR/log/slurmctld.log
SlurmdLogFile=$DIR/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=2000 State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF="$DIR/slurm.conf"
  slurmctld -f "$SLURM_CONF" >"$DIR/log/slurmctld.out" 2>&1 || { say "slurmctld did not start: $(tail -3 "$DIR/log/slurmctld.log" 2>/dev/null | tr '\n' ' ')"; do_stop; return 5; }
  for _ in $(seq 1 50); do [ -s "$DIR/slurmctld.pid" ] && break; sleep 0.1; done
  echo slurmctld >> "$DIR/started"
  slurmd -f "$SLURM_CONF" >"$DIR/log/slurmd.out" 2>&1 || { say "slurmd did not start: $(tail -3 "$DIR/log/slurmd.log" 2>/dev/null | tr '\n' ' ')"; do_stop; return 5; }
  for _ in $(seq 1 50); do [ -s "$DIR/slurmd.pid" ] && break; sleep 0.1; done
  echo slurmd >> "$DIR/started"
  local state=""
  for _ in $(seq 1 60); do
    state=$(sinfo -h -o '%t' 2>/dev/null | head -1)
    [ "$state" = "idle" ] && break
    sleep 0.5
  done
  if [ "$state" != "idle" ]; then
    say "the node is not idle after 30 s (state '$state'): $(tail -3 "$DIR/log/slurmd.log" 2>/dev/null | tr '\n' ' ')"
    do_stop; return 5
  fi
  say "up: node $host, $cpus CPUs, partition debug; export SLURM_CONF=$DIR/slurm.conf"
}

case "$cmd" in
  start) do_start ;;
  stop) do_stop ;;
  status)
    if [ -f "$DIR/slurm.conf" ] && [ -f "$DIR/started" ]; then SLURM_CONF="$DIR/slurm.conf" sinfo; else say "not started from $DIR"; exit 1; fi ;;
  *) echo "usage: $0 start|stop|status [DIR]" >&2; exit 2 ;;
esac
