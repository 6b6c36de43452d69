"""cover.subdivide (docs/python.md): Catmull–Clark of a cube against a pure-NumPy textbook
implementation, every scheme against the CLI's output, the array conventions and the errors."""

import numpy as np
import pytest

import cover
from conftest import MODELS, cli_json, read_off

# The cube [0, 1]^3, outward (counter-clockwise seen from outside) quads.
CUBE_V = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=np.float64)
CUBE_F = np.array([[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2],
                   [1, 3, 7, 5]], dtype=np.int64)


def textbook_catmull_clark(V, F):
    """One Catmull–Clark level of a closed quad mesh (Catmull & Clark 1978): face points are
    face centroids; edge points the average of the edge's ends and its two face points; vertex
    points (Q + 2R + (n - 3)P) / n with Q the average of the adjacent face points, R of the
    incident edges' midpoints. Returns the three point sets and the quads as coordinate tuples."""
    face_pt = V[F].mean(axis=1)
    edges = {}
    for f, face in enumerate(F):
        for k in range(len(face)):
            key = tuple(sorted((face[k], face[(k + 1) % len(face)])))
            edges.setdefault(key, []).append(f)
    edge_pt = {e: (V[e[0]] + V[e[1]] + face_pt[fs[0]] + face_pt[fs[1]]) / 4
               for e, fs in edges.items()}
    vertex_pt = np.empty_like(V)
    for v in range(len(V)):
        fs = [f for f, face in enumerate(F) if v in face]
        es = [e for e in edges if v in e]
        n = len(es)
        Q = face_pt[fs].mean(axis=0)
        R = np.mean([(V[a] + V[b]) / 2 for a, b in es], axis=0)
        vertex_pt[v] = (Q + 2 * R + (n - 3) * V[v]) / n
    quads = []
    for f, face in enumerate(F):
        for k in range(len(face)):
            a, b, c = face[k - 1], face[k], face[(k + 1) % len(face)]
            quads.append((vertex_pt[b], edge_pt[tuple(sorted((b, c)))], face_pt[f],
                          edge_pt[tuple(sorted((a, b)))]))
    return vertex_pt, np.array(list(edge_pt.values())), face_pt, quads


def canonical_quads(quads):
    """Each quad's corners as rounded tuples, rotated to start at its smallest; sorted."""
    out = []
    for q in quads:
        pts = [tuple(np.round(p, 12)) for p in q]
        k = pts.index(min(pts))
        out.append(tuple(pts[k:] + pts[:k]))
    return sorted(out)


def test_catmull_clark_of_a_cube_equals_the_textbook_rule():
    V, F = cover.subdivide(CUBE_V, CUBE_F)
    assert V.dtype == np.float64 and V.shape == (8 + 12 + 6, 3)
    assert F.dtype == np.int64 and F.shape == (24, 4)
    vertex_pt, edge_pt, face_pt, quads = textbook_catmull_clark(CUBE_V, CUBE_F)
    # Vertex points first, in input order: the cube's corner (0,0,0) goes to (2/9, 2/9, 2/9).
    np.testing.assert_allclose(V[:8], vertex_pt, rtol=0, atol=1e-15)
    np.testing.assert_allclose(V[0], [2 / 9] * 3, rtol=0, atol=1e-15)
    np.testing.assert_allclose(V[7], [7 / 9] * 3, rtol=0, atol=1e-15)
    # Then edge points (order of first appearance), then face points in face order.
    assert sorted(map(tuple, np.round(V[8:20], 12))) == sorted(map(tuple, np.round(edge_pt, 12)))
    np.testing.assert_allclose(V[20:], face_pt, rtol=0, atol=1e-15)
    assert canonical_quads(V[F]) == canonical_quads(quads)
    # The face point of the face z = 0 is its centre; an edge point of a cube edge is at 1/8
    # from the two faces' planes: (1/2, 1/8, 1/8) for the edge (0,0,0)-(1,0,0).
    assert [0.5, 0.5, 0.0] in V[20:].tolist()
    assert [0.5, 0.125, 0.125] in V[8:20].tolist()


def test_exact_rounding_agrees_on_a_cube():
    V1, F1 = cover.subdivide(CUBE_V, CUBE_F, levels=2)
    V2, F2 = cover.subdivide(CUBE_V, CUBE_F, levels=2, exact_rounding=True)
    np.testing.assert_array_equal(F1, F2)
    np.testing.assert_allclose(V1, V2, rtol=0, atol=1e-15)


@pytest.mark.parametrize("model, scheme, levels, extra", [
    ("torus.off", "catmull-clark", 2, []),
    ("torus.off", "doo-sabin", 1, []),
    ("knot.off", "loop", 1, []),
    ("knot.off", "sqrt3", 2, ["--exact-rounding"]),
])
def test_equals_the_cli(tmp_path, model, scheme, levels, extra):
    out = tmp_path / "out.off"
    j = cli_json("subdivide", MODELS / model, "-o", out, "--scheme", scheme, "--levels", levels,
                 *extra)
    V0, F0 = read_off(MODELS / model)
    V, F = cover.subdivide(V0, F0, scheme, levels, exact_rounding=bool(extra))
    Vc, Fc = read_off(out)
    np.testing.assert_array_equal(V, Vc)
    if isinstance(Fc, list):
        assert F == Fc
    else:
        np.testing.assert_array_equal(F, Fc)
    assert j["vertices"] == len(V) and j["faces"] == len(F)


def test_mixed_degrees_in_and_out():
    # A square pyramid: one quad and four triangles, as a list of index lists.
    V = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 1]]
    F = [[0, 3, 2, 1], [0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    Vc, Fc = cover.subdivide(V, F)
    assert Fc.shape == (4 + 4 * 3, 4)  # quads: one per corner
    assert len(Vc) == 5 + 8 + 5
    Vd, Fd = cover.subdivide(V, F, "doo-sabin")
    assert isinstance(Fd, list) and sorted({len(f) for f in Fd}) == [3, 4]
    assert len(Fd) == 5 + 8 + 5 and len(Vd) == 16
    assert all(isinstance(i, int) for f in Fd for i in f)
    # levels 0: the input back, in the output conventions.
    V0, F0 = cover.subdivide(V, F, levels=0)
    np.testing.assert_array_equal(V0, np.asarray(V, dtype=np.float64))
    assert F0 == F


def test_errors():
    with pytest.raises(cover.InputError, match="scheme"):
        cover.subdivide(CUBE_V, CUBE_F, "butterfly")
    with pytest.raises(cover.InputError, match="levels"):
        cover.subdivide(CUBE_V, CUBE_F, levels=-1)
    with pytest.raises(cover.InputError, match="levels"):
        cover.subdivide(CUBE_V, CUBE_F, levels=25)
    with pytest.raises(cover.InputError):
        cover.subdivide(CUBE_V, CUBE_F, "loop")  # quads
    with pytest.raises(cover.InputError, match="out of range"):
        cover.subdivide(CUBE_V, CUBE_F + 1)
    fin = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])  # three triangles on one edge
    with pytest.raises(cover.InputError):
        cover.subdivide(np.random.default_rng(1).random((5, 3)), fin, "loop")
    with pytest.raises(ValueError):
        cover.subdivide(CUBE_V[:, :2], CUBE_F)
    with pytest.raises(TypeError):
        cover.subdivide(CUBE_V, CUBE_F.astype(np.float64))
    assert issubclass(cover.InputError, ValueError)


CUBE_OBJ = """v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1
vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5
f 1/1 4/2 3/3 2/4\nf 5/1 6/2 7/3 8/4\nf 1/1 2/2 6/3 5/4\nf 2/1 3/2 7/3 6/4\nf 3/1 4/2 8/3 7/4
f 4/5 1/2 5/3 8/4
"""


def cube_obj_arrays():
    """The cube of CUBE_OBJ as (V, F, UV per corner), read here."""
    V, vt, F, UV = [], [], [], []
    for line in CUBE_OBJ.splitlines():
        w = line.split()
        if w[0] == "v":
            V.append([float(x) for x in w[1:]])
        elif w[0] == "vt":
            vt.append([float(x) for x in w[1:]])
        elif w[0] == "f":
            F.append([int(r.split("/")[0]) - 1 for r in w[1:]])
            UV.extend(vt[int(r.split("/")[1]) - 1] for r in w[1:])
    return np.array(V), np.array(F), np.array(UV)


@pytest.mark.parametrize("scheme", ["catmull-clark", "doo-sabin"])
def test_texture_coordinates_through_the_cli_read_back_by_vtk(tmp_path, scheme):
    vtk = pytest.importorskip("vtkmodules.vtkIOGeometry")
    from vtkmodules.util.numpy_support import vtk_to_numpy
    (tmp_path / "cube.obj").write_text(CUBE_OBJ)
    out = tmp_path / "out.obj"
    j = cli_json("subdivide", tmp_path / "cube.obj", "-o", out, "--scheme", scheme,
                 "--levels", 2)
    assert j["texture_coordinates"] is True
    V, F, UV = cube_obj_arrays()
    Vs, Fs, UVs = cover.subdivide(V, F, scheme, 2, uv=UV)
    assert UVs.shape == (sum(len(f) for f in Fs), 2)
    reader = vtk.vtkOBJReader()
    reader.SetFileName(str(out))
    reader.Update()
    poly = reader.GetOutput()
    points = vtk_to_numpy(poly.GetPoints().GetData())
    tcoords = vtk_to_numpy(poly.GetPointData().GetTCoords())
    cells = poly.GetPolys()
    ids = vtk_to_numpy(cells.GetConnectivityArray())
    offsets = vtk_to_numpy(cells.GetOffsetsArray())
    assert len(offsets) - 1 == len(Fs)
    corner = 0
    for f, face in enumerate(Fs):
        for k, v in enumerate(face):
            p = ids[offsets[f] + k]
            np.testing.assert_allclose(points[p], Vs[v], rtol=0, atol=1e-6)  # float32
            np.testing.assert_allclose(tcoords[p], UVs[corner], rtol=0, atol=1e-7)  # float32
            corner += 1


def test_texture_coordinates_keep_seams_and_interpolate_within_faces():
    V, F, UV = cube_obj_arrays()
    Vs, Fs, UVs = cover.subdivide(V, F, "catmull-clark", 1, uv=UV)
    # Quad of old corner c: (old vertex, edge point, face point, edge point).
    UVc = UVs.reshape(-1, 4, 2)
    UVin = UV.reshape(6, 4, 2)
    for f in range(6):
        for k in range(4):
            q = UVc[4 * f + k]
            np.testing.assert_array_equal(q[0], UVin[f, k])
            np.testing.assert_array_equal(q[1], (UVin[f, k] + UVin[f, (k + 1) % 4]) / 2)
            np.testing.assert_array_equal(q[2], UVin[f].mean(axis=0))
    # The (faces, n, k) form gives the same; wrong counts are InputErrors naming uv.
    np.testing.assert_array_equal(cover.subdivide(V, F, uv=UV.reshape(6, 4, 2))[2], UVs)
    with pytest.raises(cover.InputError, match="uv"):
        cover.subdivide(V, F, uv=UV[:-1])
