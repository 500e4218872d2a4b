#!/usr/bin/env bash
# A one-node SLURM cluster on this machine, for tests and trying the sbatch script (docs/background/slurm.md):
#   tools/slurm/local-cluster.sh start DIR   config, state, logs and its own munge daemon in DIR;
#                                            prints the line `export SLURM_CONF=DIR/slurm.conf`
#   tools/slurm/local-cluster.sh stop DIR    cancels its jobs, stops its daemons by their pid files
# Needs root and Debian's slurm-wlm and munge (tools/deps.sh). Each cluster gets free ports and
# its own munged socket, so it cannot collide with another cluster or a daemon left running.
set -euo pipefail

die() { echo "local-cluster: $*" >&2; exit 1; }
cmd=${1:-}
dir=${2:-}
[[ ( $cmd == start || $cmd == stop ) && -n $dir ]] || die "usage: $0 start|stop DIR"

# Stops the process in pid file $1: TERM, then KILL after 10 s.
stop_pid() {
  local file=$1 pid
  [[ -s $file ]] || return 0
  pid=$(<"$file")
  [[ $pid =~ ^[0-9]+$ ]] || return 0
  kill "$pid" 2>/dev/null || { rm -f "$file"; return 0; }
  for _ in $(seq 1 100); do
    kill -0 "$pid" 2>/dev/null || { rm -f "$file"; return 0; }
    sleep 0.1
  done
  kill -9 "$pid" 2>/dev/null || true
  rm -f "$file"
}

if [[ $cmd == stop ]]; then
  [[ -d $dir ]] || exit 0
  dir=$(cd "$dir" && pwd)
  if [[ -s $dir/run/slurmctld.pid && -f $dir/slurm.conf ]]; then
    # Our cluster's jobs only: the clients talk to the controller SLURM_CONF names.
    SLURM_CONF=$dir/slurm.conf timeout 10 scancel --quiet --user "$(id -un)" 2>/dev/null || true
    sleep 1
  fi
  stop_pid "$dir/run/slurmd.pid"
  stop_pid "$dir/run/slurmctld.pid"
  stop_pid "$dir/munge/munged.pid"
  echo "local-cluster: stopped the cluster in $dir"
  exit 0
fi

[[ $(id -u) -eq 0 ]] || die "needs root (slurmd runs jobs as their users; munged runs as munge)"
for b in slurmctld slurmd munged sbatch sinfo squeue scancel runuser python3; do
  command -v "$b" >/dev/null || die "'$b' is missing (tools/deps.sh installs slurm-wlm and munge)"
done
id munge >/dev/null 2>&1 || die "no munge user (install the munge package)"
[[ -r /etc/munge/munge.key ]] || die "no /etc/munge/munge.key (the munge package creates it)"
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
[[ ! -e $dir/slurm.conf ]] || die "$dir holds a cluster already; stop it first"
chmod 755 "$dir"  # the munge user must reach its folder inside
mkdir -p "$dir/state" "$dir/spool" "$dir/log" "$dir/run" "$dir/munge"
runuser -u munge -- test -x "$dir" ||
  die "the munge user cannot reach $dir (a parent folder is not searchable by others); use a folder like /tmp/X"
chown munge:munge "$dir/munge"
chmod 755 "$dir/munge"  # munged wants its socket folder reachable by all

# Two free TCP ports (bound and released at once; the daemons take them right after).
read -r ctld_port slurmd_port < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
host=$(hostname -s)
cpus=$(nproc)
cat > "$dir/slurm.conf" <<CONF
# Written by tools/slurm/local-cluster.sh: a one-node test cluster.
ClusterName=canopytest
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=canopy Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF

runuser -u munge -- munged --socket="$dir/munge/munge.socket" --pid-file="$dir/munge/munged.pid" \
  --seed-file="$dir/munge/munged.seed" --log-file="$dir/munge/munged.log" || die "munged did not start (see $dir/munge/munged.log)"
for _ in $(seq 1 50); do [[ -S $dir/munge/munge.socket ]] && break; sleep 0.1; done
[[ -S $dir/munge/munge.socket ]] || die "munged did not start (see $dir/munge/munged.log)"

export SLURM_CONF=$dir/slurm.conf
slurmctld -f "$SLURM_CONF" || die "slurmctld did not start (see $dir/log/slurmctld.log)"
slurmd -f "$SLURM_CONF" || die "slurmd did not start (see $dir/log/slurmd.log)"
state=""
for _ in $(seq 1 120); do
  state=$(sinfo -h -o %T 2>/dev/null || true)
  [[ $state == idle ]] && break
  sleep 0.5
done
[[ $state == idle ]] || die "the node is not idle after 60 s (state '$state'; logs in $dir/log)"
echo "local-cluster: node $host idle (controller port $ctld_port, slurmd port $slurmd_port)" >&2
echo "export SLURM_CONF=$dir/slurm.conf"
