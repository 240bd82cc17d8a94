#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz/ (clang, ASan+UBSan, in build-fuzz/) and runs
# each for a time or a number of executions, then prints one line per target: executions,
# coverage (edges) and features, and findings.
#
# Usage: scripts/fuzz.sh [--seconds N] [--runs N] [--no-build] [TARGET...]
#   --seconds N  fuzz each target for N seconds (default 60 without --runs)
#   --runs N     fuzz each target for N executions (with --seconds: whichever comes first)
#   TARGET       names from tests/fuzz/targets/ (default: all), e.g. rawlog image
# Targets run one after the other, under nice. The corpus grows in build-fuzz/fuzz/corpus/
# (the committed seeds in tests/fuzz/corpus/ are only read); a finding is saved in
# build-fuzz/fuzz/findings/<target>/ and the script exits 1. Keep a finding's input as a
# reproducer in tests/fuzz/regressions/<target>/ with a test in tests/fuzz/.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
BUILD=$ROOT/build-fuzz
seconds=""
runs=""
build=1
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds=${2:?--seconds needs a number}; shift 2 ;;
    --runs) runs=${2:?--runs needs a number}; shift 2 ;;
    --no-build) build=0; shift ;;
    -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
    -*) echo "fuzz.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
[ -n "$seconds$runs" ] || seconds=60
if ! [[ "$seconds$runs" =~ ^[0-9]+$ ]]; then
  echo "fuzz.sh: --seconds and --runs take a whole number" >&2
  exit 2
fi
all=()
for f in tests/fuzz/targets/*.cpp; do
  n=$(basename "$f" .cpp)
  [ "$n" = fuzz_io ] || all+=("$n")
done
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")
for t in "${targets[@]}"; do
  if [ ! -f "tests/fuzz/targets/$t.cpp" ]; then
    echo "fuzz.sh: no fuzz target '$t' (known: ${all[*]})" >&2
    exit 2
  fi
done

CXX_BIN=$(command -v clang++-14 || command -v clang++ || true)
CC_BIN=$(command -v clang-14 || command -v clang || true)
if [ -z "$CXX_BIN" ] || [ -z "$CC_BIN" ]; then
  echo "fuzz.sh: clang not found (scripts/install-deps.sh installs clang and libfuzzer-14-dev)" >&2
  exit 2
fi

if [ "$build" = 1 ]; then
  launcher=()
  if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
  CC=$CC_BIN CXX=$CXX_BIN cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DST_FUZZ=ON \
    -DST_BUILD_TESTS=OFF -DST_BUILD_BENCHMARKS=OFF "${launcher[@]}" >/dev/null
  nice -n 10 cmake --build "$BUILD" -j"$(nproc)" --target "${targets[@]/#/fuzz_}"
fi

# MRPT's and OpenCV's process-lifetime allocations are not ours: leaks are checked by the
# ASan suite (scripts/sanitize.sh) on our own tests instead. An absurd malloc/calloc returns
# NULL as glibc's does (cfitsio then reports its memory error, which we turn into an
# InputError; tests/fuzz/regressions/star_list/); our own `new` still throws, a finding.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
limit=()
[ -z "$seconds" ] || limit+=(-max_total_time="$seconds")
[ -z "$runs" ] || limit+=(-runs="$runs")
status=0
rows=()
for t in "${targets[@]}"; do
  corpus=$BUILD/fuzz/corpus/$t
  findings=$BUILD/fuzz/findings/$t
  log=$BUILD/fuzz/$t.log
  mkdir -p "$corpus" "$findings"
  extra=()
  [ ! -f "tests/fuzz/dict/$t.dict" ] || extra+=(-dict="tests/fuzz/dict/$t.dict")
  # rawlog: MRPT's CImage allocates the image a damaged header declares through OpenCV's
  # malloc (tests/fuzz/upstream_mrpt/): above 256 MB malloc returns NULL, OpenCV throws and the
  # reader reports damage, as on a machine without that memory (driver/allocation_cap.cpp does
  # the same for operator new).
  target_asan=$ASAN_OPTIONS
  [ "$t" != rawlog ] || target_asan="$ASAN_OPTIONS:max_allocation_size_mb=256"
  dirs=("$corpus" "tests/fuzz/corpus/$t")
  [ ! -d "tests/fuzz/regressions/$t" ] || dirs+=("tests/fuzz/regressions/$t")
  ls "$findings" >"$log.before"
  echo "fuzz.sh: $t (${limit[*]}), log $log"
  rc=0
  ASAN_OPTIONS=$target_asan nice -n 10 "$BUILD/tests/fuzz/fuzz_$t" "${limit[@]}" -timeout=20 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$findings/" "${extra[@]}" "${dirs[@]}" >"$log" 2>&1 || rc=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  last=$(grep -E '^#[0-9]+' "$log" | tail -1 || true)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  # New artifacts, by kind (crash, leak, oom, timeout, slow-unit): each one is a finding.
  kinds=$(ls "$findings" | grep -vxF -f "$log.before" | sed 's/-[0-9a-f]*$//' | sort | uniq -c |
          awk '{printf "%s%s %s", sep, $1, $2; sep=", "}' || true)
  rm -f "$log.before"
  if [ "$rc" -ne 0 ] && [ -z "$kinds" ]; then kinds="exit $rc"; fi  # stopped without an artifact
  [ -z "$kinds" ] || { status=1; grep -m3 -E 'ERROR|runtime error|SUMMARY|finding' "$log" || true; }
  rows+=("$(printf '%-18s %12s %8s %9s  %s' "$t" "${execs:-?}" "${cov:-?}" "${ft:-?}" "${kinds:-0}")")
done
printf '\n%-18s %12s %8s %9s  %s\n' target executions cov features findings
printf '%s\n' "${rows[@]}"
exit $status
