#!/usr/bin/env bash
# The 10-minute image-level gyroless run of issue 16 (too long for ctest): the sample
# scenario rawlogs/gyroless_60s.ini (jitter about a 0.5 deg/s slew, body rates up to ~1 deg/s
# changing all the time, 5 Hz, no gyro) simulated for 600 s, then replayed with the gyroless
# filter (rawlogs/gyroless_tracker.ini). The summary shows frames tracked from frame 2,
# misidentified stars, the attitude NEES and the rate error RMS against the truth.
#
# usage: scripts/gyroless_run.sh [--seconds N] [--out DIR] [--build DIR]
# Long (~6 min of simulation on one core): run it with nice -n 10. Not part of ctest.
set -euo pipefail

repo=$(cd "$(dirname "$0")/.." && pwd)
seconds=600
out="$repo/out/gyroless"
build="$repo/build"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --seconds) seconds=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    -h|--help) sed -n 2,9p "$0"; exit 0 ;;
    *) echo "gyroless_run.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
exe="$build/app/startracker"
[[ -x "$exe" ]] || { echo "gyroless_run.sh: $exe not built" >&2; exit 2; }
[[ "$seconds" =~ ^[0-9]+$ && "$seconds" -gt 0 ]] || {
  echo "gyroless_run.sh: --seconds '$seconds' is not a positive integer" >&2; exit 2; }
mkdir -p "$out"
rawlog="$out/gyroless_${seconds}s.rawlog"
# The sample with its duration_s replaced (--frames can only shorten a run).
sed "s/^duration_s .*/duration_s     = $seconds/" "$repo/rawlogs/gyroless_60s.ini" >"$out/scenario.ini"
"$exe" simulate -q "$out/scenario.ini" --force -o "$rawlog"
"$exe" replay -q "$rawlog" --config "$repo/rawlogs/gyroless_tracker.ini" \
  --csv "$out/gyroless_${seconds}s.csv" -f | tee "$out/summary.txt"
