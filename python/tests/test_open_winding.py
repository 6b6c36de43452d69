"""Model.winding on open leaves: the generalized winding number rounded to the nearest integer,
checked against an independent solid-angle sum in numpy (Van Oosterom-Strackee over every
triangle) and against classify (nonzero exactly where |w| > 1/2)."""

import numpy as np

import cover


def open_box(shift=(0.0, 0.0, 0.0)):
    """The unit cube without its top face (z = 1): vertices and outward triangles."""
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                  [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=np.float64) + shift
    F = np.array([[0, 2, 1], [0, 3, 2], [0, 1, 5], [0, 5, 4],
                  [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])
    return V, F


def solid_angle_sum(V, F, P):
    """Sum over the triangles of their solid angle seen from each point, over 4 pi."""
    a, b, c = (V[F[:, k]][None, :, :] - P[:, None, :] for k in range(3))
    la, lb, lc = (np.linalg.norm(x, axis=2) for x in (a, b, c))
    det = np.einsum("ptk,ptk->pt", a, np.cross(b, c))
    den = (la * lb * lc + np.einsum("ptk,ptk->pt", a, b) * lc
           + np.einsum("ptk,ptk->pt", a, c) * lb + np.einsum("ptk,ptk->pt", b, c) * la)
    return (2 * np.arctan2(det, den)).sum(axis=1) / (4 * np.pi)


def lattice_points(n=50, seed=3):
    """n^2 points of the plane x = 0.3 over [-0.5, 1.5]^2, jittered off the faces."""
    g = -0.5 + 2.0 * (np.arange(n) + 0.5) / n
    y, z = np.meshgrid(g, g, indexing="ij")
    P = np.column_stack([np.full(n * n, 0.3), y.ravel(), z.ravel()])
    return P + np.random.default_rng(seed).uniform(-1e-3, 1e-3, P.shape)


def test_winding_of_an_open_leaf_is_its_rounded_generalized_winding_number():
    V, F = open_box()
    m = cover.mesh(V, F)
    assert m.warnings and "open mesh" in m.warnings[0]
    assert "(closed_only refuses)" in m.warnings[0]  # the keyword that refuses it
    P = lattice_points()
    w = m.windings(P)[:, 0]
    ref = solid_angle_sum(V, F, P)
    far = np.abs(np.abs(ref) - 0.5) > 1e-6
    assert far.sum() > 2400
    assert (w[far] == np.rint(ref[far])).all()
    inside = m.classify(P) == 1
    assert ((w != 0) == inside).all()
    assert inside.sum() > 300


def test_winding_of_a_doubled_open_leaf_reaches_two():
    (V1, F1), (V2, F2) = open_box(), open_box((0.013, 0.007, -0.011))
    V, F = np.vstack([V1, V2]), np.vstack([F1, F2 + len(V1)])
    m = cover.mesh(V, F) | cover.box([0.25, 0.25, 0.25], [0.75, 0.75, 2])
    P = lattice_points(seed=4)
    w = m.windings(P)
    ref = solid_angle_sum(V, F, P)
    far = np.abs(ref - np.rint(ref)) < 0.49
    assert (w[far, 0] == np.rint(ref[far])).all()
    assert (w[:, 0] == 2).sum() > 100
    # The closed box's column: 1 inside, 0 outside.
    inside_box = ((P > [0.25, 0.25, 0.25]) & (P < [0.75, 0.75, 2])).all(axis=1)
    assert (w[:, 1] == inside_box).all()
