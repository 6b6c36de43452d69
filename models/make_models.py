#!/usr/bin/env python3
"""Regenerates the project's small mesh models (deterministic text output).

torus.off  quad torus, major radius 2, minor 0.6, 32 x 16 (genus 1)
frame.off  box [0,4]^3 with a 2x2 square through-hole along z; the top and bottom faces
           hold the hole loop joined by false edges ([Segura2004 §3 Fig. 1])
"""
import math
import pathlib

HERE = pathlib.Path(__file__).resolve().parent


def write_off(name, verts, faces, comment):
    lines = ["OFF", f"# {comment}", f"{len(verts)} {len(faces)} 0"]
    lines += [" ".join(repr(float(c)) for c in v) for v in verts]
    lines += [" ".join(str(x) for x in [len(f)] + list(f)) for f in faces]
    (HERE / name).write_text("\n".join(lines) + "\n")


def torus(R=2.0, r=0.6, n=32, m=16):
    verts, faces = [], []
    for i in range(n):
        u = 2 * math.pi * i / n
        for j in range(m):
            v = 2 * math.pi * j / m
            verts.append((round((R + r * math.cos(v)) * math.cos(u), 12),
                          round((R + r * math.cos(v)) * math.sin(u), 12),
                          round(r * math.sin(v), 12)))
    for i in range(n):
        for j in range(m):
            a, b = i * m + j, ((i + 1) % n) * m + j
            c, d = ((i + 1) % n) * m + (j + 1) % m, i * m + (j + 1) % m
            faces.append((a, b, c, d))
    write_off("torus.off", verts, faces, "torus R=2 r=0.6, 32x16 quads")


def frame():
    lo, hi, hlo, hhi = 0, 4, 1, 3
    verts = [((hi if i & 1 else lo), (hi if i & 2 else lo), (hi if i & 4 else lo)) for i in range(8)]
    verts += [((hhi if i & 1 else hlo), (hhi if i & 2 else hlo), (hi if i & 4 else lo)) for i in range(8)]
    faces = [
        (4, 5, 7, 6, 4, 12, 14, 15, 13, 12),  # top with hole (false edge 4-12)
        (0, 2, 3, 1, 0, 8, 9, 11, 10, 8),     # bottom with hole (false edge 0-8)
        (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5),
        (8, 12, 13, 9), (10, 11, 15, 14), (8, 10, 14, 12), (9, 13, 15, 11),
    ]
    write_off("frame.off", verts, faces, "box with a square through-hole; faces with false edges")


if __name__ == "__main__":
    torus()
    frame()
