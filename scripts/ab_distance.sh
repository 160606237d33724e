#!/usr/bin/env bash
# Alternates two or more bench_distance binaries (for example one built
# from an earlier commit and one from this tree) N times, and prints per
# binary the minimum and the median ns per projection of the compliant
# coloured sweep (stream_sweep) and of the whole coloured 20 x 1 step
# (step_coloured). The machine is shared and noisy: compare binaries run in
# the same call, never figures from different calls.
#
#   scripts/ab_distance.sh 9 /tmp/before/bench_distance build/double/demos/bench/bench_distance
set -euo pipefail
if [ $# -lt 2 ] || ! [[ "$1" =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: $0 N bench_distance [bench_distance ...]  (N: alternations, a positive integer)" >&2
  exit 2
fi
n=$1
shift
for b in "$@"; do
  [ -x "$b" ] || { echo "$0: '$b' is not an executable bench_distance" >&2; exit 2; }
done
filter='stream_sweep/compliant|step_coloured/compliant/substeps:20/'
for _ in $(seq "$n"); do
  for b in "$@"; do
    # The summary bench_distance prints last: a row per benchmark, its ns
    # per projection second.
    line=$("$b" --benchmark_filter="$filter" 2>/dev/null |
      awk '($1 == "stream_sweep/compliant" || $1 ~ /^step_coloured\/compliant\/substeps:20\//) && $2 ~ /^[0-9.]+$/ {printf "%s ", $2}')
    echo "$b $line"
  done
done | python3 -c '
import statistics as st, sys
runs = {}
for line in sys.stdin:
    f = line.split()
    if len(f) != 3:
        sys.exit("ab_distance.sh: no figures from " + f[0])
    runs.setdefault(f[0], []).append((float(f[1]), float(f[2])))
print("| binary | sweep, min | sweep, median | step 20 x 1, min | step 20 x 1, median |")
print("|---|---|---|---|---|")
for b, v in runs.items():
    s = [x[0] for x in v]
    c = [x[1] for x in v]
    print("| %s | %.2f | %.2f | %.2f | %.2f |" % (b, min(s), st.median(s), min(c), st.median(c)))
'
