#!/usr/bin/env bash
# Regenerates the seed report's Fig. 5 (docs/fig5.md): builds xpbd-fig5
# (Release, double), runs it (writes docs/fig5.csv and prints the tables of
# docs/fig5.md), then charts docs/fig5.png with gnuplot (docs/fig5.gp).
#
#   scripts/fig5.sh                 build tree build/double
#   BUILD_DIR=build/x scripts/fig5.sh
#   scripts/fig5.sh --sweep         only print XPBD's spread against the compliance
#
# Extra arguments go to xpbd-fig5. Packages: scripts/setup.sh installs them
# (cmake, a C++20 compiler, Eigen, CLI11, gnuplot-nox, ...).
set -euo pipefail
cd "$(dirname "$0")/.."
build="${BUILD_DIR:-build/double}"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DXPBD_DOUBLE=ON >/dev/null
cmake --build "$build" --target xpbd-fig5 -j2
if [[ " $* " == *" --sweep "* ]]; then
  exec "$build/demos/xpbd-fig5" "$@"
fi
"$build/demos/xpbd-fig5" --csv docs/fig5.csv "$@"
gnuplot docs/fig5.gp
echo "wrote docs/fig5.png"
