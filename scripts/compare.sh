#!/usr/bin/env bash
# Regenerates the speed-vs-accuracy comparison of issue 6 (docs/results.md):
# builds xpbd-compare (Release, double), runs the sweep into
# docs/results.csv, writes docs/results.md and one gnuplot script per scene,
# and renders them to docs/results_<scene>.png.
#
#   bash scripts/compare.sh                 a fresh sweep (removes docs/results.csv first)
#   RESUME=1 bash scripts/compare.sh        continue an interrupted sweep (skips runs in the CSV)
#   BUILD_DIR=build/x JOBS=1 bash scripts/compare.sh
#   bash scripts/compare.sh --quick         a tiny sweep (3 budgets, 0.5 s; for trying it out)
#
# Extra arguments go to both `xpbd-compare run`s (--shard i/n, --scenes a,b,
# --quick). The double build runs XPBD, PBD, btSoftBody and the references
# (written to $build/compare-ref); then the float build (FLOAT_BUILD_DIR,
# default build/float-compare) runs XPBD against those double references.
# Sharded on several machines: run
#   xpbd-compare run --shard i/n --out shard_i.csv --reference-dir ref
# on each (double, then float with --methods xpbd), then
# `xpbd-compare merge shard_*.csv -o docs/results.csv` and
# `xpbd-compare report` (the last lines of this script).
set -euo pipefail
cd "$(dirname "$0")/.."
build="${BUILD_DIR:-build/double}"
fbuild="${FLOAT_BUILD_DIR:-build/float-compare}"
jobs="${JOBS:-2}"
csv=docs/results.csv
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DXPBD_DOUBLE=ON >/dev/null
cmake --build "$build" --target xpbd-compare -j"$jobs"
cmake -S . -B "$fbuild" -DCMAKE_BUILD_TYPE=Release -DXPBD_DOUBLE=OFF >/dev/null
cmake --build "$fbuild" --target xpbd-compare -j"$jobs"
exe="$build/demos/compare/xpbd-compare"
fexe="$fbuild/demos/compare/xpbd-compare"
refs="$build/compare-ref"
if [[ -z "${RESUME:-}" ]]; then rm -f "$csv"; rm -rf "$refs"; fi
start=$(date +%s)
"$exe" run --out "$csv" --reference-dir "$refs" "$@"
"$fexe" run --out "$csv" --reference-dir "$refs" --methods xpbd "$@"
seconds=$(( $(date +%s) - start ))
gp_dir="$build/compare-gp"
rm -rf "$gp_dir"
"$exe" report --csv "$csv" --docs docs --gp-dir "$gp_dir" --sweep-seconds "$seconds" \
  --command "bash scripts/compare.sh"
for f in "$gp_dir"/*.gp; do gnuplot "$f"; done
echo "wrote docs/results.md, $csv and docs/results_*.png (sweep: ${seconds} s)"
