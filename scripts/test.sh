#!/usr/bin/env bash
# Sets up (installs dependencies, builds) and runs every test: unit tests of each module and the
# end-to-end tests of the cavesim command, through CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh

# Test-only tools: the readers the export tests load our files back with (tests/formats/readers.sh).
TEST_PACKAGES=(survex therion python3-vtk9 python3-openvdb python3-numpy)
missing=()
for p in "${TEST_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  echo "test: installing ${missing[*]}" >&2
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi
ctest --test-dir "${CAVESIM_BUILD_DIR:-build}" --output-on-failure --parallel "$(nproc)" --timeout 900
