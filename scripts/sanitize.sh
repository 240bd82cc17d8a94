#!/usr/bin/env bash
# Builds the project with AddressSanitizer + UndefinedBehaviorSanitizer (gcc, ST_SANITIZE=ON)
# in build-asan/ and runs the test suite there, or the tests matching a regex.
#
# Usage: scripts/sanitize.sh [REGEX] [-- extra ctest args]
#   REGEX  ctest -R pattern, e.g. 'Catalog|Rawlog' (default: every test)
# Any ASan/UBSan report fails its test (UBSan stops at the first error). The first run
# builds everything once more (its objects differ from build/'s), then runs the suite.
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
# Leak checking stays on (ASan's default): our tests' processes are ours to keep clean. An
# absurd calloc in a library returns NULL as glibc's does (a fuzz reproducer makes cfitsio
# try one; tests/fuzz/regressions/star_list/).
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1:strict_string_checks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# Leaks inside MRPT, libjpeg and cfitsio that are not ours to free (reasons in the file).
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/scripts/lsan.supp:print_suppressions=0}
args=(--test-dir build-asan --output-on-failure -j"$(nproc)")
[ -z "$regex" ] || args+=(-R "$regex")
start=$(date +%s)
rc=0
nice -n 10 ctest "${args[@]}" "$@" || rc=$?
echo "sanitize.sh: ctest took $(( $(date +%s) - start )) s, exit $rc"
exit $rc
