#!/usr/bin/env bash
# README command (2): installs what is missing, builds, and runs every test.
#   - double precision (default build, GCC): all labels
#   - float build (GCC): integration (the closed-form validation tolerances
#     are set for double; the other labels run in float below)
#   - the installed package: both builds installed side by side into a
#     temporary prefix and used from outside the tree (scripts/consumer_test.sh)
#   - ASan + UBSan build (clang, float): unit, bridge and demos (scene-file
#     parsing, the runner, exports)
#   - each fuzz target of tests/fuzz for 2000 executions, built in the same
#     tree (scripts/fuzz.sh; docs/reliability.md has the campaign)
# Each stage prints its wall time when it ends ("test: <stage> passed in N s").
# Exits non-zero on any build or test failure.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="$(nproc)"
stage_start=$SECONDS
passed() {
  echo "test: $1 passed in $((SECONDS - stage_start)) s (total $SECONDS s)"
  stage_start=$SECONDS
}

scripts/setup.sh double
ctest --test-dir build/double --output-on-failure -j"$jobs"
passed "double build and tests"

scripts/setup.sh float
ctest --test-dir build/float --output-on-failure -j"$jobs" -L integration
passed "float build and tests"
scripts/consumer_test.sh build/double build/float
passed "installed package"

scripts/setup.sh asan
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build/asan --output-on-failure -j"$jobs" -L 'unit|bridge|demos'
passed "ASan/UBSan build and tests"

FUZZ_BUILD=build/asan scripts/fuzz.sh 2000
passed "fuzz targets and runs"
