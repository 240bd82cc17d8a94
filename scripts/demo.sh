#!/usr/bin/env bash
# Installs dependencies, builds (Release) and runs the main job on the embedded default.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target startracker
./build/app/startracker camera --fov-deg 11.4 --size 1024 768
