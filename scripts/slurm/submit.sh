#!/usr/bin/env bash
# Submit a sharded workflow to Slurm: the array of N tasks, then its merge, which starts only
# when every task has ended with exit 0 (--dependency=afterok; cancelled if one fails).
# Prints the two job ids, "ARRAYJOB MERGEJOB", on stdout (issue 37).
#
# usage: submit.sh montecarlo [OPTS] SHARDDIR OUTDIR EXPERIMENT [EXPERIMENT OPTIONS...]
#        submit.sh solve      [OPTS] LIST PARTSDIR OUT.jsonl [SOLVE OPTIONS...]
# OPTS:  -n N              tasks in the array (default 4)
#        --logs DIR        folder of the jobs' stdout/stderr (default slurm-logs, created)
#        --sbatch OPT      an sbatch option for both jobs, e.g. --sbatch --partition=short
#                          --sbatch --time=10:00 (repeatable; overrides the #SBATCH lines)
#        --merge-opt OPT   an option for `startracker montecarlo merge`, e.g. --no-plots
#                          (repeatable; montecarlo only)
# e.g.   submit.sh montecarlo -n 8 shards result lis-robustness --runs 10000 --seed 1 --algorithms pyramid
#        submit.sh solve -n 8 frames.txt parts solved.jsonl --fov-deg 11.4 --database stars.db
# The jobs run in the current folder (relative paths are relative to it) with this shell's
# environment (sbatch --export=ALL, the default): set ST_BIN to the startracker program
# when it is not on PATH. Templates: montecarlo.sbatch, montecarlo-merge.sbatch,
# solve.sbatch, solve-merge.sbatch beside this script.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
usage() { sed -n '2,22p' "$0" >&2; exit 2; }
[[ $# -ge 1 ]] || usage
kind=$1
shift
n=4
logs=slurm-logs
sb=()
merge_opts=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    -n) n=$2; shift 2 ;;
    --logs) logs=$2; shift 2 ;;
    --sbatch) sb+=("$2"); shift 2 ;;
    --merge-opt) merge_opts+=("$2"); shift 2 ;;
    -h|--help) usage ;;
    *) break ;;
  esac
done
[[ "$n" =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: -n needs a positive number" >&2; exit 2; }
mkdir -p "$logs"   # Slurm does not create the folder of --output: the job would fail
logs=$(cd "$logs" && pwd)

# sbatch --parsable prints "JOBID" or "JOBID;CLUSTER".
submit() { local id; id=$(sbatch --parsable "$@"); echo "${id%%;*}"; }

case "$kind" in
  montecarlo)
    [[ $# -ge 3 ]] || usage
    shards=$1; out=$2; shift 2
    array=$(submit "${sb[@]}" --array="0-$((n - 1))" --output="$logs/%x-%A_%a.out" \
      "$here/montecarlo.sbatch" "$shards" "$@")
    merge=$(submit "${sb[@]}" --dependency="afterok:$array" --kill-on-invalid-dep=yes \
      --output="$logs/%x-%j.out" "$here/montecarlo-merge.sbatch" "$shards" "$out" \
      "${merge_opts[@]}")
    ;;
  solve)
    [[ $# -ge 3 ]] || usage
    list=$1; parts=$2; out=$3; shift 3
    array=$(submit "${sb[@]}" --array="0-$((n - 1))" --output="$logs/%x-%A_%a.out" \
      "$here/solve.sbatch" "$list" "$parts" "$@")
    merge=$(submit "${sb[@]}" --dependency="afterok:$array" --kill-on-invalid-dep=yes \
      --output="$logs/%x-%j.out" "$here/solve-merge.sbatch" "$list" "$parts" "$out")
    ;;
  *) usage ;;
esac
echo "submit.sh: $kind: array job $array ($n tasks), merge job $merge after it; logs in $logs" >&2
echo "$array $merge"
