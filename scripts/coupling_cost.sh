#!/usr/bin/env bash
# CPU cost at equal error of the pre-solve coupling against the old one
# (issue 11; the figures are in docs/bullet-bridge.md section 2).
#
#   bash scripts/coupling_cost.sh              old = b032f7f (the last commit with the action hook)
#   OLD=<commit> SCENE=cloth_on_sphere bash scripts/coupling_cost.sh
#
# Builds xpbd-compare (Release, double) of the old commit in a git worktree
# under build/, and of the working tree, then runs XPBD on the scene over the
# sweep's budgets with each, one after the other on the same machine:
#   - old: the action hook after Bullet's solver; as in the old sweep, Bullet
#     stepped at every substep (its one-step-per-frame runs lag);
#   - new: pre-solve coupling, with Bullet stepped as the new sweep steps it
#     for the scene (cloth_on_sphere: at every substep, its box rests on the
#     ground) and, where the scene has a dynamic body, the other way
#     (xpbd_rigid_once: once per frame).
# Each is judged against its own reference (XPBD 4000x1 in the same
# coupling), by the particles' RMS error averaged over the sample times
# (every 0.25 s; both CSV formats carry it in err_series; the old format has
# no body error). The scene must be the same in both commits
# (cloth_on_sphere is). Prints one line per budget: ms/frame and error of
# each, and the time ratios old/new. Takes ~15 minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
old="${OLD:-b032f7f}"
scene="${SCENE:-cloth_on_sphere}"
out=build/coupling-cost
wt="$out/old-src"
mkdir -p "$out"
if [[ ! -d "$wt" ]]; then git worktree add --detach "$wt" "$old" >/dev/null; fi
cmake -S "$wt" -B "$out/old-build" -DCMAKE_BUILD_TYPE=Release -DXPBD_DOUBLE=ON >/dev/null
cmake --build "$out/old-build" --target xpbd-compare -j"$(nproc)" >/dev/null
cmake -S . -B build/double -DCMAKE_BUILD_TYPE=Release -DXPBD_DOUBLE=ON >/dev/null
cmake --build build/double --target xpbd-compare -j"$(nproc)" >/dev/null
rm -f "$out/old.csv" "$out/new.csv"
"$out/old-build/demos/compare/xpbd-compare" run --scenes "$scene" --methods reference,xpbd --out "$out/old.csv"
build/double/demos/compare/xpbd-compare run --scenes "$scene" --methods reference,xpbd,xpbd_rigid_once \
  --out "$out/new.csv"
# The column numbers of method, substeps, iterations, status, wall_ms_median
# and err_series differ between the two CSV formats: find them by name.
summarise() {
  awk -F, -v want="$2" '
    NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
    $col["method"] == want {
      n = split($col["err_series"], s, ";"); sum = 0
      for (k = 1; k <= n; ++k) { split(s[k], f, ":"); sum += f[2] }
      printf "%sx%s %s %s %.6g\n", $col["substeps"], $col["iterations"], $col["status"], $col["wall_ms_median"], sum / n
    }' "$1"
}
echo "budget | old: status ms/frame mean-RMS(m) | new: status ms/frame mean-RMS(m) | time old/new" \
  "| new, Bullet once per frame: status ms/frame mean-RMS(m) | time old/new-once"
join <(summarise "$out/old.csv" xpbd | sort) <(summarise "$out/new.csv" xpbd | sort) |
  join - <(summarise "$out/new.csv" xpbd_rigid_once | sort) |
  awk '{ printf "%s | %s %.4g %.4g | %s %.4g %.4g | %.3g | %s %.4g %.4g | %.3g\n", $1, $2, $3, $4, $5, $6, $7, $3 / $6,
         $8, $9, $10, $3 / $9 }' | sort -t x -k1,1n
echo "references (|B - 2B|, mean RMS over the samples): old $(summarise "$out/old.csv" reference | cut -d' ' -f4) m," \
  "new $(summarise "$out/new.csv" reference | cut -d' ' -f4) m"
