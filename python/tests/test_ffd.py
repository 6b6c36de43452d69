"""Free-form deformation: cover.ffd against the scene's "ffd" node (the same mesh through the CLI's
loader), the identity lattice, and the certified chord bound."""

import json

import numpy as np
import pytest

import cover


def identity(lo, hi, degree):
    axes = [np.linspace(lo[a], hi[a], degree[a] + 1) for a in range(3)]
    return np.array([[x, y, z] for x in axes[0] for y in axes[1] for z in axes[2]])


def test_identity_lattice_returns_the_input():
    V, F = cover.box([0, 0, 0], [1, 2, 3]).evaluate()
    W, G, report = cover.ffd(V, F, [-1, -1, -1], [2, 3, 4], identity([-1, -1, -1], [2, 3, 4], [1, 1, 1]))
    assert report == {"levels": 0, "chord_bound": 0.0}
    assert np.array_equal(V, W) and np.array_equal(F, G)


def test_ffd_equals_the_scene_node(tmp_path):
    V, F = cover.box([-0.5, -0.5, -0.5], [0.5, 0.5, 0.5]).evaluate()
    cover.write_mesh(tmp_path / "box.off", V, F)
    P = identity([-1, -1, -1], [1, 1, 1], [2, 2, 2])
    P[13] += [0.3, 0.2, 0.4]  # the centre control point
    W, G, report = cover.ffd(V, F, [-1, -1, -1], [1, 1, 1], P, degree=[2, 2, 2], tolerance=5e-3)
    assert 0 < report["chord_bound"] <= 5e-3 and report["levels"] > 0
    scene = {"ffd": {"lattice": {"min": [-1, -1, -1], "max": [1, 1, 1], "degree": [2, 2, 2],
                                 "points": P.tolist()},
                     "tolerance": 5e-3, "child": {"mesh": "box.off"}}}
    (tmp_path / "ffd.json").write_text(json.dumps(scene))
    loaded = cover.load(tmp_path / "ffd.json")
    assert loaded.volume(exact=True) == cover.mesh(W, G).volume(exact=True)
    assert loaded.info()["leaves_info"][0]["closed"]


def test_bad_lattices_are_refused():
    V, F = cover.box([0, 0, 0], [1, 1, 1]).evaluate()
    with pytest.raises(cover.InputError, match="control points"):
        cover.ffd(V, F, [0, 0, 0], [1, 1, 1], np.zeros((3, 3)))
    with pytest.raises(cover.InputError, match="outside the lattice box"):
        cover.ffd(V, F, [0.5, 0, 0], [1, 1, 1], identity([0.5, 0, 0], [1, 1, 1], [1, 1, 1]))
    with pytest.raises(cover.InputError, match="degree"):
        cover.ffd(V, F, [0, 0, 0], [1, 1, 1], identity([0, 0, 0], [1, 1, 1], [1, 1, 1]), degree=[0, 1, 1])
