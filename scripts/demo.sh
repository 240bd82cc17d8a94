#!/usr/bin/env bash
# Installs dependencies, builds (Release) and runs the main job: the star tracker + attitude
# filter replayed over the committed slewing sample rawlog (summary on stdout, trajectory CSV,
# output rawlog with STAR_TRACKER observations, PNG plots in out/replay/).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target startracker
mkdir -p out
# -f: the demo's own outputs of an earlier run are replaced (without it they are refused).
./build/app/startracker replay rawlogs/slew_2dps.rawlog --config rawlogs/tracker.ini --plots out/replay --csv out/replay.csv \
  -o out/replay.rawlog -f
