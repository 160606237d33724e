#!/usr/bin/env bash
# The fuzz targets of tests/fuzz (docs/reliability.md):
#   fuzz_scene_file  a scene file through parsing, validation and 1-2 frames
#   fuzz_obj         the OBJ reader
#   fuzz_world       the embedding API driven by a byte stream
#
#   scripts/fuzz.sh [RUNS] [TARGET...]
#
# Builds build/fuzz with clang (libFuzzer, AddressSanitizer, UBSan; the
# tests are not built there) and runs each target (default: all three) for
# RUNS executions (default 2000, the short run of scripts/test.sh; a
# campaign: 1000000) from its seed corpus
# tests/fuzz/corpus/<target> (plus the scene examples and the malformed
# corpus for fuzz_scene_file). New inputs go to <build>/corpus/<target>,
# which later runs continue from. A crash, sanitizer report, leak or timeout
# stops the run with a non-zero status and leaves the input in
# <build>/artifacts/. The mutations follow FUZZ_SEED (default 1, so a
# run from the committed corpus is reproducible; 0 = a random seed).
# FUZZ_BUILD=<dir> uses a tree that is already configured with XPBD_FUZZ=ON
# instead of build/fuzz: scripts/test.sh runs the targets of build/asan
# (scripts/setup.sh asan), whose instrumented libraries its sanitizer tests
# use too. That tree is built with -DNDEBUG (Eigen's assertions off);
# build/fuzz keeps them on.
set -euo pipefail
cd "$(dirname "$0")/.."
runs="${1:-2000}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scene_file obj world)
build="${FUZZ_BUILD:-build/fuzz}"
if [ "$build" = build/fuzz ]; then
  if ! command -v clang++ >/dev/null; then
    echo "fuzz: clang++ not found (Debian: apt-get install clang libclang-rt-14-dev)" >&2
    exit 2
  fi
  cmake -S . -B build/fuzz -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" -DXPBD_FUZZ=ON \
    -DXPBD_BUILD_TESTS=OFF -DXPBD_BUILD_BENCHMARKS=OFF >/dev/null
elif ! grep -q '^XPBD_FUZZ:BOOL=ON$' "$build/CMakeCache.txt" 2>/dev/null; then
  echo "fuzz: FUZZ_BUILD=$build is not a build tree configured with XPBD_FUZZ=ON" >&2
  exit 2
fi
cmake --build "$build" -j"$(nproc)" --target "${targets[@]/#/fuzz_}"
mkdir -p "$build/artifacts"
for t in "${targets[@]}"; do
  corpus="$build/corpus/$t"
  mkdir -p "$corpus"
  cp tests/fuzz/corpus/"$t"/* "$corpus"/
  if [ "$t" = scene_file ]; then
    cp docs/scene-example.json "$corpus"/
    for f in tests/demos/malformed/*.json; do cp "$f" "$corpus/malformed-$(basename "$f")"; done
  fi
  echo "fuzz_$t: $runs runs"
  log="$build/fuzz_$t.log"
  if ! ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    "$build/tests/fuzz/fuzz_$t" -runs="$runs" -timeout=60 -rss_limit_mb=2048 -max_len=65536 \
    -print_final_stats=1 -seed="${FUZZ_SEED:-1}" -artifact_prefix="$build/artifacts/$t-" "$corpus" \
    >"$log" 2>&1; then
    tail -n 60 "$log" >&2
    echo "fuzz_$t: failed (log $log); the input is in $build/artifacts/" >&2
    exit 1
  fi
  grep -E '^stat::(number_of_executed_units|average_exec_per_sec|peak_rss_mb)' "$log"
done
