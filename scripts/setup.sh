#!/usr/bin/env bash
# Installs every Debian package the build, the tests and the benchmarks need (skipped when all are
# present), then configures and builds the Release tree in build/ (CURVEDSLICER_BUILD_DIR
# overrides the folder). Idempotent; works as root or through sudo. For Debian 12.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libnanoflann-dev libcgal-dev libboost-dev
  libfcl-dev  # robot/collision: torch and positioner against part and deposit (FCL)
  python3-numpy python3-scikit-fmm
  python3-dev pybind11-dev
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev
  libocct-data-exchange-dev
  freecad-python3 xvfb xauth
  clang libomp-dev  # tests/fuzz: libFuzzer (libclang-common-14-dev, pulled by clang-14), OpenMP
  ccache  # a second build compiles only what changed (scripts/compiler_launcher.sh)
  rsync  # scripts/freecad11_leg.sh copies the tree into the FreeCAD 1.1 chroot
)

missing=()
for pkg in "${packages[@]}"; do
  status="$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)"
  if [[ "$status" != "install ok installed" ]]; then
    missing+=("$pkg")
  fi
done

if ((${#missing[@]} > 0)); then
  if [[ "$(id -u)" -eq 0 ]]; then
    sudo=()
  elif command -v sudo >/dev/null 2>&1; then
    sudo=(sudo)
  else
    echo "setup.sh: missing packages (${missing[*]}) and not root; install them or run as root" >&2
    exit 1
  fi
  echo "setup.sh: installing ${missing[*]}"
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
    "${missing[@]}"
else
  echo "setup.sh: all ${#packages[@]} packages present"
fi

build="${CURVEDSLICER_BUILD_DIR:-$repo/build}"
jobs="$(nproc 2>/dev/null || echo 2)"
source "$repo/scripts/compiler_launcher.sh"
cmake -S "$repo" -B "$build" -G Ninja "${launcher[@]}" -DCMAKE_BUILD_TYPE=Release
build_start=$(date +%s)
cmake --build "$build" -j "$jobs"
echo "setup.sh: Release build ready in $build in $(($(date +%s) - build_start)) s (command line:" \
  "$build/cpp/curvedslicer)"
