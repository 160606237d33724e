#!/usr/bin/env bash
# Installs the Debian 12 packages the project needs (only those missing),
# then configures and builds one variant.
#
#   scripts/setup.sh [double|float|asan]     (default: double)
#
# Build trees: build/double, build/float, build/asan. Idempotent; works as
# root, or through sudo otherwise.
set -euo pipefail
cd "$(dirname "$0")/.."

variant="${1:-double}"
packages=(build-essential cmake pkg-config git
          libbullet-dev libeigen3-dev libfcl-dev libgtest-dev libbenchmark-dev
          nlohmann-json3-dev libcli11-dev libtinyobjloader-dev gnuplot-nox)
# The sanitizer build is made with clang, with libFuzzer's runtime
# (libclang-rt-14-dev, only recommended by clang).
[ "$variant" != asan ] || packages+=(clang libclang-rt-14-dev)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "setup: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
    sudo_cmd=(sudo)
  fi
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

case "$variant" in
  double) flags=(-DCMAKE_BUILD_TYPE=Release -DXPBD_DOUBLE=ON) ;;
  # float: the Release build in float, for what the sanitizer build below
  # (also float) does not run: the integration tests, and the installed
  # float package (scripts/consumer_test.sh). No demos, benchmarks or tools.
  float)  flags=(-DCMAKE_BUILD_TYPE=Release -DXPBD_DOUBLE=OFF -DXPBD_BUILD_DEMOS=OFF -DXPBD_BUILD_BENCHMARKS=OFF
                 -DXPBD_BUILD_TOOLS=OFF -DXPBD_TEST_LABELS=integration) ;;
  # asan: clang, float, -O1 with line tables only (-g1: file and line in the
  # reports, a fraction of full debug information's compile time), and the
  # labels scripts/test.sh runs under the sanitizers: unit, bridge and demos
  # (not the integration tests, which take too long instrumented, nor the
  # closed-form validation tests, whose tolerances are set for double). In
  # float, so that the unit, bridge and demo tests run in both precisions
  # without a third build. XPBD_FUZZ=ON builds the fuzz targets in the same
  # tree, so that scripts/test.sh's short fuzz run needs no second build of
  # the libraries (FUZZ_BUILD=build/asan scripts/fuzz.sh), with the cheaper
  # coverage instrumentation (XPBD_FUZZ_COVERAGE, CMakeLists.txt). clang
  # compiled the sanitized libraries in about half GCC's time (scene_file.cpp
  # 22 s vs 39 s, step.cpp 16 s vs 39 s, one compile each).
  asan)   flags=(-DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo
                 "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
                 -DXPBD_DOUBLE=OFF -DXPBD_SANITIZE=ON -DXPBD_FUZZ=ON -DXPBD_FUZZ_COVERAGE=counters
                 -DXPBD_BUILD_BENCHMARKS=OFF -DXPBD_BUILD_TOOLS=OFF
                 "-DXPBD_TEST_LABELS=unit;bridge;demos") ;;
  *) echo "setup: unknown variant '$variant' (double|float|asan)" >&2; exit 2 ;;
esac
cmake -S . -B "build/$variant" "${flags[@]}" >/dev/null
cmake --build "build/$variant" -j"$(nproc)"
