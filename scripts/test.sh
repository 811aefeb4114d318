#!/usr/bin/env bash
# Sets up (installs dependencies, builds) and runs every test: unit tests of each module and the
# end-to-end tests of the cavesim command, through CTest; then the sanitizer build with its unit
# tests, end-to-end runs and bounded fuzzing (scripts/sanitize.sh; CAVESIM_SANITIZE=0 skips it).
set -euo pipefail
cd "$(dirname "$0")/.."
# MPI for the ensemble's 2-rank test (tests/cli/ensemble_mpi.sh); installed before the build
# configures, so the build finds it and `cavesim ensemble` runs under mpirun.
. scripts/install_packages.sh
install_packages test openmpi-bin libopenmpi-dev
BUILD_DIR=${CAVESIM_BUILD_DIR:-build}
if [ -f "$BUILD_DIR/CMakeCache.txt" ] && ! grep -q '^MPI_CXX_COMPILER:FILEPATH=/' "$BUILD_DIR/CMakeCache.txt"; then
  cmake -U 'MPI_*' -S . -B "$BUILD_DIR" >&2  # configured before MPI was installed: look again
fi
bash scripts/setup.sh

# Test-only tools: the readers the export tests load our files back with (tests/formats/readers.sh,
# tests/cli/exports.sh); pytest, networkx and matplotlib for the Python module's tests and
# examples/sweep_p_rate.py; headless Chromium with the DevTools client that opens report.html
# (tests/cli/report_html.sh); clang with its sanitizer and libFuzzer runtimes (scripts/sanitize.sh).
TEST_PACKAGES=(survex therion python3-vtk9 python3-openvdb python3-numpy python3-pytest python3-networkx
  python3-matplotlib chromium python3-websocket python3-pil clang libclang-rt-dev)
install_packages test "${TEST_PACKAGES[@]}"
ctest --test-dir "$BUILD_DIR" --output-on-failure --parallel "$(nproc)" --timeout 900
if [ "${CAVESIM_SANITIZE:-1}" != 0 ]; then
  bash scripts/sanitize.sh
fi
