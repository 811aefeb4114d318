#!/usr/bin/env bash
# Sets up (installs dependencies, builds) and runs every test: unit tests of each module and the
# end-to-end tests of the cavesim command, through CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
ctest --test-dir "${CAVESIM_BUILD_DIR:-build}" --output-on-failure --parallel "$(nproc)" --timeout 900
