#!/usr/bin/env python3
"""Validate your own collision code against a cdbench pose set, in Python with numpy only.

The "implementation" here is deliberately trivial: the mover collides when the axis-aligned
bounding boxes of the placed mover and of the fixed mesh overlap. It never misses a collision
(a penetrating mover's box overlaps the fixed box) but reports many false positives, which
`cdbench score` counts against the certified clearances.

Usage: score_bounding_boxes.py POSESET_DIR OUT_DIR [CDBENCH]
  writes OUT_DIR/answers.csv (pose,collides,time_ns) and runs
  `CDBENCH score POSESET_DIR OUT_DIR/answers.csv -o OUT_DIR --name numpy-aabb --surface-only`.
Meshes: OFF or OBJ (the paths recorded in poseset.json).
"""
import json
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from read_poseset import read_off, read_poseset  # noqa: E402


def read_vertices(path):
    """Vertices (n, 3) of an OFF or OBJ mesh."""
    if path.lower().endswith(".off"):
        return read_off(path)[0]
    if path.lower().endswith(".obj"):
        with open(path, encoding="utf-8", errors="replace") as f:
            return np.array([line.split()[1:4] for line in f if line.startswith("v ")], dtype=float)
    raise SystemExit(f"{path}: this example reads OFF and OBJ meshes only")


def main(poseset, out, cdbench="cdbench"):
    meta, p = read_poseset(poseset)
    fixed = read_vertices(meta["fixed"]["path"])
    mover = read_vertices(meta["mover"]["path"])
    fixed_lo, fixed_hi = fixed.min(axis=0), fixed.max(axis=0)
    placed = np.isfinite(p["t"]).all(axis=1)
    os.makedirs(out, exist_ok=True)
    with open(f"{out}/answers.csv", "w", encoding="utf-8") as f:
        f.write("pose,collides,time_ns\n")
        for k in np.flatnonzero(placed):
            start = time.perf_counter_ns()
            world = mover @ p["R"][k].T + p["t"][k]  # x_world = R x + t
            lo, hi = world.min(axis=0), world.max(axis=0)
            collides = bool(np.all(lo <= fixed_hi) and np.all(fixed_lo <= hi))
            elapsed = time.perf_counter_ns() - start
            f.write(f"{p['pose'][k]},{int(collides)},{elapsed}\n")
    subprocess.run([cdbench, "score", poseset, f"{out}/answers.csv", "-o", out, "--name", "numpy-aabb",
                    "--surface-only"], check=True)
    with open(f"{out}/summary.json", encoding="utf-8") as f:
        summary = json.load(f)
    levels = summary["implementations"][0]["levels"]
    fp = sum(level["false_positives"] for level in levels)
    fn = sum(level["false_negatives"] + level["missed_or_contained"] for level in levels)
    print(f"numpy-aabb: {int(placed.sum())} poses, {fp} false positives, {fn} missed collisions")
    return 0 if fn == 0 else 1  # bounding boxes must never miss a collision


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    sys.exit(main(*sys.argv[1:4]))
