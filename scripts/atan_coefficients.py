#!/usr/bin/env python3
"""Coefficients of the polynomial atan of the dihedral stream kernel
(xpbd/src/lane_atan2.hpp), reproducible with the Python standard library:

    python3 scripts/atan_coefficients.py

atan(t) = t P(t^2) on |t| <= tan(pi/8) (the reduced range of lane_atan2),
with P of degree 11 in double and 5 in float: P interpolates
atan(sqrt(s))/sqrt(s) at the Chebyshev nodes of [0, tan(pi/8)^2], computed
in 60-digit decimal arithmetic, then rounded to the precision's nearest
values. Prints the coefficients (lowest degree first) and the largest
relative error of t P(t^2) against atan(t), the polynomial evaluated by
Horner's rule in the target precision, over 200,001 points of the range.
"""
import math
import struct
from decimal import Decimal as D, getcontext

getcontext().prec = 60


def atan_series(t):
    # atan(t) = sum (-1)^k t^(2k+1)/(2k+1), |t| <= 0.42: 60 digits in ~80 terms.
    t = D(t)
    term, s, k, t2 = t, D(0), 0, t * t
    while True:
        add = term / (2 * k + 1)
        if k % 2:
            add = -add
        if abs(add) < D(10) ** -58:
            break
        s += add
        term *= t2
        k += 1
    return s


def f(s):  # atan(sqrt(s))/sqrt(s), s > 0
    r = D(s).sqrt()
    return atan_series(r) / r


def solve(a, b):
    n = len(b)
    m = [row[:] + [bb] for row, bb in zip(a, b)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        for r in range(c + 1, n):
            q = m[r][c] / m[c][c]
            for k in range(c, n + 1):
                m[r][k] -= q * m[c][k]
    x = [D(0)] * n
    for r in reversed(range(n)):
        x[r] = (m[r][n] - sum(m[r][k] * x[k] for k in range(r + 1, n))) / m[r][r]
    return x


def to_float32(v):
    return struct.unpack("f", struct.pack("f", float(v)))[0]


def fit(degree, rounding):
    t_max = math.tan(math.pi / 8)
    a = D(t_max) * D(t_max)
    n = degree + 1
    nodes = [a / 2 * (1 - D(math.cos(math.pi * (2 * i + 1) / (2 * n)))) for i in range(n)]
    coeffs = solve([[s ** k for k in range(n)] for s in nodes], [f(s) for s in nodes])
    c = [rounding(float(x)) for x in coeffs]
    worst = 0.0
    for i in range(200001):
        t = rounding(t_max * i / 200000)
        if t == 0:
            continue
        s = rounding(t * t)
        p = c[-1]
        for k in reversed(range(n - 1)):
            p = rounding(rounding(p * s) + c[k])
        approx = rounding(t * p)
        exact = atan_series(t)
        worst = max(worst, abs((D(approx) - exact) / exact))
    return c, worst


for name, degree, rounding in (("double", 11, float), ("float", 5, to_float32)):
    c, worst = fit(degree, rounding)
    print(f"{name}: degree {degree}, largest relative error {float(worst):.3e}")
    for v in c:
        print(f"  {v!r}")
