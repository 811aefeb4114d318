#!/usr/bin/env bash
# Installs cavesim's build dependencies (Debian 12 packages; needs root or sudo), then configures
# and builds into build/. Idempotent: a second run installs nothing and rebuilds only what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(cmake g++ ninja-build ccache pkg-config python3
  libopenvdb-dev libboost-iostreams-dev libopenmesh-dev libboost-graph-dev
  libtbb-dev libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libgtest-dev libbenchmark-dev
  libpng-dev zlib1g-dev libtinygltf-dev libcairo2-dev fonts-dejavu-core libeigen3-dev
  libgdal-dev python3-gdal  # site inputs (GeoTIFF, CRSs); python3-gdal runs scenarios/site/make_site.py
  python3-dev pybind11-dev python3-numpy)  # the Python module (python/), built when these are found

. scripts/install_packages.sh
install_packages setup "${PACKAGES[@]}"

BUILD_DIR=${CAVESIM_BUILD_DIR:-build}
if [ ! -f "$BUILD_DIR/build.ninja" ]; then
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >&2
fi
cmake --build "$BUILD_DIR" --parallel "$(nproc)" >&2

# The interactive 3D view of report.html: Google's <model-viewer> from the npm registry, fetched once
# into the build (never committed) and copied next to each report.html by the run. Licence
# Apache-2.0 (its bundle includes three.js, MIT, and lit, BSD-3-Clause): kept beside it as LICENSE.
# Without it (no network) everything else works; the page then says it has no 3D view.
MODEL_VIEWER_VERSION=4.4.0
VIEWER_DIR="$BUILD_DIR/vendor/model-viewer"
if [ "$(cat "$VIEWER_DIR/VERSION" 2>/dev/null)" != "$MODEL_VIEWER_VERSION" ]; then
  tmp=$(mktemp -d)
  # The tarball named by the registry's metadata, checked against its sha512 integrity (no npm needed).
  if python3 - "$MODEL_VIEWER_VERSION" "$tmp/mv.tgz" <<'PY' && tar -xzf "$tmp/mv.tgz" -C "$tmp"; then
import base64, hashlib, json, sys, urllib.request
version, out = sys.argv[1], sys.argv[2]
meta = json.load(urllib.request.urlopen("https://registry.npmjs.org/@google/model-viewer/" + version, timeout=60))
data = urllib.request.urlopen(meta["dist"]["tarball"], timeout=120).read()
algo, digest = meta["dist"]["integrity"].split("-", 1)
if algo != "sha512" or base64.b64encode(hashlib.sha512(data).digest()).decode() != digest:
    sys.exit("model-viewer tarball: integrity check failed")
open(out, "wb").write(data)
PY
    mkdir -p "$VIEWER_DIR"
    cp "$tmp/package/dist/model-viewer-umd.min.js" "$tmp/package/LICENSE" "$VIEWER_DIR/"
    echo "$MODEL_VIEWER_VERSION" > "$VIEWER_DIR/VERSION"
    echo "setup: model-viewer $MODEL_VIEWER_VERSION (Apache-2.0) in $VIEWER_DIR" >&2
  else
    echo "setup: could not fetch @google/model-viewer from the npm registry; report.html will have no 3D view" >&2
  fi
  rm -rf "$tmp"
fi
