#!/usr/bin/env bash
# Installs every build/run/test dependency from Debian 12 packages. Idempotent.
# MRPT component packages only: the libmrpt-dev metapackage drags in ROS1, Qt and VTK.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
PKGS=(
  build-essential cmake pkg-config git
  libmrpt-obs-dev libmrpt-hwdrivers-dev libmrpt-bayes-dev libmrpt-gui-dev
  mrpt-apps
  libopencv-dev libeigen3-dev
  libcli11-dev nlohmann-json3-dev libgtest-dev libgmock-dev libbenchmark-dev
  libcfitsio-dev zlib1g-dev
  libjpeg-dev   # jpeglib.h: libjpeg's fatal errors as exceptions (sensors/mrpt/jpeg_errors.hpp)
  libpng-dev libtiff-dev   # imageio/: sky images decoded without OpenCV's imgcodecs (start-up)
  gnuplot-nox python3
  pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-dev
  xvfb xauth
  clang libfuzzer-14-dev   # scripts/fuzz.sh (libFuzzer, ASan+UBSan)
  # The outside oracle for plate solving (scripts/compare_astrometry.py, ctest
  # astrometry_net_agreement): solve-field, its Tycho-2 index (scales 10-19) and astropy.
  astrometry.net astrometry-data-tycho2-10-19 python3-astropy
  # Running at scale (README): a real single-node Slurm cluster in ctest (scripts/slurm/,
  # tests/slurm/) and Dask's LocalCluster under the Python module (python/startracker/scale.py).
  slurmctld slurmd slurm-client munge python3-dask python3-distributed
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PKGS[@]} packages already installed"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update
$SUDO apt-get install -y --no-install-recommends "${missing[@]}"
