#!/usr/bin/env python3
"""Read a cdbench pose set (format: doc/pose-set-format.md) with numpy, and check its invariants.

Usage: read_poseset.py DIR   -- prints a summary; exits 1 if an invariant fails.
As a module: meta, poses = read_poseset(DIR); poses["R"] is (n, 3, 3), poses["t"] (n, 3), ...
"""
import json
import sys

import numpy as np


def read_poseset(directory):
    with open(f"{directory}/poseset.json", encoding="utf-8") as f:
        meta = json.load(f)
    table = np.genfromtxt(f"{directory}/poses.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    table = np.atleast_1d(table)
    col = lambda name: np.asarray(table[name], dtype=float)
    poses = {
        "pose": np.asarray(table["pose"], dtype=np.int64),
        "level": np.asarray(table["level"], dtype=np.int64),
        "target": col("target"),
        # x_world = R @ x + t, R row-major in the file
        "R": np.stack([col(f"r{i}{j}") for i in range(3) for j in range(3)], axis=1).reshape(-1, 3, 3),
        "t": np.stack([col("tx"), col("ty"), col("tz")], axis=1),
        "dir": np.stack([col("dir_x"), col("dir_y"), col("dir_z")], axis=1),
        "clearance": np.stack([col("clearance_lo"), col("clearance_hi")], axis=1),
        "status": np.asarray(table["status"], dtype=str),
    }
    return meta, poses


def read_off(path):
    """Vertices (n, 3) and triangles (m, 3) of an ASCII OFF file (the offsets/ meshes)."""
    with open(path, encoding="utf-8") as f:
        tokens = [tok for line in f for tok in line.split("#")[0].split()]
    assert tokens[0] == "OFF", f"{path}: not an OFF file"
    nv, nf = int(tokens[1]), int(tokens[2])
    v = np.array(tokens[4:4 + 3 * nv], dtype=float).reshape(nv, 3)
    rest = np.array(tokens[4 + 3 * nv:], dtype=np.int64).reshape(nf, 4)
    return v, rest[:, 1:]


def main(directory):
    meta, p = read_poseset(directory)
    n = len(p["pose"])
    problems = []
    if meta.get("format") != "cdbench-poseset":
        problems.append("poseset.json: format is not cdbench-poseset")
    certified = p["status"] == "certified"
    R = p["R"][certified]
    err = np.abs(np.einsum("nij,nkj->nik", R, R) - np.eye(3)).max() if len(R) else 0.0
    if err > 1e-12:
        problems.append(f"rotation not orthonormal (max |R R^T - I| = {err:.3g})")
    if len(R) and np.abs(np.linalg.norm(p["dir"][certified], axis=1) - 1).max() > 1e-12:
        problems.append("approach direction not unit")
    lo, hi = p["clearance"][certified, 0], p["clearance"][certified, 1]
    if np.any(lo > hi):
        problems.append("clearance_lo > clearance_hi")
    tol = meta["certification"]["tolerance"]
    if meta["polishing"]["enabled"]:
        tgt = p["target"][certified]
        off = np.sum((lo < tgt - tol) | (hi > tgt + tol))
        if off:
            problems.append(f"{off} certified polished poses are not within the tolerance of their target")
    print(f"{directory}: {n} poses, {int(certified.sum())} certified, {len(meta['levels'])} levels")
    for level in meta["levels"]:
        sel = (p["level"] == level["index"]) & certified
        c = p["clearance"][sel].mean(axis=1) if sel.any() else np.array([np.nan])
        print(f"  level {level['spec']:>8}: target {level['target']:+.6g}, {int(sel.sum())} certified, "
              f"clearance mean {np.nanmean(c):+.6g}")
    for prob in problems:
        print("PROBLEM:", prob)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "."))
