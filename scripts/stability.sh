#!/usr/bin/env bash
# Regenerates the stability map of issue 6, item 5 (docs/stability.md):
# builds xpbd-compare (Release, double), runs the stability sweep into
# docs/stability.csv, writes one gnuplot script per method and
# docs/stability_grids.md, and renders docs/stability_<method>.png.
#
#   bash scripts/stability.sh               a fresh sweep (removes docs/stability.csv first)
#   RESUME=1 bash scripts/stability.sh      continue an interrupted sweep
#   BUILD_DIR=build/x JOBS=1 bash scripts/stability.sh
#   bash scripts/stability.sh --quick       a 2x2 corner of every sweep
#
# Extra arguments go to `xpbd-compare stability run` (--quick, --shard i/n).
# Sharded: `xpbd-compare stability run --shard i/n --out part_i.csv` on each
# machine, then `xpbd-compare stability merge part_*.csv -o docs/stability.csv`
# (one header, sweep order, a run in two parts kept once if both agree),
# then the report and gnuplot lines below.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${BUILD_DIR:-build/double}"
jobs="${JOBS:-2}"
csv=docs/stability.csv
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DXPBD_DOUBLE=ON >/dev/null
cmake --build "$build" --target xpbd-compare -j"$jobs"
exe="$build/demos/compare/xpbd-compare"
if [[ -z "${RESUME:-}" ]]; then rm -f "$csv"; fi
start=$(date +%s)
"$exe" stability run --out "$csv" "$@"
seconds=$(( $(date +%s) - start ))
gp_dir="$build/stability-gp"
rm -rf "$gp_dir"
"$exe" stability report --csv "$csv" --docs docs --gp-dir "$gp_dir"
for f in "$gp_dir"/*.gp; do gnuplot "$f"; done
echo "wrote $csv, docs/stability_grids.md and docs/stability_*.png (sweep: ${seconds} s)"
