"""The Python API on its own and against independent paths: analytic volumes and hits of boxes,
numpy ray parity on a triangle mesh, shapes and dtypes, errors, thread counts, large arrays,
Ctrl-C."""

import os
import signal
import subprocess
import threading
import time
import tracemalloc

import numpy as np
import pytest

import cover
from conftest import (COVER_BIN, MODELS, canonical_triangles, parity_inside, read_png_rgb,
                      signed_volume)


def box_mesh(lo, hi):
    """Vertices and outward triangles of the box [lo, hi] (an independent mesh)."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    V = np.array([[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
                  [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]], dtype=np.float64)
    F = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                  [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])
    return V, F


def octahedron():
    V = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    F = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4],
                  [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    return V, F


def test_version_and_class_names():
    assert cover.__version__ == "0.2.0"
    assert cover.CLASS_NAMES == ("outside", "inside", "face", "edge", "vertex")


def test_box_classes_and_volume_are_analytic():
    b = cover.box([0, 0, 0], [2, 3, 4])
    assert b.volume() == 24.0
    info = b.volume_info()
    assert info["method"] == "covering" and info["error_bound"] == 0 and info["area"] == 52.0
    assert np.array_equal(b.bounds(), [[0, 0, 0], [2, 3, 4]])
    P = [[1, 1, 1], [3, 1, 1], [0, 1, 1], [0, 0, 1], [0, 0, 0], [2, 3, 4], [1, 1.5, 4]]
    assert b.classify(P).tolist() == [1, 0, 2, 3, 4, 4, 2]


def test_operators_match_analytic_volumes():
    a = cover.box([0, 0, 0], [2, 2, 2])
    b = cover.box([1, 1, 1], [3, 3, 3])
    assert (a | b).volume() == pytest.approx(15, rel=1e-4)
    assert (a & b).volume() == pytest.approx(1, rel=1e-4)
    assert (a - b).volume() == pytest.approx(7, rel=1e-4)
    assert (a | b).volume(exact=True) == pytest.approx(15, rel=1e-14)
    assert (a - b).volume(exact=True) == pytest.approx(7, rel=1e-14)
    assert (~a).classify([[1, 1, 1], [5, 5, 5]]).tolist() == [0, 1]
    assert not (~a).bounded and (a | b).bounded
    with pytest.raises(cover.NotComputable):
        (~a).volume()
    with pytest.raises(cover.NotComputable):
        (~a).bounds()
    assert (a | b).leaves == 2


def test_transforms_return_new_models():
    b = cover.box([0, 0, 0], [1, 1, 1])
    moved = b.translate([10, 0, 0])
    assert np.array_equal(b.bounds(), [[0, 0, 0], [1, 1, 1]])
    assert np.array_equal(moved.bounds(), [[10, 0, 0], [11, 1, 1]])
    assert b.scale(2).volume() == 8 and b.scale([1, 2, 3]).volume() == 6
    assert b.scale(np.float32(2)).volume() == 8
    r = b.rotate([0, 0, 1], 90)
    assert np.allclose(r.bounds(), [[-1, 0, 0], [0, 1, 1]], atol=1e-15)
    M = np.eye(4)
    M[:3, 3] = [1, 2, 3]
    assert np.array_equal(b.transform(M).bounds(), [[1, 2, 3], [2, 3, 4]])
    mirror = np.diag([-1.0, 1, 1, 1])
    assert b.transform(mirror).volume() == 1.0  # a mirror keeps the solid solid
    with pytest.raises(cover.InputError):
        b.transform(np.zeros((4, 4)))
    with pytest.raises(ValueError, match="4x4"):
        b.transform(np.eye(3))


def test_mirror_union_all_and_intersection_all():
    b = cover.box([0, 0, 0], [1, 2, 3])
    m = b.mirror([1, 0, 0])
    assert np.array_equal(m.bounds(), [[-1, 0, 0], [0, 2, 3]])
    assert m.volume(exact=True) == 6.0  # a mirror keeps the solid solid
    with pytest.raises(cover.InputError, match="normal"):
        b.mirror([0, 0, 0])
    # union_all equals the chained operator and numpy's "inside any box" on random points.
    rng = np.random.default_rng(11)
    lows = rng.uniform(0, 4, size=(60, 3))
    boxes = [cover.box(lo, lo + 0.7) for lo in lows]
    chained = boxes[0]
    for part in boxes[1:]:
        chained = chained | part
    P = rng.uniform(-0.5, 5, size=(5000, 3))
    inside_any = ((P[:, None, :] > lows[None]) & (P[:, None, :] < lows[None] + 0.7)).all(2).any(1)
    for model in (cover.union_all(boxes), cover.union_all(iter(boxes)), chained):
        assert model.leaves == 60
        codes = model.classify(P)
        assert np.array_equal(codes[np.isin(codes, [0, 1])] == 1, inside_any[np.isin(codes, [0, 1])])
    assert cover.union_all([]).empty
    both = cover.intersection_all([cover.box([0, 0, 0], [2, 2, 2]), cover.box([1, 1, 1], [3, 3, 3])])
    assert both.volume(exact=True) == 1.0
    with pytest.raises(cover.PreconditionError):
        cover.intersection_all([])


def test_mesh_classification_equals_numpy_ray_parity():
    V, F = octahedron()
    V = V * [1.3, 0.9, 1.1] + [0.1, -0.2, 0.05]
    model = cover.mesh(V, F)
    P = np.random.default_rng(7).uniform(-1.5, 1.5, size=(4000, 3))
    codes = model.classify(P)
    assert not np.isin(codes, [2, 3, 4]).any()  # random points miss the surface
    assert np.array_equal(codes == 1, parity_inside(V, F, P))
    assert model.volume() == pytest.approx(signed_volume(V, F), rel=1e-14)


def test_mesh_accepts_any_integer_index_dtype_and_inside_out():
    V, F = box_mesh([0, 0, 0], [1, 2, 3])
    for f in (F.astype(np.int32), F.astype(np.uint32), F.astype(np.uint64), F.tolist()):
        assert cover.mesh(V, f).volume() == 6.0
    with pytest.warns(UserWarning):
        flipped = cover.mesh(V, F[:, ::-1])
    assert flipped.volume() == 6.0 and flipped.warnings


def test_winding_numbers_of_overlapping_leaves():
    a = cover.box([0, 0, 0], [2, 2, 2])
    b = cover.box([1, 1, 1], [3, 3, 3])
    w = (a | b).windings([[0.5, 0.5, 0.5], [1.5, 1.5, 1.5], [2.5, 2.5, 2.5], [5, 5, 5]])
    assert w.dtype == np.int32 and w.shape == (4, 2)
    assert w.tolist() == [[1, 0], [1, 1], [0, 1], [0, 0]]
    V, F = box_mesh([0, 0, 0], [1, 1, 1])
    double = cover.mesh(np.vstack([V, V]), np.vstack([F, F + 8]))  # two coincident shells
    assert double.windings([[0.5, 0.5, 0.5]]).tolist() == [[2]]


def test_cast_hits_box_faces():
    b = cover.box([0, 0, 0], [1, 1, 1])
    O = np.array([[-1, 0.5, 0.5], [0.5, 0.5, 3], [5, 5, 5], [0.5, 0.25, 0.5]])
    D = np.array([[2, 0, 0], [0, 0, -1], [1, 0, 0], [0, 1, 0]], float)
    h = b.first_hits(O, D)
    assert isinstance(h, cover.Hits)
    assert h.hit.tolist() == [True, True, False, False]  # the last starts inside: no entry
    assert h.t[:2].tolist() == [0.5, 2.0] and np.isinf(h.t[2])
    assert h.normal[:2].tolist() == [[-1, 0, 0], [0, 0, 1]]
    assert h.leaf.dtype == np.int32 and h.face.dtype == np.int64 and h.leaf[2] == -1
    points = O[:2] + h.t[:2, None] * D[:2]
    assert np.isin(b.classify(points), [2, 3, 4]).all()
    shared = b.first_hits(O[:2], [1, 0, 0])  # one direction for every ray
    assert shared.hit.tolist() == [True, False]


def test_cast_gives_every_crossing_and_first_hits_the_first():
    """cast() is C++'s Model::cast (every crossing, the inside spans); first_hits() its first
    entry. Checked against the analytic crossings of two disjoint boxes along x."""
    m = cover.box([0, 0, 0], [1, 1, 1]) | cover.box([2, 0, 0], [3, 1, 1])
    O = np.array([[-1, 0.5, 0.5], [0.5, 0.5, 0.5], [-1, 5, 5]])
    c = m.cast(O, [1, 0, 0])
    assert isinstance(c, cover.Casts)
    assert c.offsets.tolist() == [0, 4, 7, 7] and c.span_offsets.tolist() == [0, 2, 4, 4]
    assert c.t[:4].tolist() == [1, 2, 3, 4] and c.t[4:].tolist() == [0.5, 1.5, 2.5]
    assert c.sign[:4].tolist() == [-1, 1, -1, 1]
    assert c.leaf[:4].tolist() == [0, 0, 1, 1]
    assert c.spans.tolist() == [[1, 2], [3, 4], [0, 0.5], [1.5, 2.5]]
    assert c.uncertain.tolist() == [0, 0, 0]
    h = m.first_hits(O, [1, 0, 0])
    assert h.hit.tolist() == [True, True, False] and h.t[:2].tolist() == [1, 1.5]


def test_windings_is_the_cpp_name_and_winding_warns_at_the_callers_line():
    b = cover.box([0, 0, 0], [1, 1, 1])
    assert b.windings([[0.5, 0.5, 0.5]]).tolist() == [[1]]
    with pytest.warns(DeprecationWarning, match="windings") as record:
        assert b.winding([[0.5, 0.5, 0.5]]).tolist() == [[1]]
    assert record[0].filename == __file__


def test_repair_warnings_name_the_callers_line():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    with pytest.warns(UserWarning, match="open mesh") as record:
        cover.mesh(V, [[0, 2, 1], [0, 1, 3]])
    assert record[0].filename == __file__


def test_volume_is_a_float_with_its_provenance():
    """Model.volume() returns the C++ VolumeResult's fields on a float; pickles; equals the
    dict of volume_info() and of `cover volume --json`."""
    import pickle
    v = cover.box([0, 0, 0], [1, 2, 3]).volume()
    assert isinstance(v, cover.VolumeResult) and isinstance(v, float)
    assert v == 6 and v.volume == 6 and v.method == "covering" and v.error_bound == 0
    assert v.area == 22 and v + 1 == 7
    assert v.as_dict() == cover.box([0, 0, 0], [1, 2, 3]).volume_info()
    w = pickle.loads(pickle.dumps(v))
    assert w == v and w.method == v.method and isinstance(w, cover.VolumeResult)
    ball = cover.sphere([0, 0, 0], 1, 16) - cover.box([0, 0, 0], [2, 2, 2])
    r = ball.volume(rays=64)
    assert r.method == "rays" and r.rays > 0 and r.error_bound > 0
    assert "VolumeResult(volume=" in repr(r) and str(v) == "6.0" and f"{v}" == "6.0"


def test_write_png_and_notebook_display(tmp_path):
    m = cover.box([0, 0, 0], [1, 1, 1]) - cover.sphere([1, 1, 1], 0.6, 24)
    image = m.render(64, 48)
    cover.write_png(tmp_path / "a.png", image)
    assert np.array_equal(read_png_rgb(tmp_path / "a.png"), image)
    png = m._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    (tmp_path / "b.png").write_bytes(png)
    assert read_png_rgb(tmp_path / "b.png").shape == (240, 320, 3)
    assert cover.Model()._repr_png_() is None
    with pytest.raises(cover.InputError, match="image"):
        cover.write_png(tmp_path / "c.png", image[:, :, :2])
    with pytest.raises(cover.InputError, match="jpg"):
        cover.write_png(tmp_path / "c.jpg", image)
    assert not (tmp_path / "c.png").exists()


def test_voxelize_converges_to_volume_and_indexes_xyz():
    b = cover.box([0, 0, 0], [1, 0.5, 0.25])
    grid = b.voxelize(64, bounds=(0, 0, 0, 1))
    assert grid.shape == (64, 64, 64) and grid.dtype == np.bool_ and grid.flags.c_contiguous
    assert grid[:, :32, :16].all() and grid.sum() == 64 * 32 * 16  # [x, y, z]


def test_render_view_and_section():
    m = cover.load(MODELS / "default.json")
    image = m.render(32, 24, view="front")
    assert image.shape == (24, 32, 3) and image.dtype == np.uint8
    assert (image[0, 0] == 255).all()  # background
    assert not np.array_equal(image, m.render(32, 24, view="front", section=(0, -1, 0, 0)))  # front half off
    # Messages name Python's parameters, never the CLI's flags.
    with pytest.raises(cover.InputError, match=r"^view: unknown view 'sideways'"):
        m.render(32, 24, view="sideways")
    with pytest.raises(cover.InputError, match=r"^width, height: expected whole numbers"):
        m.render(0, 24)
    with pytest.raises(cover.InputError, match=r"^res: expected a whole number from 1 to"):
        m.voxelize(5000)
    with pytest.raises(cover.InputError, match=r"^bounds: expected finite"):
        m.voxelize(8, bounds=(0, 0, 0, -1))


def test_evaluate_leaf_ids():
    # box - sphere: faces on the box's planes come from leaf 0, the others from the sphere (1).
    m = cover.box([0, 0, 0], [2, 2, 2]) - cover.sphere([2, 2, 1.5], 1.2, segments=16)
    V, F = m.evaluate()
    V2, F2, L = m.evaluate(leaf_ids=True)
    assert np.array_equal(V, V2) and np.array_equal(F, F2)
    assert L.dtype == np.int32 and L.shape == (len(F),)
    T = V[F]  # (m, 3, 3)
    on_box = np.zeros(len(F), bool)
    for axis in range(3):
        for c in (0.0, 2.0):
            on_box |= np.all(T[:, :, axis] == c, axis=1)
    assert np.array_equal(L, np.where(on_box, 0, 1))
    assert 0 < np.count_nonzero(L == 1) < len(F)
    assert np.array_equal(m.evaluate(leaf_ids=True, threads=1)[2], m.evaluate(leaf_ids=True, threads=2)[2])


def test_evaluate_self_intersecting_leaf():
    # Two overlapping cubes in one leaf: its nonzero-winding set, their union (volume 15).
    V = np.array([[x, y, z] for x in (0, 2) for y in (0, 2) for z in (0, 2)], float)
    F = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    m = cover.mesh(np.vstack([V, V + 1]), np.vstack([F, F + 8]))
    Ve, Fe = m.evaluate()
    assert signed_volume(Ve, Fe) == pytest.approx(15, rel=1e-12)
    P = np.random.default_rng(3).uniform(-0.5, 3.5, (2000, 3))
    assert np.array_equal(m.classify(P) == 1, cover.mesh(Ve, Fe).classify(P) == 1)


def test_evaluate_and_clip_volumes_agree():
    m = cover.load(MODELS / "default.json")
    V, F = m.evaluate()
    exact = m.volume(exact=True)
    assert signed_volume(V, F) == pytest.approx(exact, rel=1e-12)
    (Va, Fa), (Vb, Fb) = m.clip((0, 0, 1, 0.25))
    assert signed_volume(Va, Fa) + signed_volume(Vb, Fb) == pytest.approx(exact, rel=1e-9)
    box = cover.box([0, 0, 0], [1, 1, 1])
    (Va, Fa), (Vb, Fb) = box.clip([0, 0, 1, 0.25])  # quads cut into convex pieces, triangulated
    assert signed_volume(Va, Fa) == pytest.approx(0.75) and signed_volume(Vb, Fb) == pytest.approx(0.25)


def test_evaluate_cells_pieces_sum_to_the_result():
    two = cover.box([0, 0, 0], [2, 2, 2])
    pieces = two.evaluate_cells(2, bounds=(0, 0, 0, 2))
    assert [p["cell"] for p in pieces] == [(i, j, k) for i in range(2) for j in range(2) for k in range(2)]
    for p in pieces:  # full cells are their boxes
        assert p["volume"] == 1 and p["area"] == 6 and p["cap_area"] == 3
        assert signed_volume(p["vertices"], p["faces"]) == pytest.approx(1, rel=1e-12)
    m = cover.box([0, 0, 0], [1, 1, 1]) - cover.sphere([1, 1, 1], 0.7)
    V, F = m.evaluate()
    pieces = m.evaluate_cells(3, threads=1)
    assert sum(p["volume"] for p in pieces) == pytest.approx(signed_volume(V, F), rel=1e-12)
    assert all(p["faces"].dtype == np.int64 and p["faces"].shape[1] == 3 for p in pieces)
    with pytest.raises(cover.InputError):
        m.evaluate_cells(0)
def test_decompose_gives_convex_pieces_summing_to_the_volume():
    m = cover.box([0, 0, 0], [4, 4, 2]) - cover.cylinder([2, 2, -1], [2, 2, 3], 1, segments=12)
    pieces = m.decompose()
    assert len(pieces) > 1
    total = 0.0
    for V, F in pieces:
        assert V.dtype == np.float64 and F.shape[1] == 3
        total += signed_volume(V, F)
        # convex: every vertex on the inner side of every face plane (up to float noise here;
        # the C++ tests check it exactly)
        n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
        side = np.einsum("fk,fvk->fv", n, V[None, :, :] - V[F[:, 0]][:, None, :])
        assert side.max() <= 1e-9
    assert total == pytest.approx(m.volume(exact=True), rel=1e-9)


def test_clip_triangulates_nonconvex_faces():
    path = MODELS / "frame.off"  # a square frame: faces with holes / non-convex polygons
    m = cover.load(path)
    (Va, Fa), (Vb, Fb) = m.clip((0, 0, 1, 1.0))
    assert signed_volume(Va, Fa) + signed_volume(Vb, Fb) == pytest.approx(m.volume(), rel=1e-12)


def test_empty_model():
    e = cover.Model()
    assert e.empty and e.leaves == 0
    assert e.classify([[0, 0, 0]]).tolist() == [0] and e.volume() == 0
    b = cover.box([0, 0, 0], [1, 1, 1])
    assert (e | b).volume() == 1
    with pytest.raises(cover.PreconditionError):
        ~e


@pytest.mark.parametrize("bad, message", [
    (np.zeros((5, 2)), r"points: expected an array of shape \(n, 3\), got shape \(5, 2\)"),
    (np.zeros(3), r"got shape \(3,\)"),
    (np.zeros((2, 3, 1)), r"got shape \(2, 3, 1\)"),
])
def test_wrong_shapes_raise_value_error_naming_argument(bad, message):
    b = cover.box([0, 0, 0], [1, 1, 1])
    with pytest.raises(ValueError, match=message):
        b.classify(bad)
    with pytest.raises(ValueError, match=message.replace("points", "origins")):
        b.first_hits(bad, [1, 0, 0])


def test_wrong_arguments():
    b = cover.box([0, 0, 0], [1, 1, 1])
    with pytest.raises(TypeError):
        b.classify(np.array([["a", "b", "c"]]))
    with pytest.raises(cover.InputError, match="point 1 has a non-finite coordinate"):
        b.classify([[0, 0, 0], [np.nan, 0, 0]])
    with pytest.raises(ValueError, match="threads"):
        b.classify([[0, 0, 0]], threads=-1)
    with pytest.raises(ValueError, match="min: expected 3 numbers"):
        cover.box([0, 0], [1, 1, 1])
    with pytest.raises(cover.InputError, match="min < max"):
        cover.box([0, 0, 0], [0, 1, 1])
    with pytest.raises(cover.InputError, match="radius"):
        cover.sphere([0, 0, 0], -1)
    with pytest.raises(cover.InputError, match="res"):
        b.voxelize(0)
    with pytest.raises(ValueError, match="bounds: expected 4 numbers"):
        b.voxelize(8, bounds=(0, 0, 0))
    with pytest.raises(ValueError, match="plane: expected 4 numbers"):
        b.clip((0, 0, 1))
    with pytest.raises(cover.InputError):
        b.clip((0, 0, 0, 1))
    V, F = box_mesh([0, 0, 0], [1, 1, 1])
    with pytest.raises(cover.InputError, match="vertex index 8 out of range"):
        cover.mesh(V, F + 1)
    with pytest.raises(cover.InputError, match="vertex index -1 out of range"):
        cover.mesh(V, F - 1)
    with pytest.raises(cover.InputError, match="open mesh"):
        cover.mesh(V, F[:-1], closed_only=True)
    with pytest.raises(TypeError, match="integers"):
        cover.mesh(V, F.astype(float))
    with pytest.raises(ValueError, match=r"F: expected an array of shape \(m, 3\)"):
        cover.mesh(V, F[:, :2])


def test_errors_name_the_callers_index_beyond_one_batch():
    b = cover.box([0, 0, 0], [1, 1, 1])
    P = np.zeros((1_100_000, 3))
    P[1_050_000, 2] = np.inf
    with pytest.raises(cover.InputError, match="classify: point 1050000 has"):
        b.classify(P)
    with pytest.raises(cover.InputError, match="windings: point 1050000 has"):
        b.windings(P)
    D = np.ones((300_000, 3))
    D[299_999] = 0
    with pytest.raises(cover.InputError, match="first_hits: ray 299999 has a zero direction"):
        b.first_hits(np.zeros((300_000, 3)), D)


def test_input_errors_are_value_errors():
    assert issubclass(cover.InputError, ValueError)
    assert issubclass(cover.NotComputable, RuntimeError)
    with pytest.raises(ValueError):
        cover.load("/nonexistent/model.off")


def test_results_do_not_depend_on_threads():
    m = cover.load(MODELS / "default.json")
    P = np.random.default_rng(3).uniform(-4, 4, size=(50000, 3))
    assert np.array_equal(m.classify(P, threads=1), m.classify(P, threads=2))
    assert np.array_equal(m.windings(P, threads=1), m.windings(P, threads=2))
    assert np.array_equal(m.voxelize(40, threads=1), m.voxelize(40, threads=2))
    assert m.volume_info(threads=1) == m.volume_info(threads=2)
    assert np.array_equal(m.render(40, 30, threads=1), m.render(40, 30, threads=2))
    h1, h2 = m.first_hits(P[:1000], [0, 0, 1], threads=1), m.first_hits(P[:1000], [0, 0, 1], threads=2)
    assert all(np.array_equal(a, b) for a, b in zip(h1, h2))
    (V1, F1), (V2, F2) = m.evaluate(threads=1), m.evaluate(threads=2)
    assert np.array_equal(V1, V2)
    assert np.array_equal(canonical_triangles(F1), canonical_triangles(F2))


def test_million_points_in_any_layout(bunny_path):
    m = cover.load(bunny_path)
    lo, hi = m.bounds()
    P = np.random.default_rng(11).uniform(lo, hi, size=(1_000_000, 3))
    codes = m.classify(P)  # float64 C-contiguous: viewed in place, no copy
    assert codes.shape == (1_000_000,) and codes.dtype == np.uint8
    assert np.array_equal(codes, m.classify(np.asfortranarray(P)))  # converted once
    readonly = P.copy()
    readonly.flags.writeable = False
    assert np.array_equal(codes, m.classify(readonly))
    P32 = P.astype(np.float32)
    assert np.array_equal(m.classify(P32), m.classify(P32.astype(np.float64)))
    strided = np.zeros((1_000_000, 4))
    strided[:, :3] = P
    assert np.array_equal(codes, m.classify(strided[:, :3]))
    counts = np.bincount(codes, minlength=5)
    assert counts[0] > 0 and counts[1] > 0


def test_float64_c_contiguous_points_are_not_copied(bunny_path):
    """NumPy reports its buffers to tracemalloc: classifying a float64 C-contiguous array
    allocates only the (n,) uint8 result; a Fortran-ordered one is converted once (n x 24 bytes)."""
    m = cover.load(bunny_path)
    lo, hi = m.bounds()
    P = np.random.default_rng(2).uniform(lo, hi, size=(1_000_000, 3))
    m.classify(P[:10])  # BVH built outside the measurement
    F = np.asfortranarray(P)
    peaks = []
    for points in (P, F):
        tracemalloc.start()
        codes = m.classify(points)
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
        del codes
    assert peaks[0] < 2 * P.shape[0]  # the 1 MB result, no 24 MB copy
    assert peaks[1] >= P.nbytes       # the converted copy


def test_ctrl_c_stops_a_long_classification(bunny_path):
    m = cover.load(bunny_path)
    lo, hi = m.bounds()
    P = np.random.default_rng(5).uniform(lo, hi, size=(8_000_000, 3))
    m.classify(P[:1000])  # BVH built before the timer starts
    timer = threading.Timer(0.05, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    finished = False
    start = time.monotonic()
    try:
        with pytest.raises(KeyboardInterrupt):
            m.classify(P, threads=1)
            finished = True
    finally:
        timer.cancel()
    assert not finished, "the kernel ran to its end before the interrupt"
    assert time.monotonic() - start >= 0  # (no timed assertion: the call stopped by raising)


def test_evaluate_cells_refuses_n_over_max_memory_before_evaluating():
    m = cover.box([0, 0, 0], [1, 1, 1]) - cover.sphere([1, 1, 1], 0.5)
    start = time.monotonic()
    with pytest.raises(cover.InputError, match=r"evaluate_cells: n = 2000: the pieces need "
                                               r"23437500 MiB, over max_memory = 4096 MiB"):
        m.evaluate_cells(2000)
    assert time.monotonic() - start < 5  # refused up front: evaluating would take minutes
    block = cover.box([0.1, 0.2, 0.3], [0.9, 0.7, 0.8])
    assert len(block.evaluate_cells(10, max_memory=4)) > 0  # 10^3 cells: 3000 KiB
    with pytest.raises(cover.InputError, match="over max_memory = 4 MiB"):
        m.evaluate_cells(12, max_memory=4)  # 12^3 cells: 5184 KiB
    with pytest.raises(cover.InputError, match="max_memory: expected MiB"):
        m.evaluate_cells(2, max_memory=0)


def test_scale_names_s_and_what_is_wrong():
    b = cover.box([0, 0, 0], [1, 1, 1])
    with pytest.raises(cover.InputError, match=r"s: scale factors \(1e-200, 1e-200, 1e-200\) "
                                               r"multiply volumes by about 1e-600, which "
                                               r"underflows a double"):
        b.scale(1e-200)
    with pytest.raises(cover.InputError, match="overflows a double"):
        b.scale([1e200, 1e200, 1e-10])
    with pytest.raises(cover.InputError, match="s: the y scale factor is 0"):
        b.scale([1, 0, 1])
    with pytest.raises(cover.InputError, match="s: expected finite scale factors"):
        b.scale(np.inf)
    assert b.scale(1e-100).volume() > 0  # small but representable
    with pytest.raises(cover.InputError, match="the determinant, about 1e-600, is beyond"):
        b.transform(np.diag([1e-200, 1e-200, 1e-200, 1.0]))


def test_unbounded_result_raises_not_computable_from_every_brep_kernel():
    m = ~cover.box([0, 0, 0], [1, 1, 1])
    for call in (m.evaluate, m.decompose, lambda: m.clip((0, 0, 1, 0.5)),
                 lambda: m.evaluate_cells(2, bounds=(0, 0, 0, 1)), m.volume, m.bounds):
        with pytest.raises(cover.NotComputable, match="unbounded"):
            call()


def test_voxel_bounds_and_voxelize_name_res():
    b = cover.box([0, 0, 0], [1, 1, 1])
    assert b.voxel_bounds(8192) == b.voxel_bounds(8192)
    with pytest.raises(cover.InputError, match=r"^res: expected a whole number from 1 to 16384"):
        b.voxel_bounds(16385)
    with pytest.raises(cover.InputError, match=r"^res: expected a whole number from 1 to 4096 "
                                               r"\(above, voxelize_brick or cover.dask.voxelize"):
        b.voxelize(8192)


def test_two_python_threads_with_their_own_limits_run_at_once():
    """threads= binds one call (a TBB task arena), not the process: two Python threads with
    threads=1 each hold the kernel at the same time (their wall intervals overlap), and the
    answers equal a single call's. Overlap is checked, not speed."""
    m = cover.load(MODELS / "torus.off")
    P = np.random.default_rng(3).uniform(-3, 3, size=(400_000, 3))
    expected = m.classify(P)
    spans, results = {}, {}

    def work(name):
        start = time.perf_counter()
        results[name] = m.classify(P, threads=1)
        spans[name] = (start, time.perf_counter())

    threads = [threading.Thread(target=work, args=(k,)) for k in ("a", "b")]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    (a0, a1), (b0, b1) = spans["a"], spans["b"]
    assert max(a0, b0) < min(a1, b1), spans  # both were running at once
    assert np.array_equal(results["a"], expected) and np.array_equal(results["b"], expected)


def test_errors_name_python_parameters_and_memory_is_estimated_first():
    m = cover.box([0, 0, 0], [1, 1, 1])
    with pytest.raises(cover.InputError, match=r"voxelize: .* MiB .*over max_memory = 4096 MiB"):
        m.voxelize(4096)  # 64 GiB of bool: refused before numpy allocates anything
    with pytest.raises(cover.InputError, match="max_memory = 1 MiB"):
        m.voxelize_brick(1024, (0, 1024, 0, 1024, 0, 8), max_memory=1)
    assert m.voxelize(8, max_memory=1).sum() > 0
    with pytest.raises(cover.InputError, match=r"^n: expected at least 1"):
        m.evaluate_cells(0)
    with pytest.raises(cover.InputError, match=r"^res: "):
        m.voxelize(5000)
    adaptive, none = m.volume(rays=0), m.volume()
    assert adaptive == none and adaptive.method == none.method  # 0: adaptive, as in C++


def test_non_cubic_grids_equal_the_clis(tmp_path):
    """voxelize(voxel_size=h) and voxelize(dims=...) are the CLI's --voxel-size and --dims grids
    (their .npy, uint8 there), non-cubic; exactly one of res, voxel_size, dims."""
    path = MODELS / "torus.off"
    m = cover.load(path)
    for option, value, kw in (("--dims", "20,12,7", {"dims": (20, 12, 7)}),
                              ("--voxel-size", "0.25", {"voxel_size": 0.25})):
        out = tmp_path / "g.npy"
        r = subprocess.run([str(COVER_BIN), "voxelize", str(path), option, value, "-o", str(out),
                            "--quiet"], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        grid = m.voxelize(**kw)
        assert np.array_equal(np.load(out), grid.astype(np.uint8))
        assert grid.any() and not grid.all()
    assert m.voxelize(dims=(20, 12, 7)).shape == (20, 12, 7)
    with pytest.raises(cover.InputError, match="exactly one"):
        m.voxelize(16, dims=(4, 4, 4))
    with pytest.raises(cover.InputError, match="exactly one"):
        m.voxelize()
    with pytest.raises(cover.InputError, match="^dims: "):
        m.voxelize(dims=(4, 0, 4))
