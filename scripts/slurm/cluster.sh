#!/usr/bin/env bash
# A private single-node Slurm cluster in one folder, for the ctest test (tests/slurm/) and for
# trying the sbatch templates beside this script on one machine (issue 37).
#
# usage: scripts/slurm/cluster.sh start DIR   generate DIR/slurm.conf and a munge key, start
#                                             munged, slurmctld and slurmd, wait until the
#                                             node is idle (at most $ST_SLURM_START_TIMEOUT s, 20);
#                                             with ST_SLURM_WATCH_PID=PID, stop by itself
#                                             once process PID has ended
#        scripts/slurm/cluster.sh env DIR     print the `export SLURM_CONF=...` lines for the
#                                             client commands: eval "$(cluster.sh env DIR)"
#        scripts/slurm/cluster.sh stop DIR    cancel the jobs, stop the daemons and munged
#
# Everything lives in DIR (config, munge key and socket, state, spool, logs, pid files), so it
# runs beside a system Slurm/munge without touching them: its own munged socket (AuthInfo),
# free high ports and no cgroups (proctrack/linuxproc, task/none; containers have no systemd).
# Needs slurmctld, slurmd, slurm-client and munge (Debian 12: Slurm 22.05, munge 0.5.15).
# As root the daemons run as root (SlurmUser=root); as another user they run as that user,
# which is enough for that user's own jobs.
#
# No accounting: sacct needs slurmdbd and a database (accounting_storage/filetxt is gone
# since Slurm 17), so sacct says "accounting storage is disabled" here. States and exit codes
# of finished jobs come from `scontrol show job` (kept MinJobAge=3600 s after the end) and from
# the job-completion log DIR/jobcomp.txt (jobcomp/filetxt: one line per finished job with
# JobState and ExitCode).
#
# Exit status of start: 0 when the node is idle; 1 when Slurm could not be started here
# (missing commands, daemons not coming up: the log tails are printed); 2 for usage errors.
set -uo pipefail

usage() { sed -n '2,12p' "$0" >&2; exit 2; }
[[ $# -eq 2 ]] || usage
cmd=$1
case "$cmd" in
  start) mkdir -p "$2" 2>/dev/null || { echo "cluster.sh: cannot create $2" >&2; exit 1; } ;;
  stop) [[ -d "$2" ]] || exit 0 ;;
  env) [[ -s "$2/slurm.conf" ]] || { echo "cluster.sh: no cluster in $2" >&2; exit 1; } ;;
  *) usage ;;
esac
dir=$(cd "$2" && pwd)
conf="$dir/slurm.conf"
self=$(cd "$(dirname "$0")" && pwd)/$(basename "$0")
sock="$dir/munge.socket"

log_tails() {
  local f
  for f in munged slurmctld slurmd; do
    # A daemon in the foreground logs to both; the .out alone has what came before the log.
    [[ -s "$dir/$f.log" ]] && f="$f.log" || f="$f.out"
    [[ -s "$dir/$f" ]] || continue
    echo "---- tail of $dir/$f" >&2
    tail -n 15 "$dir/$f" >&2
  done
}

# A TCP port nothing is bound to, below Linux's ephemeral range (32768-60999) so that
# outgoing connections do not take it between the check and the daemon's bind.
port_free() {
  local p=$1
  if command -v ss >/dev/null 2>&1; then
    [[ -z "$(ss -Htan "( sport = :$p )" 2>/dev/null)" ]] || return 1
  fi
  if [[ -x /usr/bin/python3 ]]; then
    /usr/bin/python3 - "$p" <<'EOF' || return 1
import socket, sys
s = socket.socket()
s.bind(("", int(sys.argv[1])))
EOF
  fi
  return 0
}
# pick_port VAR: a free port into VAR, not one of those picked before ($taken).
taken=""
pick_port() {
  local p _
  for _ in $(seq 1 200); do
    p=$((20000 + RANDOM % 12000))
    [[ " $taken " == *" $p "* ]] && continue
    if port_free "$p"; then taken="$taken $p"; printf -v "$1" '%s' "$p"; return 0; fi
  done
  echo "cluster.sh: no free port found" >&2
  return 1
}

pid_alive() { [[ -n "$1" ]] && kill -0 "$1" 2>/dev/null; }
pid_of() { [[ -s "$dir/$1.pid" ]] && cat "$dir/$1.pid"; }

# Stop daemons by the pids we recorded: TERM to all of them, wait up to 10 s, then KILL.
stop_pids() {
  local name pid _ alive
  local -a pids=()
  for name in "$@"; do
    pid=$(pid_of "$name") && pid_alive "$pid" && kill -TERM "$pid" 2>/dev/null && pids+=("$name:$pid")
  done
  for _ in $(seq 1 100); do
    alive=0
    for pid in "${pids[@]}"; do pid_alive "${pid#*:}" && alive=1; done
    [[ $alive -eq 0 ]] && break
    sleep 0.1
  done
  for pid in "${pids[@]}"; do
    if pid_alive "${pid#*:}"; then
      echo "cluster.sh: ${pid%%:*} (${pid#*:}) did not stop, killing it" >&2
      kill -KILL "${pid#*:}" 2>/dev/null
    fi
  done
  for name in "$@"; do rm -f "$dir/$name.pid"; done
}

do_env() {
  # The client commands (sbatch, squeue, scontrol, scancel, sinfo) find this cluster through
  # SLURM_CONF; sbatch passes it on to the jobs (--export=ALL is the default).
  echo "export SLURM_CONF=$conf"
}

do_stop() {
  if [[ -s "$conf" ]] && pid_alive "$(pid_of slurmctld)"; then
    # Jobs still running would outlive slurmd (their slurmstepd is not its child).
    SLURM_CONF=$conf scancel --user="$(id -un)" >/dev/null 2>&1
    local _
    for _ in $(seq 1 50); do
      [[ -z "$(SLURM_CONF=$conf squeue -h -t RUNNING,COMPLETING 2>/dev/null)" ]] && break
      sleep 0.2
    done
  fi
  stop_pids watchdog slurmd slurmctld
  stop_pids munged   # last: the daemons talk through it until they are gone
  rm -f "$sock" "$sock.lock"
}

# ST_SLURM_WATCH_PID=PID: stop the cluster once process PID is gone, e.g. a test killed by
# ctest's timeout (SIGKILL: no trap runs, and the daemons are not its children any more).
start_watchdog() {
  local watch=${ST_SLURM_WATCH_PID:-}
  [[ -n "$watch" ]] || return 0
  # shellcheck disable=SC2016  # expanded by the watchdog's own bash
  setsid bash -c 'while kill -0 "$1" 2>/dev/null; do sleep 1; done
                  rm -f "$3/watchdog.pid"; exec bash "$2" stop "$3"' \
    watchdog "$watch" "$self" "$dir" >"$dir/watchdog.out" 2>&1 </dev/null &
  echo $! >"$dir/watchdog.pid"
}

do_start() {
  local c missing=()
  for c in munged slurmctld slurmd sbatch squeue scontrol sinfo; do
    command -v "$c" >/dev/null 2>&1 || [[ -x "/usr/sbin/$c" ]] || missing+=("$c")
  done
  if [[ ${#missing[@]} -gt 0 ]]; then
    echo "cluster.sh: missing ${missing[*]} (Debian: apt-get install slurmctld slurmd slurm-client munge)" >&2
    return 1
  fi
  export PATH="$PATH:/usr/sbin:/sbin"
  # The socket path must fit in sockaddr_un (108 bytes).
  if [[ ${#sock} -gt 100 ]]; then
    echo "cluster.sh: $dir is too long a path for a UNIX socket; use a shorter folder" >&2
    return 2
  fi
  if pid_alive "$(pid_of slurmctld)" || pid_alive "$(pid_of slurmd)" || pid_alive "$(pid_of munged)"; then
    echo "cluster.sh: a cluster is already running in $dir (stop it first)" >&2
    return 1
  fi
  # munged refuses a key or socket folder others can write to; clients need to reach the socket.
  chmod 755 "$dir"
  mkdir -p "$dir/state" "$dir/spool"
  rm -f "$dir"/*.log "$dir"/*.out "$dir"/jobcomp.txt

  local user node ncpu
  user=$(id -un)
  node=$(hostname -s)
  ncpu=$(nproc 2>/dev/null || echo 1)
  # At least 2 CPUs so that two 1-CPU array tasks run at once even on a 1-core runner
  # (config_overrides below: the node is not drained for having fewer than configured).
  [[ $ncpu -ge 2 ]] || ncpu=2

  # ---- munge: our own key, socket, pid, log and seed files ----
  if [[ ! -s "$dir/munge.key" ]]; then
    if command -v mungekey >/dev/null 2>&1 || [[ -x /usr/sbin/mungekey ]]; then
      mungekey --create --keyfile="$dir/munge.key" 2>/dev/null ||
        dd if=/dev/urandom of="$dir/munge.key" bs=1024 count=1 status=none
    else
      dd if=/dev/urandom of="$dir/munge.key" bs=1024 count=1 status=none
    fi
  fi
  chmod 0400 "$dir/munge.key"
  rm -f "$sock" "$sock.lock"
  # -F: stay in the foreground so that $! is its pid; --force: run although the socket
  # of an earlier, killed munged is left over.
  setsid munged -F --force --socket="$sock" --key-file="$dir/munge.key" \
    --pid-file="$dir/munged.pidfile" --log-file="$dir/munged.log" \
    --seed-file="$dir/munged.seed" >"$dir/munged.out" 2>&1 </dev/null &
  echo $! >"$dir/munged.pid"
  local _
  for _ in $(seq 1 50); do [[ -S "$sock" ]] && break; sleep 0.1; done
  if [[ ! -S "$sock" ]] || ! pid_alive "$(pid_of munged)"; then
    echo "cluster.sh: munged did not start" >&2
    cat "$dir/munged.out" >&2
    log_tails; do_stop; return 1
  fi

  # ---- slurm.conf ----
  local ctld_port slurmd_port
  if ! pick_port ctld_port || ! pick_port slurmd_port; then do_stop; return 1; fi
  cat >"$conf" <<EOF
# Generated by scripts/slurm/cluster.sh: a private single-node cluster in $dir
ClusterName=st-private
# Addresses given explicitly: no DNS lookup of the host name.
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$user
SlurmdUser=$user
# Our own munged: AuthInfo's socket is used by auth/munge (daemons and client commands) and
# by cred/munge (job step credentials).
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sock
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pidfile
SlurmdPidFile=$dir/slurmd.pidfile
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# No cgroups (containers without systemd, non-root users): processes tracked through /proc,
# no binding, no accounting gatherer.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
# sacct needs slurmdbd: finished jobs are kept an hour for scontrol show job, and logged here.
JobCompType=jobcomp/filetxt
JobCompLoc=$dir/jobcomp.txt
MinJobAge=3600
# One CPU per 1-CPU task, so array tasks share the node.
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
# Dependent jobs (the merge after the array) start within a second or two, not a minute;
# a job whose dependency can never be met (a failed array task) is cancelled, not left pending.
SchedulerParameters=sched_interval=2,sched_min_interval=100000,kill_invalid_depend
ReturnToService=2
SlurmdParameters=config_overrides
MailProg=/bin/true
# No MPI for these jobs (the daemons still log that they cannot load PMIx: harmless).
MpiDefault=none
InactiveLimit=0
KillWait=5
SlurmdTimeout=120
NodeName=$node NodeAddr=127.0.0.1 NodeHostname=$node CPUs=$ncpu RealMemory=1000 State=UNKNOWN
PartitionName=debug Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF

  # ---- the daemons, in the foreground (-D) of background jobs, so that we know their pids ----
  setsid slurmctld -D -i -f "$conf" >"$dir/slurmctld.out" 2>&1 </dev/null &
  echo $! >"$dir/slurmctld.pid"
  setsid slurmd -D -f "$conf" -N "$node" >"$dir/slurmd.out" 2>&1 </dev/null &
  echo $! >"$dir/slurmd.pid"

  local timeout=${ST_SLURM_START_TIMEOUT:-20} state="" t0=$SECONDS d
  while (( SECONDS - t0 < timeout )); do
    for d in slurmctld slurmd; do
      if ! pid_alive "$(pid_of "$d")"; then
        echo "cluster.sh: $d exited while starting" >&2
        log_tails; do_stop; return 1
      fi
    done
    state=$(SLURM_CONF=$conf sinfo -h -n "$node" -o %T 2>/dev/null | head -n 1)
    if [[ "$state" == idle ]]; then
      echo "cluster.sh: node $node idle ($ncpu CPUs), SLURM_CONF=$conf"
      start_watchdog
      return 0
    fi
    sleep 0.5
  done
  echo "cluster.sh: node $node not idle after ${timeout} s (state: '${state:-no answer}')" >&2
  log_tails
  do_stop
  return 1
}

case "$cmd" in
  start) do_start; exit $? ;;
  stop) do_stop; exit 0 ;;
  env) do_env ;;
  *) usage ;;
esac
