#!/usr/bin/env bash
# ThreadSanitizer pass over what runs on several threads: xpbd::Workers and
# the threaded coloured sweep (StepConfig::workers, SystemSettings::workers).
# Not part of CI (scripts/test.sh); run it after changing workers.cpp or the
# stream code.
#
#   bash scripts/tsan.sh        (builds build/tsan; about 5 minutes on 2 cores)
#
# Exits non-zero if a test fails or ThreadSanitizer reports anything.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh double >/dev/null  # the packages (and a normal build)
cmake -S . -B build/tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DXPBD_DOUBLE=ON \
  -DXPBD_BUILD_BENCHMARKS=OFF -DXPBD_BUILD_DEMOS=OFF \
  -DCMAKE_CXX_FLAGS="-fsanitize=thread" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" >/dev/null
tests=(test_workers test_distance_stream test_world_settings)
cmake --build build/tsan -j"$(nproc)" --target "${tests[@]}"
for t in "${tests[@]}"; do
  echo "tsan: $t"
  TSAN_OPTIONS="halt_on_error=1 exitcode=66" "build/tsan/tests/$t"
done
echo "tsan: ok"
