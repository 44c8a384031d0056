#!/usr/bin/env python3
"""Writes a user pose file for `cdbench certify`: COUNT poses with random quaternions (not
normalised: certify normalises) and translations of the given lengths in turn, in random
directions. Usage: random_poses.py OUT.csv COUNT SEED R1[,R2...]"""
import math
import random
import sys

out, count, seed, radii = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), [float(r) for r in sys.argv[4].split(",")]
random.seed(seed)
with open(out, "w") as f:
    f.write("pose,qw,qx,qy,qz,tx,ty,tz\n")
    for i in range(count):
        q = [random.gauss(0, 1) for _ in range(4)]
        d = [random.gauss(0, 1) for _ in range(3)]
        n = math.sqrt(sum(x * x for x in d))
        r = radii[i % len(radii)]
        f.write("%d,%s,%s\n" % (i, ",".join(repr(x) for x in q), ",".join(repr(r * x / n) for x in d)))
