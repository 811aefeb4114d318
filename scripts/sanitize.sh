#!/usr/bin/env bash
# The sanitizer part of the test command (called by scripts/test.sh): an AddressSanitizer +
# UndefinedBehaviorSanitizer build (clang) of the unit tests and the cavesim command in a build
# directory of its own, the unit tests and a few end-to-end runs under it, then each libFuzzer
# target run for a bounded time from its committed seed corpus (fuzz/corpus/<target>; the scenario
# target also from the shipped scenarios/*.toml).
#   CAVESIM_ASAN_BUILD_DIR  build directory (default build-asan)
#   CAVESIM_FUZZ_SECONDS    seconds per fuzz target (default 60; 0 skips fuzzing)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${CAVESIM_ASAN_BUILD_DIR:-build-asan}
FUZZ_SECONDS=${CAVESIM_FUZZ_SECONDS:-60}
SAN="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
# Unit tests of every module and of the public API (libcavesim.so; the Python module is not built
# here: it would need the sanitizer runtime preloaded into Python); the fuzz targets; the command.
MODULES=(core fastmarch flownet sim render mesh morpho formats site speleo app lib)
TARGETS=("${MODULES[@]/#/test_}" cavesim fuzz_scenario fuzz_state_file fuzz_checkpoint)
start=$(date +%s)
cmake -S . -B "$BUILD" -G Ninja -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DCMAKE_CXX_FLAGS="$SAN" \
  -DCMAKE_EXE_LINKER_FLAGS="$SAN" -DCMAKE_SHARED_LINKER_FLAGS="$SAN" -DCAVESIM_BUILD_BENCH=OFF \
  -DCAVESIM_BUILD_PYTHON=OFF -DCAVESIM_BUILD_FUZZ=ON >/dev/null
cmake --build "$BUILD" -j"$(nproc)" --target "${TARGETS[@]}"
built=$(date +%s)
echo "sanitize: build $((built - start)) s" >&2

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/scripts/lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
fail=0
for t in "${MODULES[@]}"; do
  if ! "$BUILD/tests/$t/test_$t" --gtest_brief=1 >"$BUILD/test_$t.log" 2>&1; then
    echo "sanitize: test_$t FAILED (log: $BUILD/test_$t.log)" >&2
    tail -40 "$BUILD/test_$t.log" >&2
    fail=1
  fi
done
tested=$(date +%s)
echo "sanitize: unit tests $((tested - built)) s" >&2

# End-to-end under the sanitizers: runs of the small and the default scenario, a report rebuilt from
# the run's files, the fault tests (size limit, signals, concurrency), the mutated state files, an
# ensemble (members in parallel, resumed) and runs killed and resumed from their checkpoints.
E2E=$BUILD/e2e && rm -rf "$E2E" && mkdir -p "$E2E"
for t in run_small faults state_mutations ensemble checkpoint; do
  if ! bash tests/cli/$t.sh "$PWD/$BUILD/cavesim" "$PWD" "$E2E/$t" >"$E2E/$t.log" 2>&1; then
    echo "sanitize: end-to-end $t FAILED (log: $E2E/$t.log)" >&2
    grep -v '^ok' "$E2E/$t.log" | tail -40 >&2
    fail=1
  fi
done
if ! "$BUILD/cavesim" run --out "$E2E/fig10" -q --force >"$E2E/fig10.log" 2>&1 ||
   ! "$BUILD/cavesim" report "$E2E/fig10" >>"$E2E/fig10.log" 2>&1; then
  echo "sanitize: fig10 run and report FAILED" >&2
  tail -40 "$E2E/fig10.log" >&2
  fail=1
fi
ran=$(date +%s)
echo "sanitize: end-to-end $((ran - tested)) s" >&2

if [ "$FUZZ_SECONDS" -gt 0 ]; then
  for t in scenario state_file checkpoint; do
    corpus=$BUILD/fuzz-corpus-$t && rm -rf "$corpus" && mkdir -p "$corpus"
    if [ "$t" = scenario ]; then cp scenarios/*.toml "$corpus/"; fi
    if ! "$BUILD/fuzz/fuzz_$t" -max_total_time="$FUZZ_SECONDS" -rss_limit_mb=2048 -print_final_stats=1 \
         -artifact_prefix="$BUILD/fuzz-$t-" "$corpus" "fuzz/corpus/$t" >"$BUILD/fuzz_$t.log" 2>&1; then
      echo "sanitize: fuzz_$t found a failure (artifact $BUILD/fuzz-$t-*, log $BUILD/fuzz_$t.log)" >&2
      grep -A30 "ERROR\|runtime error\|deadly signal" "$BUILD/fuzz_$t.log" | head -60 >&2
      fail=1
    fi
    echo "sanitize: fuzz_$t: $(grep -m1 'stat::number_of_executed_units' "$BUILD/fuzz_$t.log" | awk '{print $2}') executions in ${FUZZ_SECONDS} s" >&2
  done
fi
echo "sanitize: total $(($(date +%s) - start)) s, $([ $fail -eq 0 ] && echo passed || echo FAILED)" >&2
exit $fail
