#!/usr/bin/env bash
# Builds the Debian package: ./scripts/package.sh [BUILD_DIR]  (default build/)
# -> BUILD_DIR/package/startracker_<version>_<arch>.deb. Configures and builds what is
# missing first (Release). Install it with `sudo apt install ./startracker_*.deb`; look
# inside without installing with `dpkg -c` or `dpkg -x FILE.deb ROOT`.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" >/dev/null
cmake --build "$build" -j"$(nproc)"
(cd "$build" && cpack --config CPackConfig.cmake -B "$PWD/package")
ls -l "$build"/package/startracker_*.deb
dpkg-deb -f "$build"/package/startracker_*.deb Depends
