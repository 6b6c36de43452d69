#!/usr/bin/python3
"""Writes the 10-leaf, ~600k-triangle preview scene of bench/render_vs_cgal as a Cover scene.

Usage: bench/preview_scene.py MESH_FOLDER OUT.json   (MESH_FOLDER: libcgal-demo data/meshes,
extracted into build/cgal-data/data/meshes at configure time). The leaves, their placement and
the expression ((A ∪ B ∪ C) − (D ∪ E)) ∪ ((F ∩ G) − H) ∪ (I − J) are render_vs_cgal's kLeaves:
each mesh scaled so that its largest box side is 2·half_size, centred, rotated about an axis,
moved to a centre. The matrices are computed here in float64 (M = T·R·S·C, row-major).
"""
import json
import math
import os
import sys

import numpy as np

LEAVES = [  # file, centre, half_size, axis, degrees (bench/render_vs_cgal.cpp kLeaves)
    ("bunny00.off", (-0.2, -0.2, 0), 0.8, (0, 0, 1), 0),
    ("bunny00.off", (0.2, 0.2, 0.05), 0.8, (0.2, 1, 0.3), 70),
    ("refined_elephant.off", (0.1, -0.35, 0.35), 0.9, (1, 0.2, 0.1), 30),
    ("armadillo.off", (0.3, -0.4, 0.3), 0.55, (0.3, 1, 0.2), 120),
    ("bunny00.off", (0.05, -0.3, 0.5), 0.5, (1, 1, 0), 200),
    ("armadillo.off", (0.75, 0.75, 0), 0.85, (0.1, 0.3, 1), 20),
    ("bunny00.off", (0.8, 0.8, 0.1), 0.85, (0.4, 0.1, 1), 160),
    ("fandisk_large.off", (0.85, 0.55, 0.25), 0.55, (0.3, 1, 0.2), 45),
    ("armadillo.off", (-0.75, -0.75, 0), 0.8, (0.2, 0.2, 1), 250),
    ("bear.off", (-0.55, -0.95, 0.3), 0.5, (0, 1, 0.3), 90),
]


def off_box(path):
    """Bounding box of an OFF file's vertices."""
    with open(path) as f:
        tokens = []
        for line in f:
            line = line.split("#")[0].split()
            if line:
                tokens.extend(line)
            if len(tokens) >= 4:
                break
        assert tokens[0] == "OFF", path
        nv = int(tokens[1])
        rest = tokens[4:]
        data = rest + f.read().split()
    v = np.array(data[: 3 * nv], dtype=float).reshape(nv, 3)
    return v.min(axis=0), v.max(axis=0)


def rotation(axis, degrees):
    a = np.array(axis, dtype=float)
    a /= np.linalg.norm(a)
    t = math.radians(degrees)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(t) * k + (1 - math.cos(t)) * (k @ k)


def leaf(folder, spec):
    file, centre, half, axis, degrees = spec
    lo, hi = off_box(os.path.join(folder, file))
    c = 0.5 * (lo + hi)
    s = 2 * half / max(hi - lo)
    m = np.eye(4)
    m[:3, :3] = rotation(axis, degrees) * s
    m[:3, 3] = np.array(centre, dtype=float) - m[:3, :3] @ c
    return {"mesh": os.path.abspath(os.path.join(folder, file)),
            "transform": {"matrix": [float(x) for x in m.reshape(-1)]}}


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: preview_scene.py MESH_FOLDER OUT.json")
    folder, out = sys.argv[1], sys.argv[2]
    L = [leaf(folder, s) for s in LEAVES]
    scene = {"union": [
        {"difference": [{"union": [L[0], L[1], L[2]]}, {"union": [L[3], L[4]]}]},
        {"difference": [{"intersection": [L[5], L[6]]}, L[7]]},
        {"difference": [L[8], L[9]]}]}
    with open(out, "w") as f:
        json.dump(scene, f, indent=1)


if __name__ == "__main__":
    main()
