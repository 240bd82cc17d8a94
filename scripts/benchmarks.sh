#!/usr/bin/env bash
# Builds and runs every Google Benchmark program (tests/bench/bench_*.cpp) pinned to one core
# and regenerates BENCHMARKS.md from their JSON output, with the machine they ran on.
# Usage: ./scripts/benchmarks.sh [build-dir]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j"$(nproc)"
OUT="$BUILD/bench-json"
# The last core: on small VMs core 0 also serves the system's interrupts.
CORE=$(( $(nproc) - 1 ))
export ST_BENCH_CORE=$CORE
rm -rf "$OUT" && mkdir -p "$OUT"
for exe in "$BUILD"/tests/bench_*; do
  [ -x "$exe" ] || continue
  name=$(basename "$exe")
  echo "== $name" >&2
  # One core (taskset) so that numbers compare with the issues' "on one core" targets.
  taskset -c "$CORE" "$exe" --benchmark_out="$OUT/$name.json" --benchmark_out_format=json \
    --benchmark_repetitions=3 --benchmark_report_aggregates_only=true >&2
done
python3 scripts/benchmarks_to_md.py "$OUT" > BENCHMARKS.md
# Whole processes (start-up as users feel it): its own section of BENCHMARKS.md.
python3 scripts/startup.py --exe "$BUILD/app/startracker" >/dev/null
echo "wrote BENCHMARKS.md" >&2
