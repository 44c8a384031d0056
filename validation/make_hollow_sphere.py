#!/usr/bin/env python3
"""Writes a hollow sphere as an OFF file: an icosphere of radius 1 (the icosahedron with its edges'
midpoints pushed onto the sphere SUBDIVISIONS times, 20 * 4^k faces) and the same sphere scaled by
RATIO, reversed, as its cavity: a closed solid with one thin curved wall (thickness 1 - RATIO), whose deepest points
form a 2-D plateau along the wall's mid-surface. Used in doc/performance.md ("What is still slow")
to measure the maximum penetration's search on thin shells.
Usage: validation/make_hollow_sphere.py OUT.off SUBDIVISIONS RATIO   (e.g. shell.off 3 0.97)"""
import math
import sys


def icosphere(subdivisions):
    t = (1 + 5 ** 0.5) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
             (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
             (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        middle = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                p = [(verts[a][i] + verts[b][i]) / 2 for i in range(3)]
                n = math.sqrt(sum(x * x for x in p))
                verts.append(tuple(x / n for x in p))
                middle[key] = len(verts) - 1
            return middle[key]

        finer = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            finer += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = finer
    return verts, faces


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    out, subdivisions, ratio = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
    if not 0 < ratio < 1 or not 0 <= subdivisions <= 7:
        sys.exit("make_hollow_sphere.py: RATIO must lie in (0, 1) and SUBDIVISIONS in [0, 7]")
    verts, faces = icosphere(subdivisions)
    n = len(verts)
    with open(out, "w") as f:
        f.write("OFF\n%d %d 0\n" % (2 * n, 2 * len(faces)))
        for scale in (1.0, ratio):
            for v in verts:
                f.write("%.17g %.17g %.17g\n" % tuple(scale * x for x in v))
        for a, b, c in faces:
            f.write("3 %d %d %d\n" % (a, b, c))
        for a, b, c in faces:  # the cavity faces inwards: reversed
            f.write("3 %d %d %d\n" % (n + c, n + b, n + a))


if __name__ == "__main__":
    main()
