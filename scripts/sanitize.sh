#!/usr/bin/env bash
# Builds the project with AddressSanitizer + UndefinedBehaviorSanitizer (gcc, ST_SANITIZE=ON)
# in build-asan/ and runs the test suite there, or the tests matching a regex.
#
# Usage: scripts/sanitize.sh [REGEX] [-- extra ctest args]
#   REGEX  ctest -R pattern, e.g. 'Catalog|Rawlog' (default: every test)
# Any ASan/UBSan report fails its test (UBSan stops at the first error). Takes about the
# suite's time times 2-3 after a build of everything (the build's objects differ from
# build/'s, so the first build is a full one).
set -euo pipefail
cd "$(dirname "$0")/.."
regex=""
if [ $# -gt 0 ] && [ "$1" != "--" ]; then regex=$1; shift; fi
[ "${1:-}" != "--" ] || shift
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release -DST_SANITIZE=ON -DST_BUILD_BENCHMARKS=OFF \
  "${launcher[@]}" >/dev/null
nice -n 10 cmake --build build-asan -j"$(nproc)"
# Leaks: MRPT keeps its class registry and OpenCV its buffers for the process's life; the
# suite passes with leak checking on, so it stays on.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0:strict_string_checks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
args=(--test-dir build-asan --output-on-failure -j"$(nproc)")
[ -z "$regex" ] || args+=(-R "$regex")
start=$(date +%s)
rc=0
nice -n 10 ctest "${args[@]}" "$@" || rc=$?
echo "sanitize.sh: ctest took $(( $(date +%s) - start )) s, exit $rc"
exit $rc
