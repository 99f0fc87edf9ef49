#!/usr/bin/env python3
"""Least-squares fit of placement's error model to measured walks (tools/calibrate_error.sh).

Each row of the tables is one probe set baked at one face size: its measured walk MAE and the parts of
its prediction (placement/include/cubeao/placement/error_model.h). Uncapped,
    predicted = occluded * occ + slope * texel_near + screen * unserved_occ,
linear in the constants; unserved pixels are few on the shared walks, so `screen` is kept (GTAO's walk
MAE over the mean occlusion, given with --screen) and occluded and slope minimise the relative squared
miss (a walk with half the error counts as much). Prints the fit, each row's prediction against its
measurement, and the largest relative miss. Plain Python: a 2x2 normal-equation solve needs no library.
"""
import csv
import sys



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


def fit(rows, screen):
    cols = ["occ", "texel_near"]
    x = [[r[c] / r["mae"] for c in cols] for r in rows]
    y = [1.0 - screen * r["unserved_occ"] / r["mae"] for r in rows]
    ata = [[sum(xi[i] * xi[j] for xi in x) for j in range(2)] for i in range(2)]
    aty = [sum(xi[i] * yi for xi, yi in zip(x, y)) for i in range(2)]
    return solve(ata, aty)


def main(args):
    screen = 0.35
    if args[:1] == ["--screen"]:
        screen, args = float(args[1]), args[2:]
    rows = []
    for path in args:
        with open(path) as f:
            for r in csv.DictReader(f, delimiter="\t"):
                for key in ("res", "probes", "mae", "predicted", "served", "occ", "texel", "texel_near",
                            "unserved", "unserved_occ", "capped"):
                    r[key] = float(r[key])
                r["one"] = r["served"] + r["unserved"]
                rows.append(r)
    if len(rows) < 3:
        sys.exit("fit_error_model.py: need at least 3 rows")
    occluded, slope = fit(rows, screen)
    print(f"fit over {len(rows)} rows: occluded {occluded:.4f}, slope {slope:.4f} (screen {screen:.3f} kept)")
    print(f"{'scene':10} {'set':11} {'res':>4} {'mae':>8} {'model now':>9} {'fit':>8} {'fit/mae':>7}")
    worst = rms = 0.0
    for r in rows:
        p = occluded * r["occ"] + slope * r["texel_near"] + screen * r["unserved_occ"]
        worst, rms = max(worst, abs(p / r["mae"] - 1.0)), rms + (p / r["mae"] - 1.0) ** 2 / len(rows)
        print(f"{r['scene']:10} {r['set']:11} {int(r['res']):4} {r['mae']:8.4f} {r['predicted']:9.4f} {p:8.4f}"
              f" {p / r['mae']:7.3f}")
    print(f"relative miss of the fit: rms {100 * rms ** 0.5:.1f} %, largest {100 * worst:.1f} %")


if __name__ == "__main__":
    main(sys.argv[1:])
