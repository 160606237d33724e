#!/usr/bin/env python3
"""Array order against coloured order, per unit time, on every harness scene.

Reads the comparison sweep's CSV (docs/results.csv, written by
scripts/compare.sh) and prints a Markdown table: for every point of
xpbd_coloured's error-time front, the array-order front's error at the same
wall time (interpolated linearly in log-log between neighbouring front
points; beyond its slowest point, its best error), over the coloured run's
error. Above 1 the coloured order is ahead at that cost. A run counts only
with status ok; the error is err_mean (the judged error, mean over the
samples).

    python3 scripts/order_fronts.py [docs/results.csv]
"""
import collections
import csv
import math
import sys


def front(points):
    """The points no faster point beats in error, fastest first."""
    out, best = [], math.inf
    for t, e, budget in sorted(points):
        if e < best:
            out.append((t, e, budget))
            best = e
    return out


def error_at(f, t):
    if not f or t < f[0][0]:
        return None
    for (t0, e0, _), (t1, e1, _) in zip(f, f[1:]):
        if t0 <= t <= t1:
            w = (math.log(t) - math.log(t0)) / (math.log(t1) - math.log(t0)) if t1 > t0 else 0
            return math.exp(math.log(e0) + w * (math.log(e1) - math.log(e0)))
    return f[-1][1]


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else "docs/results.csv"
    runs = collections.defaultdict(list)
    failed = collections.Counter()
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            if r["method"] not in ("xpbd", "xpbd_coloured"):
                continue
            key = (r["scene"], r["method"])
            if r["status"] != "ok":
                failed[key] += 1
                continue
            runs[key].append((float(r["wall_ms_median"]), float(r["err_mean"]),
                              f'{r["substeps"]}x{r["iterations"]}'))
    print("| scene | failed runs (array, coloured) | array error / coloured error at the coloured front's times |")
    print("|---|---|---|")
    for scene in sorted({k[0] for k in runs}):
        a, c = front(runs[(scene, "xpbd")]), front(runs[(scene, "xpbd_coloured")])
        cells = []
        for t, e, budget in c:
            ea = error_at(a, t)
            if ea is not None:
                cells.append(f"{budget}: {ea / e:.2f}")
        fails = f'{failed[(scene, "xpbd")]}, {failed[(scene, "xpbd_coloured")]}'
        print(f"| {scene} | {fails} | {'; '.join(cells) if cells else 'n/a (no common time)'} |")


if __name__ == "__main__":
    main()
