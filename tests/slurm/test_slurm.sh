#!/usr/bin/env bash
# ctest slurm_workflows (issue 37): a REAL single-node Slurm cluster on this machine
# (scripts/slurm/cluster.sh: munged, slurmctld and slurmd in a temporary folder) runs both
# sharded workflows through sbatch with the templates and scripts/slurm/submit.sh:
#  (a) Monte Carlo: lis-robustness in 4 array tasks (--shard i/4) + `montecarlo merge`
#      (afterok): every merged table, the .md report and the run file are bit-identical to
#      one single-process run of the same command;
#  (b) batch plate solve: the eight real frames of tests/data/tetra3 from a list in 3 array
#      tasks (`solve --files-from LIST --shard i/3 --resume -o part`) + `solve merge`: the
#      merged JSON Lines equal a serial `solve --files-from LIST -o` except for "timing_ms";
#      each part holds exactly its frames k % 3 == i.
# Every job must end COMPLETED with exit code 0:0 (scontrol show job: there is no slurmdbd
# for sacct). The cluster is stopped on every exit (trap; a watchdog stops it if this script
# is killed). Exit 77 (ctest SKIP_RETURN_CODE) when Slurm is missing or cannot start here,
# unless ST_SLURM_REQUIRED=1 (then that is a failure).
#
# usage: tests/slurm/test_slurm.sh STARTRACKER   (from the repository root, as ctest does)
# Environment: ST_SLURM_KEEP=1 keeps the temporary folder (it is kept anyway on failure).
set -uo pipefail

[[ $# -eq 1 ]] || { echo "usage: $0 STARTRACKER" >&2; exit 2; }
bin=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
repo=$(cd "$(dirname "$0")/../.." && pwd)
slurm="$repo/scripts/slurm"
cd "$repo" || exit 1
[[ -x "$bin" ]] || { echo "FAIL: $bin is not a program" >&2; exit 1; }
export PATH="$PATH:/usr/sbin:/sbin"

skip() {
  if [[ "${ST_SLURM_REQUIRED:-0}" == 1 ]]; then echo "FAIL (ST_SLURM_REQUIRED=1): $*" >&2; exit 1; fi
  echo "SKIP: $*" >&2
  exit 77
}
for c in munged slurmctld slurmd sbatch squeue scontrol sinfo scancel; do
  command -v "$c" >/dev/null 2>&1 ||
    skip "no $c here (Debian: apt-get install slurmctld slurmd slurm-client munge, as scripts/install-deps.sh does)"
done

t_start=$SECONDS
# A short path: the munge socket's path must fit in 108 bytes.
tmp=$(mktemp -d "${TMPDIR:-/tmp}/st-slurm.XXXXXX") || exit 1
cluster="$tmp/cluster"
failed=0
fail() { echo "FAIL: $*" >&2; failed=1; }
cleanup() {
  bash "$slurm/cluster.sh" stop "$cluster"
  if [[ $failed -ne 0 || "${ST_SLURM_KEEP:-0}" == 1 ]]; then
    echo "kept $tmp (cluster logs in $cluster, job logs in $tmp/logs)" >&2
  else
    rm -rf "$tmp"
  fi
}
trap cleanup EXIT
trap 'failed=1; exit 1' INT TERM

if ! ST_SLURM_WATCH_PID=$$ bash "$slurm/cluster.sh" start "$cluster"; then
  [[ "${ST_SLURM_REQUIRED:-0}" == 1 ]] && failed=1   # keep the folder of a failure
  skip "the Slurm daemons did not come up here (logs above)"
fi
eval "$(bash "$slurm/cluster.sh" env "$cluster")"
echo "cluster up after $((SECONDS - t_start)) s"
export ST_BIN="$bin"

# ---- submit both workflows (the jobs run in this folder, the repository root) ----
mkdir -p "$tmp/mc" "$tmp/solve"
# (a) 250 trials over 4 shards: 63/63/62/62, so unequal shards are merged too.
mc=(lis-robustness --runs 250 --seed 1 --algorithms pyramid --no-plots -q)
ids_mc=$(bash "$slurm/submit.sh" montecarlo -n 4 --logs "$tmp/logs" \
  --merge-opt --no-plots --merge-opt -q "$tmp/mc/shards" "$tmp/mc/merged" "${mc[@]}") ||
  { failed=1; echo "FAIL: sbatch refused the Monte Carlo jobs" >&2; exit 1; }

# (b) The eight frames, relative to the working directory, with a comment and a blank line.
if ! "$bin" solve --help 2>/dev/null | grep -q -- --files-from; then
  failed=1; echo "FAIL: $bin solve has no --files-from (batch solve from a list)" >&2; exit 1
fi
{
  echo "# the eight real frames of tetra3 (issue 37 test)"
  echo
  ls tests/data/tetra3/*.tiff
} >"$tmp/frames.txt"
# --no-cache: every task builds the same in-memory database (its "database" key is the same).
solve_opts=(--fov-deg 11.4 --no-cache -q)
ids_solve=$(bash "$slurm/submit.sh" solve -n 3 --logs "$tmp/logs" \
  "$tmp/frames.txt" "$tmp/solve/parts" "$tmp/solve/merged.jsonl" "${solve_opts[@]}") ||
  { failed=1; echo "FAIL: sbatch refused the solve jobs" >&2; exit 1; }
echo "submitted: Monte Carlo array/merge $ids_mc, solve array/merge $ids_solve"

# ---- the single-process references, while the jobs run ----
"$bin" montecarlo "${mc[@]}" --out "$tmp/mc/serial" >/dev/null ||
  fail "the single-process Monte Carlo run failed"
"$bin" solve --files-from "$tmp/frames.txt" -o "$tmp/solve/serial.jsonl" "${solve_opts[@]}" \
  >"$tmp/solve/serial.txt" ||
  fail "the serial batch solve failed"

# ---- wait for the four jobs (bounded) ----
all_ids="$ids_mc $ids_solve"
deadline=$((SECONDS + ${ST_SLURM_WAIT:-90}))
while [[ -n "$(squeue -h -j "${all_ids// /,}" 2>/dev/null)" ]]; do
  if (( SECONDS > deadline )); then
    fail "jobs still queued or running after ${ST_SLURM_WAIT:-90} s:"
    squeue -j "${all_ids// /,}" >&2
    break
  fi
  sleep 0.5
done
echo "jobs done after $((SECONDS - t_start)) s"

# Every record of job $1 (an array: one per task) must be COMPLETED with exit code 0:0, and
# there must be $2 of them.
check_job() {
  local id=$1 want=$2 what=$3 lines
  lines=$(scontrol -o show job "$id" | awk '{
      t = "-"; s = "?"; e = "?"
      for (i = 1; i <= NF; i++) {
        k = $i; sub(/=.*/, "", k); v = $i; sub(/^[^=]*=/, "", v)
        if (k == "ArrayTaskId") t = v; else if (k == "JobState") s = v; else if (k == "ExitCode") e = v
      }
      print t, s, e }')
  while read -r l; do echo "  $what job $id task $l"; done <<<"$lines"
  local n ok
  n=$(echo "$lines" | grep -c .)
  ok=$(echo "$lines" | grep -c ' COMPLETED 0:0$')
  [[ $n -eq $want && $ok -eq $want ]] ||
    fail "$what job $id: $ok of $n records COMPLETED with exit 0:0, $want expected (logs: $tmp/logs)"
}
read -r mc_array mc_merge <<<"$ids_mc"
read -r solve_array solve_merge <<<"$ids_solve"
check_job "$mc_array" 4 "Monte Carlo array"
check_job "$mc_merge" 1 "Monte Carlo merge"
check_job "$solve_array" 3 "solve array"
check_job "$solve_merge" 1 "solve merge"

# ---- (a) the merged Monte Carlo tables against the single run ----
for i in 0 1 2 3; do
  ls "$tmp/mc/shards"/*_run.shard-$i-of-4.txt >/dev/null 2>&1 ||
    fail "Monte Carlo: shard $i/4 wrote no run file into $tmp/mc/shards"
done
tables=("$tmp"/mc/serial/*.csv "$tmp"/mc/serial/*.md)
[[ ${#tables[@]} -ge 3 && -e "${tables[0]}" && -e "${tables[-1]}" ]] ||
  fail "Monte Carlo: the single run wrote no tables or report"
if diff -r "$tmp/mc/serial" "$tmp/mc/merged" >"$tmp/mc.diff" 2>&1; then
  echo "Monte Carlo: merged = single run (${tables[*]##*/} and the run file)"
else
  fail "Monte Carlo: the merged tables differ from the single run:"
  head -n 20 "$tmp/mc.diff" >&2
fi

# ---- (b) the merged JSON Lines against the serial batch, "timing_ms" left out ----
if /usr/bin/python3 - "$tmp/frames.txt" "$tmp/solve/serial.jsonl" "$tmp/solve/merged.jsonl" \
    "$tmp/solve/parts" <<'EOF'
import json, os, sys

list_file, serial_file, merged_file, parts_dir = sys.argv[1:5]
frames = [l.strip() for l in open(list_file) if l.strip() and not l.lstrip().startswith("#")]

def drop_timing(v):
    if isinstance(v, dict):
        return {k: drop_timing(x) for k, x in v.items() if k != "timing_ms"}
    if isinstance(v, list):
        return [drop_timing(x) for x in v]
    return v

def load(path):
    if not os.path.exists(path):
        print("FAIL: solve: no " + path, file=sys.stderr)
        sys.exit(1)
    with open(path) as f:
        return [drop_timing(json.loads(l)) for l in f if l.strip()]

ok = True
def bad(msg):
    global ok
    ok = False
    print("FAIL: solve: " + msg, file=sys.stderr)

serial, merged = load(serial_file), load(merged_file)
if [r.get("image") for r in serial] != frames:
    bad("the serial run's frames are not the list's")
if [r.get("image") for r in merged] != frames:
    bad("the merged frames %s are not the list's %s" % ([r.get("image") for r in merged], frames))
if not all(r.get("solved") is True for r in serial):
    bad("not every real frame solved in the serial run")
for i, (a, b) in enumerate(zip(serial, merged)):
    if a != b:
        keys = sorted(k for k in set(a) | set(b) if a.get(k) != b.get(k))
        bad("frame %d (%s) differs from the serial run in %s" % (i, a.get("image"), keys))
# Each part holds exactly its shard's frames: k % 3 == i.
n = 3
for i in range(n):
    p = os.path.join(parts_dir, "part-%d-of-%d.jsonl" % (i, n))
    got = sorted(r.get("image") for r in load(p))
    if got != sorted(frames[i::n]):
        bad("%s holds %s, expected %s" % (p, got, frames[i::n]))
if ok:
    print("solve: merged = serial apart from timing_ms (%d frames, %d parts)" % (len(merged), n))
sys.exit(0 if ok else 1)
EOF
then :; else fail "solve: the merged JSON Lines differ from the serial batch"; fi

echo "slurm_workflows: $((SECONDS - t_start)) s"
if [[ $failed -ne 0 ]]; then
  echo "slurm_workflows FAILED" >&2
  exit 1
fi
echo "slurm_workflows passed"
