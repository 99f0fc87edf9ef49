#!/usr/bin/env python3
"""Least-squares fit of placement's error model to measured walks (tools/calibrate_error.sh).

Each row of the tables is one probe set baked at one face size: its measured walk MAE and the parts of
its prediction. Uncapped, predicted = floor * served + slope * texel + fallback * unserved, linear in the
three constants; unserved pixels are few on the shared walks, so the fallback is fitted only when the
rows vary it, else kept. Prints the fit, each row's prediction against its measurement, and the
largest relative miss. Plain Python: a 2x2 or 3x3 normal-equation solve needs no library.
"""
import csv
import sys

FALLBACK = 0.08  # error_model.h's current fallback, kept when the rows cannot fit it


def solve(a, b):
    """Gaussian elimination with partial pivoting on a small dense system."""
    n = len(b)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        for r in range(n):
            if r != c and m[c][c] != 0:
                f = m[r][c] / m[c][c]
                m[r] = [x - f * y for x, y in zip(m[r], m[c])]
    return [m[i][n] / m[i][i] for i in range(n)]


def fit(rows, with_fallback):
    cols = ["served", "texel"] + (["unserved"] if with_fallback else [])
    x = [[r[c] for c in cols] for r in rows]
    y = [r["mae"] - (0.0 if with_fallback else FALLBACK * r["unserved"]) for r in rows]
    ata = [[sum(xi[i] * xi[j] for xi in x) for j in range(len(cols))] for i in range(len(cols))]
    aty = [sum(xi[i] * yi for xi, yi in zip(x, y)) for i in range(len(cols))]
    k = solve(ata, aty)
    return k[0], k[1], (k[2] if with_fallback else FALLBACK)


def main(paths):
    rows = []
    for path in paths:
        with open(path) as f:
            for r in csv.DictReader(f, delimiter="\t"):
                for key in ("res", "probes", "mae", "predicted", "served", "texel", "unserved", "capped"):
                    r[key] = float(r[key])
                rows.append(r)
    if len(rows) < 3:
        sys.exit("fit_error_model.py: need at least 3 rows")
    spread = max(r["unserved"] for r in rows) - min(r["unserved"] for r in rows)
    floor, slope, fallback = fit(rows, with_fallback=spread > 0.02)
    print(f"fit over {len(rows)} rows: floor {floor:.5f}, slope {slope:.4f}, fallback {fallback:.4f}"
          f" ({'fitted' if spread > 0.02 else 'kept: unserved share varies by %.3f only' % spread})")
    print(f"{'scene':10} {'set':11} {'res':>4} {'mae':>8} {'model now':>9} {'fit':>8} {'fit/mae':>7}")
    worst = 0.0
    for r in rows:
        p = floor * r["served"] + slope * r["texel"] + fallback * r["unserved"]
        worst = max(worst, abs(p / r["mae"] - 1.0))
        print(f"{r['scene']:10} {r['set']:11} {int(r['res']):4} {r['mae']:8.4f} {r['predicted']:9.4f} {p:8.4f}"
              f" {p / r['mae']:7.3f}")
    print(f"largest relative miss of the fit: {100 * worst:.1f} %")


if __name__ == "__main__":
    main(sys.argv[1:])
