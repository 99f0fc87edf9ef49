#!/usr/bin/env python3
"""A triangle soup for load tests (docs/RELIABILITY.md): N small random triangles in a 100 m box,
every corner written separately (no shared vertices, as scanners and STL exporters write them).

usage: make_soup.py N OUT.stl|OUT.obj   (binary STL, or OBJ text)"""
import random
import struct
import sys


def triangles(n, seed=5):
    rng = random.Random(seed)
    for _ in range(n):
        cx, cy, cz = rng.uniform(0, 100), rng.uniform(0, 100), rng.uniform(0, 100)
        yield [(cx + rng.gauss(0, 0.05), cy + rng.gauss(0, 0.05), cz + rng.gauss(0, 0.05)) for _ in range(3)]


def main():
    if len(sys.argv) != 3 or not sys.argv[2].endswith((".stl", ".obj")):
        sys.exit(__doc__)
    n, out = int(sys.argv[1]), sys.argv[2]
    if out.endswith(".stl"):
        pack = struct.Struct("<12fH").pack
        with open(out, "wb") as f:
            f.write(b"cubeao soup".ljust(80, b" ") + struct.pack("<I", n))
            for t in triangles(n):
                f.write(pack(0.0, 0.0, 0.0, *t[0], *t[1], *t[2], 0))  # zero normal: the reader computes one
    else:
        with open(out, "w") as f:
            for t in triangles(n):
                f.write("v %.6f %.6f %.6f\nv %.6f %.6f %.6f\nv %.6f %.6f %.6f\n" % (*t[0], *t[1], *t[2]))
            for i in range(n):
                f.write("f %d %d %d\n" % (3 * i + 1, 3 * i + 2, 3 * i + 3))


if __name__ == "__main__":
    main()
