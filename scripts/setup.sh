#!/usr/bin/env bash
# Installs cavesim's build dependencies (Debian 12 packages; needs root or sudo), then configures
# and builds into build/. Idempotent: a second run installs nothing and rebuilds only what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(cmake g++ ninja-build ccache pkg-config python3
  libopenvdb-dev libboost-iostreams-dev libopenmesh-dev libboost-graph-dev
  libtbb-dev libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libgtest-dev libbenchmark-dev
  libpng-dev zlib1g-dev libtinygltf-dev)

. scripts/install_packages.sh
install_packages setup "${PACKAGES[@]}"

BUILD_DIR=${CAVESIM_BUILD_DIR:-build}
if [ ! -f "$BUILD_DIR/build.ninja" ]; then
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >&2
fi
cmake --build "$BUILD_DIR" --parallel "$(nproc)" >&2
