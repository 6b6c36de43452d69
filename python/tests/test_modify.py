"""cover.modify: modeling operations on arrays, against the CLI's `cover modify` of the same
mesh and script (byte-identical meshes), topology invariants computed here from the arrays
(Euler characteristic, edges used twice), and one-line errors naming the operation."""

import json
import subprocess

import numpy as np
import pytest

import cover

from conftest import COVER_BIN, SOURCE_DIR


def slab():
    """models/slab.off read here: 32 vertices, 30 quads."""
    lines = [l for l in (SOURCE_DIR / "models" / "slab.off").read_text().splitlines()
             if l and not l.startswith("#")]
    nv, nf, _ = map(int, lines[1].split())
    V = np.array([list(map(float, l.split())) for l in lines[2:2 + nv]])
    F = np.array([list(map(int, l.split()))[1:] for l in lines[2 + nv:2 + nv + nf]])
    return V, F


def euler_and_edges(F):
    faces = [list(f) for f in F]
    directed = {}
    for f in faces:
        for i, a in enumerate(f):
            b = f[(i + 1) % len(f)]
            directed[(a, b)] = directed.get((a, b), 0) + 1
    undirected = {tuple(sorted(e)) for e in directed}
    closed = all(directed.get((b, a), 0) == 1 and n == 1 for (a, b), n in directed.items())
    return len(undirected), len(faces), closed


def test_genus_three_part_matches_the_cli(tmp_path):
    V, F = slab()
    ops = json.loads((SOURCE_DIR / "models" / "genus3_part.json").read_text())
    V2, F2 = cover.modify(V, F, ops)
    E, nf, closed = euler_and_edges(F2)
    assert closed
    assert len(V2) - E + nf == 2 - 2 * 3
    out = tmp_path / "g3.off"
    subprocess.run([str(COVER_BIN), "modify", str(SOURCE_DIR / "models" / "slab.off"), "--ops",
                    str(SOURCE_DIR / "models" / "genus3_part.json"), "-o", str(out)], check=True,
                   capture_output=True)
    lines = [l for l in out.read_text().splitlines() if l and not l.startswith("#")]
    nv = int(lines[1].split()[0])
    cli_V = np.array([list(map(float, l.split())) for l in lines[2:2 + nv]])
    np.testing.assert_array_equal(cli_V, V2)
    # The script as JSON text gives the same mesh.
    V3, F3 = cover.modify(V, F, json.dumps(ops))
    np.testing.assert_array_equal(V3, V2)
    np.testing.assert_array_equal(np.asarray(F3), np.asarray(F2))


def test_extrusion_counts_and_points():
    V, F = slab()
    V2, F2 = cover.modify(V, F, [{"extrude": {"face": [3.5, 0.5, 0.6], "distance": 0.5}}])
    assert len(V2) == len(V) + 4 and len(F2) == len(F) + 4
    # The moved face's four corners are the top corners of cell 3 raised by 0.5.
    raised = sorted(tuple(p) for p in V2[len(V):])
    np.testing.assert_allclose(raised, [(3, 0, 1.1), (3, 1, 1.1), (4, 0, 1.1), (4, 1, 1.1)],
                               rtol=0, atol=1e-15)


def test_bad_operations_raise_input_errors_naming_the_path():
    V, F = slab()
    with pytest.raises(cover.InputError, match=r"operations: /0/pipe/faces/1: face 99 is not live"):
        cover.modify(V, F, [{"pipe": {"faces": [0, 99]}}])
    with pytest.raises(cover.InputError, match=r"unknown operation"):
        cover.modify(V, F, '[{"twirl": {}}]')
    with pytest.raises(cover.InputError, match=r"boundary"):
        cover.modify(V, F[:-1], [])


def test_halfedge_mesh_operators_against_euler_and_the_script():
    V, F = slab()
    m = cover.HalfedgeMesh(V, F)
    assert (m.vertex_count, m.edge_count, m.face_count, m.genus, m.components) == (32, 60, 30, 0, 1)
    p = m.create_vertex([0.5, 0.5, 2.0])
    assert (m.vertex_count, m.face_count, m.components) == (33, 31, 2)
    m.insert_edge(p, (0, 1))  # join the point-sphere to face 0's corner at vertex 1
    assert (m.edge_count, m.face_count, m.components) == (61, 30, 1)
    m.delete_edge(60)
    m.delete_vertex(p)
    V2, F2 = m.arrays()
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(np.asarray(F2), F)
    m.pipe([1.5, 0.5, 0.6], [1.5, 0.5, 0.0], segments=2)
    m.extrude([5.5, 0.5, 0.6], 0.3, kind="stellate")
    m.check()
    assert m.genus == 1
    E, nf, closed = euler_and_edges(m.arrays()[1])
    assert closed and m.vertex_count - E + nf == 0
    ops = [{"pipe": {"faces": [[1.5, 0.5, 0.6], [1.5, 0.5, 0.0]], "segments": 2}},
           {"extrude": {"face": [5.5, 0.5, 0.6], "distance": 0.3, "kind": "stellate"}}]
    V3, F3 = cover.modify(V, F, ops)
    np.testing.assert_array_equal(V3, m.arrays()[0])
    with pytest.raises(cover.InputError, match="not a point-sphere"):
        m.delete_vertex(0)


def test_curved_handle_matches_the_script_and_arches_over():
    V, F = slab()
    m = cover.HalfedgeMesh(V, F)
    m.pipe([1.5, 0.5, 0.6], [5.5, 0.5, 0.6], segments=12, curved=True, weights=(1.0, 1.0),
           path=[[3.5, 0.5, 2.5]])
    m.check()
    assert m.genus == 1 and m.vertex_count == 32 + 4 * 11
    ops = [{"pipe": {"faces": [[1.5, 0.5, 0.6], [5.5, 0.5, 0.6]], "segments": 12,
                     "curved": True, "path": [[3.5, 0.5, 2.5]]}}]
    V2, F2 = cover.modify(V, F, ops)
    np.testing.assert_array_equal(V2, m.arrays()[0])
    assert m.arrays()[0][:, 2].max() > 2.5
    with pytest.raises(cover.InputError, match="weights"):
        cover.HalfedgeMesh(V, F).pipe(0, 5, segments=4, curved=True, weights=(0.0, 1.0))
