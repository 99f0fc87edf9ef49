#!/usr/bin/env python3
"""MAE of image directories against a truth directory, split into edge pixels and the rest.
Usage: edge_mae.py TRUTH_DIR DIR... [--frames A:B]
Reads ao_NNNN.exr through `oiiotool --dumpdata` (first channel). An edge pixel is one whose value in
the truth differs from a 4-neighbour's by more than 0.1: the mask comes from the truth alone, so no
compared image picks its own pixels. Used for `reference --aa` against Blender (docs/BENCHMARKS.md)."""
import os
import re
import subprocess
import sys


def read(path):
    out = subprocess.run(["oiiotool", "--dumpdata", path], capture_output=True, text=True, check=True).stdout
    px = {(int(m[1]), int(m[2])): float(m[3]) for m in re.finditer(r"Pixel \((\d+), (\d+)\):\s+([-\d.e+]+)", out)}
    w, h = max(k[0] for k in px) + 1, max(k[1] for k in px) + 1
    return [[px[(x, y)] for x in range(w)] for y in range(h)]


def edges(img):
    h, w = len(img), len(img[0])
    mask = [[False] * w for _ in range(h)]
    for y in range(h):
        for x in range(w):
            for yy, xx in ((y, x + 1), (y + 1, x)):
                if yy < h and xx < w and abs(img[y][x] - img[yy][xx]) > 0.1:
                    mask[y][x] = mask[yy][xx] = True
    return mask


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--frames")]
    frames = [a.split("=", 1)[1] if "=" in a else None for a in sys.argv[1:] if a.startswith("--frames")]
    if len(args) < 2:
        sys.exit(__doc__)
    truth, dirs = args[0], args[1:]
    names = sorted(n for n in os.listdir(truth) if re.fullmatch(r"ao_\d{4}\.exr", n))
    if frames and frames[0]:
        a, b = (int(v) for v in frames[0].split(":"))
        names = [n for n in names if a <= int(n[3:7]) < b]
    sums = {d: [0.0, 0, 0.0, 0] for d in dirs}
    for n in names:
        t = read(os.path.join(truth, n))
        mask = edges(t)
        for d in dirs:
            img, s = read(os.path.join(d, n)), sums[d]
            for y, row in enumerate(t):
                for x, v in enumerate(row):
                    e = abs(img[y][x] - v)
                    if mask[y][x]:
                        s[2] += e
                        s[3] += 1
                    else:
                        s[0] += e
                        s[1] += 1
    for d, (rest, nrest, edge, nedge) in sums.items():
        total = nrest + nedge
        print(f"{d}: MAE {(rest + edge) / total:.4f}; at edges ({100 * nedge / total:.0f} % of pixels) "
              f"{edge / max(nedge, 1):.4f}; elsewhere {rest / max(nrest, 1):.4f}  ({len(names)} frames)")


main()
