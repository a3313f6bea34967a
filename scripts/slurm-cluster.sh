#!/usr/bin/env bash
# A single-node SLURM cluster on this machine, for trying job arrays (scripts/test-slurm,
# docs/cli.md §Running a study on a cluster).
#
#   scripts/slurm-cluster.sh start DIR   install slurm-wlm and munge when missing, write a
#                                        munge key and a slurm.conf under DIR, start munged,
#                                        slurmctld and slurmd, wait until the node is idle
#   scripts/slurm-cluster.sh env DIR     print the `export SLURM_CONF=…` that points sbatch,
#                                        sinfo, squeue … at this cluster (eval it)
#   scripts/slurm-cluster.sh stop DIR    stop the daemons and remove what start wrote
#
# Runs as root (the daemons do, and the packages come from apt-get); a non-root caller is
# told how. Everything lives under DIR (key, configuration, state, spool, logs, sockets,
# pid files): nothing under /etc or /var is written, so it does not disturb a system slurm
# or munge, though it uses slurm's default ports 6817/6818.
set -euo pipefail

usage() {
  echo "usage: $0 start DIR | env DIR | stop DIR" >&2
  exit 2
}
[ $# -eq 2 ] || usage
cmd=$1
dir=$(realpath -m "$2")
conf=$dir/slurm.conf
# What `start` creates in DIR, and all that `stop` removes.
created=(slurm.conf munge state spool log slurmctld.pid slurmd.pid)

say() { echo "slurm-cluster: $*" >&2; }

need_root() {
  if [ "$(id -u)" != 0 ]; then
    say "$1 needs root (the daemons run as root); run it with sudo, after"
    say "  sudo apt-get install slurm-wlm munge"
    exit 1
  fi
}

install_packages() {
  command -v slurmctld >/dev/null && command -v slurmd >/dev/null && command -v sbatch >/dev/null \
    && command -v munged >/dev/null && return 0
  say "installing slurm-wlm and munge from Debian"
  # Keep the packages' own services from starting (this script starts its own daemons).
  local policy=/usr/sbin/policy-rc.d made_policy=
  if [ ! -e $policy ]; then
    printf '#!/bin/sh\nexit 101\n' >$policy && chmod 755 $policy && made_policy=1
  fi
  local rc=0
  { DEBIAN_FRONTEND=noninteractive apt-get update -qq &&
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq -o DPkg::Lock::Timeout=600 \
      slurm-wlm munge >/dev/null; } || rc=$?
  [ -z "$made_policy" ] || rm -f $policy
  [ $rc = 0 ] || { say "apt-get install slurm-wlm munge failed (exit $rc)"; exit 1; }
}

# CPUs and memory as this machine (and slurmd, which checks them) sees them.
node_line() {
  local host=$1 cpus mem_kb
  cpus=$(nproc)
  mem_kb=$(awk '/^MemTotal:/ {print $2}' /proc/meminfo)
  # 90 % of the memory: a node configured above what slurmd measures would be drained.
  echo "NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$((mem_kb / 1024 * 9 / 10)) State=UNKNOWN"
}

write_conf() {
  local host=$1
  cat >"$conf" <<EOF
# Single-node cluster written by scripts/slurm-cluster.sh; remove with its stop command.
ClusterName=chute
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket.2
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
$(node_line "$host")
PartitionName=chute Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
}

start_munge() {
  local m=$dir/munge
  mkdir -p "$m" && chmod 700 "$m"
  # A fresh 1 KiB key, readable by its owner only (munged refuses anything looser).
  ( umask 077 && head -c 1024 /dev/urandom >"$m/munge.key" )
  munged --key-file="$m/munge.key" --socket="$m/munge.socket.2" --pid-file="$m/munged.pid" \
    --log-file="$m/munged.log" --seed-file="$m/munged.seed" --force
}

wait_idle() {
  local host=$1 state=
  for _ in $(seq 1 60); do
    state=$(SLURM_CONF=$conf sinfo -h -N -n "$host" -o %t 2>/dev/null || true)
    [ "$state" = idle ] && return 0
    sleep 1
  done
  say "the node $host is not idle after 60 s (state: ${state:-none}); logs in $dir/log"
  tail -n 20 "$dir/log/slurmctld.log" "$dir/log/slurmd.log" >&2 2>/dev/null || true
  return 1
}

start() {
  need_root start
  install_packages
  if [ -e "$conf" ]; then
    say "$dir already holds a cluster; stop it first: $0 stop $dir"
    exit 1
  fi
  local host
  host=$(hostname -s)
  mkdir -p "$dir/state" "$dir/spool" "$dir/log"
  write_conf "$host"
  start_munge
  SLURM_CONF=$conf slurmctld
  SLURM_CONF=$conf slurmd -N "$host"
  wait_idle "$host"
  say "node $host idle; use it with: eval \"\$($0 env $dir)\""
}

# Stop the daemon whose pid file is $1, waiting (bounded) for it to exit.
stop_daemon() {
  local pidfile=$1 pid
  [ -f "$pidfile" ] || return 0
  pid=$(cat "$pidfile")
  if [ -n "$pid" ] && kill "$pid" 2>/dev/null; then
    for _ in $(seq 1 50); do
      kill -0 "$pid" 2>/dev/null || return 0
      sleep 0.2
    done
    kill -9 "$pid" 2>/dev/null || true
  fi
}

stop() {
  [ -e "$conf" ] || [ -d "$dir/munge" ] || { say "no cluster in $dir"; return 0; }
  stop_daemon "$dir/slurmd.pid"
  stop_daemon "$dir/slurmctld.pid"
  stop_daemon "$dir/munge/munged.pid"
  for f in "${created[@]}"; do rm -rf "${dir:?}/$f"; done
  rmdir "$dir" 2>/dev/null || true
}

case $cmd in
  start) start ;;
  env) echo "export SLURM_CONF=$conf" ;;
  stop) stop ;;
  *) usage ;;
esac
