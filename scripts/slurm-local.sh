#!/usr/bin/env bash
# A single-node Slurm cluster on this machine, from Debian's packages, for the experiment runner's
# slurm executor (tests, trying it out):
#
#   bash scripts/slurm-local.sh start [DIR]    install if needed, write DIR/slurm.conf, start munged,
#                                              slurmctld and slurmd; the partition is `local`
#   bash scripts/slurm-local.sh stop [DIR]     cancel the jobs, wait for them, stop the daemons
#   bash scripts/slurm-local.sh status [DIR]   sinfo
#
# DIR (default /tmp/vs-slurm) holds the config, state, spool, logs and pid files. The commands need
# SLURM_CONF=DIR/slurm.conf in their environment (`start` prints it; the default DIR is also linked
# from /etc/slurm/slurm.conf when that is free, so plain sbatch works).
# Needs root (the daemons, apt-get, /run/munge); exits 77 with a message when they cannot start.
# Facts this relies on (Debian 12: Slurm 22.05, munge 0.5.15, no systemd): nothing starts the
# daemons, so we start them directly; /run/munge must exist and belong to munge before munged starts;
# the node name must resolve; proctrack/linuxproc with task/none needs no cgroups; RealMemory may not
# exceed what `slurmd -C` reports; batch_sched_delay=0 drops ~3 s per batch job; without slurmdbd,
# `squeue -t all` (within MinJobAge) and `scontrol show job` give the tasks' states and exit codes;
# `scontrol shutdown` leaves running jobs' slurmstepd alive, so jobs are cancelled and waited for first.
set -euo pipefail
action=${1:-}
dir=${2:-/tmp/vs-slurm}
SKIP=77

die() { echo "slurm-local: $*" >&2; exit "${code:-1}"; }

install() {
  if command -v slurmctld >/dev/null && command -v slurmd >/dev/null && command -v sbatch >/dev/null &&
     command -v munged >/dev/null; then
    return
  fi
  [[ $(id -u) == 0 ]] || code=$SKIP die "Slurm is not installed and installing it needs root"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends slurmctld slurmd slurm-client munge \
    >/dev/null || code=$SKIP die "apt-get install slurmctld slurmd slurm-client munge failed"
}

write_conf() {
  local node cpus mem
  node=$(hostname -s)
  if ! getent hosts "$node" >/dev/null; then
    echo "127.0.0.1 $node" >>/etc/hosts
  fi
  cpus=$(nproc)
  mem=$(slurmd -C | sed -n 's/.*RealMemory=\([0-9]*\).*/\1/p')
  mkdir -p "$dir/state" "$dir/spool" "$dir/log"
  cat >"$dir/slurm.conf" <<EOF
# Written by scripts/slurm-local.sh: one node, this machine.
ClusterName=vslocal
SlurmctldHost=$node
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
SlurmctldPort=6817
SlurmdPort=6818
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/filetxt
JobCompLoc=$dir/log/jobcomp.txt
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
MinJobAge=600
DefMemPerCPU=$((mem / cpus))
ReturnToService=2
MaxArraySize=100001
MaxJobCount=200000
NodeName=$node CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=local Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
  if [[ $dir == /tmp/vs-slurm && ! -e /etc/slurm/slurm.conf ]]; then
    mkdir -p /etc/slurm && ln -s "$dir/slurm.conf" /etc/slurm/slurm.conf
  fi
}

start() {
  install
  [[ $(id -u) == 0 ]] || code=$SKIP die "starting the daemons needs root"
  export SLURM_CONF=$dir/slurm.conf
  if [[ -f $dir/slurmctld.pid ]] && kill -0 "$(cat "$dir/slurmctld.pid")" 2>/dev/null; then
    echo "slurm-local: already running ($dir)"; echo "export SLURM_CONF=$SLURM_CONF"; return
  fi
  write_conf
  if ! pgrep -u munge -x munged >/dev/null; then
    mkdir -p /run/munge /var/lib/munge /var/log/munge /etc/munge
    [[ -s /etc/munge/munge.key ]] || { dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 2>/dev/null; }
    chown munge:munge /run/munge /var/lib/munge /var/log/munge /etc/munge /etc/munge/munge.key
    chmod 0400 /etc/munge/munge.key
    chmod 0755 /run/munge
    runuser -u munge -- munged || code=$SKIP die "munged did not start"
  fi
  slurmctld || code=$SKIP die "slurmctld did not start (see $dir/log/slurmctld.log)"
  slurmd || code=$SKIP die "slurmd did not start (see $dir/log/slurmd.log)"
  for _ in $(seq 1 100); do
    if sinfo -h -o %T 2>/dev/null | grep -qx idle; then
      echo "slurm-local: up ($dir), partition local, $(nproc) CPUs"
      echo "export SLURM_CONF=$SLURM_CONF"
      return
    fi
    sleep 0.1
  done
  code=$SKIP die "the node did not become idle: $(sinfo 2>&1 | tail -1)"
}

stop() {
  export SLURM_CONF=$dir/slurm.conf
  [[ -f $SLURM_CONF ]] || { echo "slurm-local: nothing in $dir"; return; }
  if scontrol ping >/dev/null 2>&1; then
    scancel --full --user="$(id -un)" 2>/dev/null || true
    for _ in $(seq 1 100); do  # jobs' slurmstepd would outlive the daemons
      [[ -z $(squeue -h -t running,completing -o %i 2>/dev/null) ]] && break
      sleep 0.2
    done
  fi
  local name pid
  for name in slurmd slurmctld; do
    pid=$(cat "$dir/$name.pid" 2>/dev/null || true)
    if [[ -n $pid ]] && kill -0 "$pid" 2>/dev/null; then
      kill "$pid"
      for _ in $(seq 1 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    fi
    rm -f "$dir/$name.pid"
  done
  echo "slurm-local: stopped ($dir; munged left running)"
}

case $action in
  start) start ;;
  stop) stop ;;
  status) SLURM_CONF=$dir/slurm.conf sinfo ;;
  *) echo "usage: $0 start|stop|status [DIR]" >&2; exit 2 ;;
esac
