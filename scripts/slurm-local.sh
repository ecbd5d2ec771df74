#!/usr/bin/env bash
# A real one-node Slurm cluster on this machine, for tests and trials: munged, slurmctld and slurmd
# with every file under one private folder (the comments in start() say why its settings are so).
#   bash scripts/slurm-local.sh start DIR   starts it; prints `export SLURM_CONF=...` for clients
#   bash scripts/slurm-local.sh stop DIR    cancels its jobs, stops it, leaves no process behind
# DIR must be new or empty at start (a short path: munge's socket path has a 108-byte limit).
# Needs root and Debian's slurm-wlm, munge and procps (scripts/install-deps.sh --test). When it
# cannot start here (not root, a package missing, Slurm's ports taken) it says why and exits 77,
# the code the tests count as skipped.
set -euo pipefail
cmd=${1:-}
dir=${2:-}
node=rtsim-node
ports=(6817 6818)
usage() { echo "usage: $0 start|stop DIR" >&2; exit 2; }
[ -n "$cmd" ] && [ -n "$dir" ] || usage
cannot() { echo "slurm-local: cannot start a cluster here: $*" >&2; exit 77; }
die() { echo "slurm-local: $*" >&2; exit 1; }

port_taken() { (exec 3<> "/dev/tcp/127.0.0.1/$1") 2> /dev/null; }
alive() { [ -f "$1" ] && kill -0 "$(cat "$1")" 2> /dev/null; }
# Waits up to 30 s for `check`; fails at once when the daemon of pid file $1 has died.
wait_for() {
  local pidfile=$1 what=$2
  shift 2
  for _ in $(seq 1 300); do
    if "$@" > /dev/null 2>&1; then return 0; fi
    alive "$pidfile" || die "$what died at start (see $dir/*.log)"
    sleep 0.1
  done
  die "$what did not come up in 30 s (see $dir/*.log)"
}

start() {
  [ "$(id -u)" -eq 0 ] || cannot "not root (munged changes user, slurmd runs jobs as their owner)"
  for c in munged mungekey slurmctld slurmd sbatch scontrol squeue sinfo pgrep runuser; do
    command -v "$c" > /dev/null || cannot "$c is missing (apt-get install slurm-wlm munge procps)"
  done
  for p in "${ports[@]}"; do
    ! port_taken "$p" || cannot "port $p is taken (another Slurm cluster?)"
  done
  mkdir -p "$dir"
  dir=$(cd "$dir" && pwd)
  [ -z "$(ls -A "$dir")" ] || die "$dir is not empty"
  chmod 755 "$dir"
  runuser -u munge -- test -x "$dir" || die "the munge user cannot reach $dir (a folder above it is private)"
  local m="$dir/munge"
  mkdir -p "$m" "$dir/state" "$dir/spool"
  chown munge:munge "$m"
  chmod 755 "$m"  # munged: the socket folder must be searchable by all
  runuser -u munge -- mungekey --create --keyfile="$m/munge.key" --force > /dev/null
  chmod 400 "$m/munge.key"
  runuser -u munge -- munged --socket="$m/munge.socket" --key-file="$m/munge.key" \
    --pid-file="$m/munged.pid" --log-file="$m/munged.log" --seed-file="$m/munged.seed"
  wait_for "$m/munged.pid" munged bash -c "munge -n -S '$m/munge.socket' | unmunge -S '$m/munge.socket'"

  # The node as slurmd sees it (CPUs, sockets, memory), under our name and on the loopback.
  # A sandbox's settings: munged's socket in DIR (no /run/munge without systemd); no cgroup,
  # accounting or MPI plugins; MinJobAge keeps finished tasks in `scontrol show job` (there is no
  # sacct without slurmdbd); batch_sched_delay=0 starts an array's tasks at once.
  local hw
  hw=$(slurmd -C | head -n 1 | sed "s/^NodeName=[^ ]*/NodeName=$node NodeAddr=127.0.0.1/")
  cat > "$dir/slurm.conf" << CONF
ClusterName=rtsim
SlurmctldHost=$(hostname -s)(127.0.0.1)
SlurmctldPort=${ports[0]}
SlurmdPort=${ports[1]}
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$m/munge.socket
SlurmUser=root
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
SchedulerParameters=batch_sched_delay=0
MinJobAge=3600
$hw State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF="$dir/slurm.conf"
  slurmctld -f "$SLURM_CONF"
  wait_for "$dir/slurmctld.pid" slurmctld bash -c "scontrol ping | grep -q UP"
  slurmd -f "$SLURM_CONF" -N "$node"
  wait_for "$dir/slurmd.pid" slurmd bash -c "sinfo -h -n $node -o %T | grep -qx idle"
  echo "export SLURM_CONF=$SLURM_CONF"
}

stop() {
  [ -d "$dir" ] || return 0
  dir=$(cd "$dir" && pwd)
  export SLURM_CONF="$dir/slurm.conf"
  if alive "$dir/slurmctld.pid"; then
    scancel --user=root > /dev/null 2>&1 || true
    scontrol shutdown > /dev/null 2>&1 || true
  fi
  # Whatever is still alive (scontrol cannot authenticate once munged is gone), job steps last:
  # they outlive a dead slurmd and are found by their folder.
  for pidfile in "$dir/slurmd.pid" "$dir/slurmctld.pid"; do
    for _ in $(seq 1 50); do alive "$pidfile" || break; sleep 0.1; done
    ! alive "$pidfile" || kill -TERM "$(cat "$pidfile")" 2> /dev/null || true
  done
  ! alive "$dir/munge/munged.pid" || kill -TERM "$(cat "$dir/munge/munged.pid")" 2> /dev/null || true
  local left
  for _ in $(seq 1 50); do
    left=$(ours)
    [ -n "$left" ] || return 0
    sleep 0.1
  done
  kill -KILL $left 2> /dev/null || true
  sleep 0.2
  [ -z "$(ours)" ] || die "processes of $dir outlived the stop: $(ours)"
}

# The cluster's processes: the daemons name $dir/ on their command lines, job steps (slurmstepd)
# run in its spool folder.
ours() {
  local pid
  pgrep -f "$dir/" || true
  for pid in $(pgrep -x slurmstepd); do
    case "$(readlink "/proc/$pid/cwd" 2> /dev/null)" in "$dir"/*) echo "$pid" ;; esac
  done
}

case "$cmd" in
  start) start ;;
  stop) stop ;;
  *) usage ;;
esac
