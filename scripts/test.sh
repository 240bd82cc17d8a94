#!/usr/bin/env bash
# Installs dependencies, builds (Release) and runs the tests with ctest.
# Usage: ./scripts/test.sh [--quick] [extra ctest args]
#   (no flag)  every test: what CI runs (.ci/run)
#   --quick    the `quick` tier (unit and property suites, ctest -L quick): the edit loop
set -euo pipefail
cd "$(dirname "$0")/.."
tier=()
if [ "${1:-}" = "--quick" ]; then
  tier=(-L quick)
  shift
fi
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
ctest --test-dir build --output-on-failure -j"$(nproc)" "${tier[@]}" "$@"
