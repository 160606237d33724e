#!/usr/bin/env bash
# ThreadSanitizer pass over what runs on several threads: xpbd::Workers, the
# threaded coloured sweeps (StepConfig::workers, SystemSettings::workers) and
# the bridge's threaded contact search (SystemSettings::workers).
# Not part of CI (scripts/test.sh); run it after changing workers.cpp or the
# stream code.
#
#   bash scripts/tsan.sh        (builds build/tsan: 14 CPU minutes, 25 minutes
#                                of wall time at nice 19 beside a CI run)
#
# Exits non-zero if a test fails or ThreadSanitizer reports anything.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh double >/dev/null  # the packages (and a normal build)
cmake -S . -B build/tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DXPBD_DOUBLE=ON \
  -DXPBD_BUILD_BENCHMARKS=OFF -DXPBD_BUILD_DEMOS=OFF \
  -DCMAKE_CXX_FLAGS="-fsanitize=thread" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" >/dev/null
# The test suites of tests/unit/test_workers.cpp, test_distance_stream.cpp,
# test_tether_stream.cpp and tests/integration/test_world_settings.cpp, and
# the threaded contact search of tests/bridge/test_world_culling.cpp, in
# their label's executable.
runs=("xpbd_tests_unit Workers.*:DistanceStream.*:TetherStream.*" "xpbd_tests_integration WorldSettings.*"
      "xpbd_tests_bridge WorldCulling.Threads*")
cmake --build build/tsan -j"$(nproc)" --target xpbd_tests_unit xpbd_tests_integration xpbd_tests_bridge
for r in "${runs[@]}"; do
  read -r exe filter <<<"$r"
  echo "tsan: $exe --gtest_filter=$filter"
  TSAN_OPTIONS="halt_on_error=1 exitcode=66" "build/tsan/tests/$exe" --gtest_filter="$filter"
done
echo "tsan: ok"
