#!/usr/bin/env bash
# A one-node Slurm cluster on this machine (munged, slurmctld, slurmd), for tests, demos and a
# laptop: tools/slurm/local-cluster.sh start|stop|status. Runs as root (or through sudo).
#
# start   installs slurm-wlm and munge if missing (apt-get), writes a slurm.conf naming this
#         host (CPUs = the cores seen, one partition "local"), starts what is not running and
#         waits until the node is idle. Idempotent: a second start changes nothing.
# stop    stops only the daemons this script started (their pids are kept in the state dir);
#         a munged that was already running stays.
# status  says which daemons run and prints sinfo; exit 0 when the node takes jobs, 3 if not.
#
# State, logs and the config live in CLOTHSIM_SLURM_DIR (default /var/tmp/clothsim-slurm).
# Clients find the config through /etc/slurm/slurm.conf, linked to ours when no other is
# there; otherwise `start` prints the SLURM_CONF line to export.
set -euo pipefail

state=${CLOTHSIM_SLURM_DIR:-/var/tmp/clothsim-slurm}
conf=$state/slurm.conf
host=$(hostname -s)
if [[ $(id -u) -ne 0 ]]; then sudo=sudo; else sudo=; fi

say() { echo "local-cluster: $*" >&2; }

install_packages() {
  local missing=()
  for p in slurm-wlm munge; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
  done
  ((${#missing[@]})) || return 0
  say "installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

# A pid file of ours whose process still runs the named program.
ours_running() {
  local pid_file=$state/$1.pid
  [[ -s $pid_file ]] || return 1
  local pid
  pid=$(<"$pid_file")
  [[ -r /proc/$pid/comm && $(</proc/$pid/comm) == "$1" ]]
}

munge_works() { munge -n </dev/null 2>/dev/null | unmunge >/dev/null 2>&1; }

start_munge() {
  if munge_works; then return 0; fi  # a munged of the system's, or ours from an earlier start
  $sudo mkdir -p /run/munge /var/log/munge /var/lib/munge /etc/munge
  $sudo chown munge:munge /run/munge /var/log/munge /var/lib/munge
  $sudo chmod 0755 /run/munge
  if [[ ! -s /etc/munge/munge.key ]]; then
    $sudo dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
  fi
  $sudo chown munge:munge /etc/munge/munge.key
  $sudo chmod 0400 /etc/munge/munge.key
  $sudo runuser -u munge -- /usr/sbin/munged --pid-file=/run/munge/clothsim-munged.pid
  for _ in $(seq 50); do munge_works && break; sleep 0.1; done
  munge_works || { say "munged did not start (see /var/log/munge/munged.log)"; exit 1; }
  $sudo cp /run/munge/clothsim-munged.pid "$state/munged.pid"
}

# slurmctld 22.05 starts pending jobs (an array's next wave, a merge whose dependency is
# met) on a scheduling pass, not when a task ends: sched_interval=1 runs one every second
# (default 60), the most it allows; without it each wave and the merge waited 2-3 s more
# (docs/cluster.md, "Where the overhead goes").
write_conf() {
  local cpus mem_mb
  cpus=$(nproc)
  mem_mb=$(awk '/MemTotal/ {print int($2 / 1024 * 0.9)}' /proc/meminfo)
  $sudo mkdir -p "$state/ctld" "$state/d" "$state/log"
  $sudo tee "$conf" >/dev/null <<EOF
# Written by tools/slurm/local-cluster.sh: a one-node cluster on $host.
ClusterName=clothsim-local
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
AuthType=auth/munge
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
JobAcctGatherType=jobacct_gather/none
SchedulerType=sched/backfill
SchedulerParameters=sched_min_interval=100000,sched_interval=1
ReturnToService=2
KillWait=10
MinJobAge=300
StateSaveLocation=$state/ctld
SlurmdSpoolDir=$state/d
SlurmctldPidFile=$state/slurmctld.pid
SlurmdPidFile=$state/slurmd.pid
SlurmctldLogFile=$state/log/slurmctld.log
SlurmdLogFile=$state/log/slurmd.log
DefMemPerCPU=$((mem_mb / cpus))
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem_mb State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
  if [[ ! -e /etc/slurm/slurm.conf ]]; then
    $sudo mkdir -p /etc/slurm
    $sudo ln -s "$conf" /etc/slurm/slurm.conf
    $sudo touch "$state/linked-etc-conf"
  fi
}

# The config the clients read: ours when /etc/slurm/slurm.conf is (a link to) it.
uses_our_conf() { [[ $(readlink -f /etc/slurm/slurm.conf 2>/dev/null) == "$(readlink -f "$conf")" ]]; }

node_state() { SLURM_CONF=$conf sinfo -h -n "$host" -o %T 2>/dev/null | head -1; }

wait_for_node() {
  local s=
  for _ in $(seq 100); do
    s=$(node_state)
    case $s in
      idle*|mixed*|allocated*|completing*) return 0 ;;
      down*|drain*) SLURM_CONF=$conf scontrol update nodename="$host" state=resume 2>/dev/null || true ;;
    esac
    sleep 0.3
  done
  say "the node is '$s' after 30 s (logs in $state/log)"
  exit 1
}

start() {
  install_packages
  $sudo mkdir -p "$state"
  start_munge
  if ! ours_running slurmctld || ! ours_running slurmd; then
    ours_running slurmctld || write_conf
    ours_running slurmctld || $sudo slurmctld -c -f "$conf"  # -c: no jobs of an earlier run come back
    ours_running slurmd || $sudo slurmd -f "$conf"
  fi
  wait_for_node
  say "running: node $host ($(nproc) CPUs), partition local, config $conf"
  uses_our_conf || say "export SLURM_CONF=$conf   # another slurm.conf is in /etc/slurm"
}

stop_daemon() {
  ours_running "$1" || return 0
  local pid
  pid=$(<"$state/$1.pid")
  $sudo kill "$pid"
  for _ in $(seq 100); do [[ -d /proc/$pid ]] || break; sleep 0.1; done
  say "stopped $1 ($pid)"
}

stop() {
  stop_daemon slurmd
  stop_daemon slurmctld
  stop_daemon munged
  $sudo rm -f "$state/munged.pid"
  if [[ -e $state/linked-etc-conf ]]; then
    uses_our_conf && $sudo rm -f /etc/slurm/slurm.conf
    $sudo rm -f "$state/linked-etc-conf"
  fi
}

status() {
  local up=0
  for d in munged slurmctld slurmd; do
    if ours_running "$d"; then echo "$d: running (pid $(<"$state/$d.pid"), started here)"
    elif [[ $d == munged ]] && munge_works; then echo "munged: running (not started here)"
    else echo "$d: stopped"; up=3; fi
  done
  if ((up == 0)); then
    SLURM_CONF=$conf sinfo
    [[ $(node_state) =~ ^(idle|mixed|allocated|completing) ]] || up=3
  fi
  return $up
}

case ${1:-} in
  start) start ;;
  stop) stop ;;
  status) status ;;
  *) echo "usage: $0 start|stop|status" >&2; exit 2 ;;
esac
