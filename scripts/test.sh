#!/usr/bin/env bash
# README command (2): installs what is missing, builds, and runs every test.
#   - double precision (default build): all labels
#   - float build: unit, bridge, integration and demos (the closed-form
#     validation tolerances are set for double)
#   - the installed package: both builds installed side by side into a
#     temporary prefix and used from outside the tree (scripts/consumer_test.sh)
#   - ASan + UBSan build: unit, validation, bridge and demos (scene-file parsing,
#     the runner, exports)
#   - when clang is installed: each fuzz target of tests/fuzz for 2000
#     executions (scripts/fuzz.sh; docs/reliability.md has the campaign)
# Exits non-zero on any build or test failure.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="$(nproc)"

scripts/setup.sh double
ctest --test-dir build/double --output-on-failure -j"$jobs"

scripts/setup.sh float
ctest --test-dir build/float --output-on-failure -j"$jobs" -L 'unit|bridge|integration|demos'
scripts/consumer_test.sh build/double build/float

scripts/setup.sh asan
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build/asan --output-on-failure -j"$jobs" -L 'unit|validation|bridge|demos'

if command -v clang++ >/dev/null; then
  scripts/fuzz.sh 2000
else
  echo "test: clang++ not installed: the fuzz targets were not run (scripts/fuzz.sh)"
fi
