#!/usr/bin/env bash
# Alternates two or more bench_triangles binaries (for example one built
# from an earlier commit and one from this tree) N times on one cloth size
# (default 64), and prints per binary the range and the median, over the
# runs, of the hierarchy's contact search (ms) and of the search over the
# cloth's own step (each run's own ratio: both timed in that run), and from
# binaries that print it, over the cloth's step element by element
# (StepConfig::levels off, the cloth step before docs/bench-levels.md). The
# machine is shared and noisy: compare binaries run in the same call, never
# figures from different calls.
#
#   scripts/ab_triangles.sh 11 /tmp/before/bench_triangles build/double/demos/bench/bench_triangles
#   SIZE=128 scripts/ab_triangles.sh 5 a/bench_triangles b/bench_triangles
set -euo pipefail
if [ $# -lt 2 ] || ! [[ "$1" =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: $0 N bench_triangles [bench_triangles ...]  (N: alternations, a positive integer; SIZE: cloth size, default 64)" >&2
  exit 2
fi
n=$1
shift
size=${SIZE:-64}
[[ "$size" =~ ^[1-9][0-9]*$ ]] || { echo "$0: SIZE='$size' is not a positive integer" >&2; exit 2; }
for b in "$@"; do
  [ -x "$b" ] || { echo "$0: '$b' is not an executable bench_triangles" >&2; exit 2; }
done
for _ in $(seq "$n"); do
  for b in "$@"; do
    # The table's row of this size: | cloth | triangles | triangle contacts |
    # cloth step | contacts, loop | contacts, hierarchy | ...
    # (and, from binaries that print it, the cloth step element by element)
    row=$("$b" "$size" | awk -F'|' -v s="$size x $size" '$2 ~ s {print $5, $7, ($12 ~ /[0-9]/ ? $12 : "-")}')
    [ -n "$row" ] || { echo "$0: no row for $size x $size from '$b'" >&2; exit 1; }
    echo "$b $row"
  done
done | python3 -c '
import statistics as st, sys
runs = {}
for line in sys.stdin:
    b, cloth, search, element = line.split()
    e = float(search) / float(element) if element != "-" else None
    runs.setdefault(b, []).append((float(search), float(search) / float(cloth), e))
for b, v in runs.items():
    s = [x[0] for x in v]
    r = [x[1] for x in v]
    e = [x[2] for x in v if x[2] is not None]
    more = ("; search / cloth step element by element %.3f-%.3f (median %.3f)" % (min(e), max(e), st.median(e))
            if e else "")
    print("%s: %d runs; search %.3f-%.3f ms (median %.3f); search / cloth step %.3f-%.3f (median %.3f)%s"
          % (b, len(v), min(s), max(s), st.median(s), min(r), max(r), st.median(r), more))
'
