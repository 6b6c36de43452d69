#!/usr/bin/env python3
"""Regenerates the plane-patcher test models ([Erleben2006] Table 1 / Fig. 19) and a
pinch case (deterministic text output).

knot.off            (2,3) torus knot tube, 180 x 16 x 2 triangles, 2880 vertices
torus1536.off       quad torus R=2 r=0.6, 64 x 24 = 1536 vertices
box_with_holes.off  a slab with two through-holes; each hole holds a floating frame (a box with a
                    through-hole) holding a small box: the cut z = 0 gives rings nested 5 deep
                    (outer, 2 holes, 2 frames, 2 frame holes, 2 boxes)
box_with_rings.off  a hollow box (cavity reversed) holding three nested square rings (frames):
                    the cut z = 0 gives 8 rings nested 8 deep
pinch.off           a slab with two tapered towers whose footprints touch at one corner (0, 0, 0):
                    the cut z = 0 walks two rings through one vertex (a pinched vertex)
Faces with holes (top and bottom of frames and the slab) are single faces whose hole loops are
joined by false edges ([Segura2004 §3 Fig. 1]).
"""
import math

from make_models import write_off  # the same OFF text writer as the project's other models


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def norm(a):
    n = math.sqrt(sum(c * c for c in a))
    return [c / n for c in a]


def tube(curve, n, m, radius):
    """Closed tube around a closed curve with Frenet frames (curvature never vanishes)."""
    verts, faces = [], []
    h = 1e-5
    for i in range(n):
        t = 2 * math.pi * i / n
        c = curve(t)
        d1 = [(curve(t + h)[k] - curve(t - h)[k]) / (2 * h) for k in range(3)]
        d2 = [(curve(t + h)[k] - 2 * c[k] + curve(t - h)[k]) / (h * h) for k in range(3)]
        T = norm(d1)
        B = norm(cross(d1, d2))
        N = cross(B, T)
        for j in range(m):
            a = 2 * math.pi * j / m
            verts.append(tuple(round(c[k] + radius * (math.cos(a) * N[k] + math.sin(a) * B[k]), 12)
                               for k in range(3)))
    for i in range(n):
        for j in range(m):
            a, b = i * m + j, ((i + 1) % n) * m + j
            c, d = ((i + 1) % n) * m + (j + 1) % m, i * m + (j + 1) % m
            faces += [(a, d, c), (a, c, b)]  # triangles: the tube's quads are not planar
    return verts, faces


def knot():
    def curve(t):
        r = 2 + math.cos(3 * t)
        return (r * math.cos(2 * t), r * math.sin(2 * t), math.sin(3 * t))
    verts, faces = tube(curve, 180, 16, 0.3)
    write_off("knot.off", verts, faces, "(2,3) torus knot tube, 180x16x2 triangles")


def torus():
    n, m, R, r = 64, 24, 2.0, 0.6
    verts, faces = [], []
    for i in range(n):
        u = 2 * math.pi * i / n
        for j in range(m):
            v = 2 * math.pi * j / m
            verts.append((round((R + r * math.cos(v)) * math.cos(u), 12),
                          round((R + r * math.cos(v)) * math.sin(u), 12), round(r * math.sin(v), 12)))
    for i in range(n):
        for j in range(m):
            a, b = i * m + j, ((i + 1) % n) * m + j
            c, d = ((i + 1) % n) * m + (j + 1) % m, i * m + (j + 1) % m
            faces.append((a, b, c, d))
    write_off("torus1536.off", verts, faces, "torus R=2 r=0.6, 64x24 quads")


class Soup:
    def __init__(self):
        self.verts, self.faces = [], []

    def v(self, p):
        self.verts.append(tuple(float(c) for c in p))
        return len(self.verts) - 1

    def prism(self, outer, holes, z0, z1, reverse=False):
        """Prism over a counter-clockwise loop with holes (loops given counter-clockwise), z in
        [z0, z1]. The top joins each hole by a false edge from outer[0]; the bottom is the top's
        mirror (its reversed sequence), so both faces are weakly simple."""
        def ring(loop, z):
            return [self.v((x, y, z)) for x, y in loop]
        ob, ot = ring(outer, z0), ring(outer, z1)
        hb = [ring(h, z0) for h in holes]
        ht = [ring(h, z1) for h in holes]
        faces = []

        def cap(outer_loop, hole_loops):  # counter-clockwise from above
            seq = list(outer_loop)
            for h in hole_loops:  # hole loops clockwise, each joined to outer[0] by a false edge
                seq += [outer_loop[0], h[0]] + h[:0:-1] + [h[0]]
            return seq
        top = cap(ot, ht)
        bottom = list(reversed(cap(ob, hb)))
        faces += [top, bottom]
        for loop_b, loop_t, outward in [(ob, ot, True)] + [(b, t, False) for b, t in zip(hb, ht)]:
            k = len(loop_b)
            for i in range(k):
                a, b = loop_b[i], loop_b[(i + 1) % k]
                c, d = loop_t[(i + 1) % k], loop_t[i]
                faces.append([a, b, c, d] if outward else [b, a, d, c])
        if reverse:
            faces = [list(reversed(f)) for f in faces]
        self.faces += faces

    def write(self, name, comment):
        write_off(name, self.verts, self.faces, comment)


def rect(x0, y0, x1, y1):
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def box_with_holes():
    s = Soup()
    s.prism(rect(-12, -6, 12, 6), [rect(-11, -5, -1, 5), rect(1, -5, 11, 5)], -3, 3)
    for cx in (-6, 6):
        s.prism(rect(cx - 4, -4, cx + 4, 4), [rect(cx - 3, -3, cx + 3, 3)], -2, 2)
        s.prism(rect(cx - 2, -2, cx + 2, 2), [], -1, 1)
    s.write("box_with_holes.off", "slab with 2 holes, each holding a frame holding a box")


def box_with_rings():
    s = Soup()
    s.prism(rect(-9, -9, 9, 9), [], -9, 9)
    s.prism(rect(-8, -8, 8, 8), [], -8, 8, reverse=True)
    for a, b in ((7, 6), (5, 4), (3, 2)):
        s.prism(rect(-a, -a, a, a), [rect(-b, -b, b, b)], -1, 1)
    s.write("box_with_rings.off", "hollow box holding three nested square rings")


def pinch():
    s = Soup()
    P = {}

    def v(x, y, z):
        if (x, y, z) not in P:
            P[(x, y, z)] = s.v((x, y, z))
        return P[(x, y, z)]

    def face(pts):
        s.faces.append([v(*p) for p in pts])

    h = 0.5
    # Top of the slab (z = 0, normal +z): four quadrant faces around the two footprints.
    face([(h, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, h, 0), (h, h, 0)])
    face([(0, 0, 0), (0, h, 0), (0, 1, 0), (-1, 1, 0), (-1, 0, 0), (-h, 0, 0)])
    face([(-h, 0, 0), (-1, 0, 0), (-1, -1, 0), (0, -1, 0), (0, -h, 0), (-h, -h, 0)])
    face([(0, 0, 0), (0, -h, 0), (0, -1, 0), (1, -1, 0), (1, 0, 0), (h, 0, 0)])
    # Slab bottom and sides (z in [-1, 0]).
    face([(-1, -1, -1), (-1, 1, -1), (1, 1, -1), (1, -1, -1)])
    face([(1, -1, -1), (1, 1, -1), (1, 1, 0), (1, 0, 0), (1, -1, 0)])
    face([(1, 1, -1), (-1, 1, -1), (-1, 1, 0), (0, 1, 0), (1, 1, 0)])
    face([(-1, 1, -1), (-1, -1, -1), (-1, -1, 0), (-1, 0, 0), (-1, 1, 0)])
    face([(-1, -1, -1), (1, -1, -1), (1, -1, 0), (0, -1, 0), (-1, -1, 0)])
    # Two towers (z in [0, 1]) tapering away from the shared corner.
    for sg in (1, -1):
        b = [(0, 0, 0), (sg * h, 0, 0), (sg * h, sg * h, 0), (0, sg * h, 0)]
        t = [(sg * 0.1, sg * 0.1, 1), (sg * h, sg * 0.1, 1), (sg * h, sg * h, 1), (sg * 0.1, sg * h, 1)]
        face(t)
        for i in range(4):
            face([b[i], b[(i + 1) % 4], t[(i + 1) % 4], t[i]])
    s.write("pinch.off", "slab with two towers touching at (0,0,0)")


if __name__ == "__main__":
    knot()
    torus()
    box_with_holes()
    box_with_rings()
    pinch()
