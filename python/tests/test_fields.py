"""Field leaves from Python (docs/cli.md "Field leaves and blends"): the same classes, field values,
volumes and pictures as the CLI, and the exact answers the mathematics gives."""

import numpy as np
import pytest

import cover
from conftest import MODELS, cli_json, read_png_rgb, run_cli

SNAKE = MODELS / "snake.json"

TWO_POINTS = """{"blend": [
  {"field": {"skeleton": {"point": [-0.35, 0, 0]}, "radius": 0.5, "influence": 1}},
  {"field": {"skeleton": {"point": [0.35, 0, 0]}, "radius": 0.5, "influence": 1}}]}"""


def test_snake_classify_equals_cli(tmp_path):
    model = cover.load(SNAKE)
    rng = np.random.default_rng(4)
    lo, hi = model.bounds()
    P = rng.uniform(lo, hi, size=(20000, 3))
    points = tmp_path / "points.txt"
    np.savetxt(points, P, fmt="%.17g")
    report = cli_json("classify", SNAKE, "--points", points)
    codes, uncertain = model.classify_counted(P)
    assert [cover.CLASS_NAMES[c] for c in codes] == report["classes"]
    assert uncertain == report["uncertain"]
    assert np.array_equal(model.classify(P), codes)
    assert (codes == 1).sum() > 1000


def test_field_values_equal_cli(tmp_path):
    scene = tmp_path / "two.json"
    scene.write_text(TWO_POINTS)
    P = np.array([[0.85, 0, 0], [0, 0, 0], [0.2, 0.3, -0.1]])
    points = tmp_path / "points.txt"
    np.savetxt(points, P, fmt="%.17g")
    report = cli_json("field", scene, "--points", points)
    f, g = cover.load(scene).field(P)
    assert f.shape == (3, 1) and g.shape == (3, 1, 3)
    assert f[:, 0].tolist() == report["field"]
    assert g[:, 0, :].tolist() == report["gradient"]
    assert f[0, 0] == 0.5625  # exactly the threshold: (0.85, 0, 0) is on the surface
    assert cover.CLASS_NAMES[cover.load(scene).classify(P)[0]] == "face"


def test_bracket_volume_equals_cli():
    model = cover.load(SNAKE)
    info = model.volume_info(tolerance=0.1)
    report = cli_json("volume", SNAKE, "--tolerance", 0.1)
    assert info["method"] == "bracket" == report["method"]
    assert info["volume"] == report["volume"] and info["error_bound"] == report["error_bound"]
    assert info["target_met"]


def test_ball_bracket_contains_its_volume(tmp_path):
    scene = tmp_path / "ball.json"
    scene.write_text('{"field": {"skeleton": {"point": [0, 0, 0]}, "radius": 0.5, "influence": 1}}')
    info = cover.load(scene).volume_info()
    assert abs(info["volume"] - 4 / 3 * np.pi * 0.125) <= info["error_bound"]
    assert info["error_bound"] <= 1e-2 * info["volume"]


def test_render_equals_cli(tmp_path):
    out = tmp_path / "snake.png"
    run_cli("render", SNAKE, "-o", out, "--size", "96x64")
    image = cover.load(SNAKE).render(96, 64)
    assert np.array_equal(image, read_png_rgb(out))


def test_what_does_not_take_fields_refuses():
    with pytest.raises(cover.InputError):
        cover.load(MODELS / "default.json").field([[0, 0, 0]])


def test_evaluate_and_polygonize_take_fields(tmp_path):
    model = cover.load(SNAKE)
    V, F = model.evaluate(mesh_resolution=32)
    assert F.shape[1] == 3 and len(F) > 1000
    out = tmp_path / "snake.off"
    run_cli("evaluate", SNAKE, "-o", out, "--mesh-resolution", "32")
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6
    assert cover.load(out).volume(exact=True) == pytest.approx(volume, rel=1e-9)
    V2, F2, report = model.polygonize(resolution=24, tolerance=1e-6)
    assert report["tolerance"] <= 1e-6 and report["cell_size"] > 0 and len(F2) > 100
    # Every vertex is within the tolerance of the surface: a step of 2·tolerance along ±x, ±y
    # or ±z changes the class for almost every vertex (the surface is oblique elsewhere).
    step = 2 * report["tolerance"]
    probes = np.concatenate([V2 + s * step * np.eye(3)[k] for k in range(3) for s in (-1, 1)])
    inside = (model.classify(probes) != 0).reshape(6, -1)
    changed = inside.any(axis=0) & ~inside.all(axis=0)
    assert changed.mean() > 0.9
    with pytest.raises(cover.InputError):
        model.polygonize(resolution=1)
    with pytest.raises(cover.InputError):
        model.polygonize(cell_size=-1.0)


def test_pickle_keeps_field_leaves():
    import pickle

    model = cover.load(SNAKE)
    back = pickle.loads(pickle.dumps(model))
    P = np.random.default_rng(2).uniform(-3, 3, size=(5000, 3))
    assert np.array_equal(back.classify(P), model.classify(P))
    assert back.info() == model.info()


def test_octree_of_field_leaves_equals_cli(tmp_path):
    out = tmp_path / "snake.json"
    report = cli_json("octree", SNAKE, "--depth", 5, "-o", out)
    leaves = report["leaves"]
    assert leaves["full"] > 0 and leaves["empty"] > 0 and leaves["partial"] > 0


def test_mesh_skeleton_alone_is_the_mesh_and_blends_round_it(tmp_path):
    """A mesh skeleton alone classifies as its mesh does (surface points `face`); blended with a
    point it grows near the point only; the CLI agrees and a bad mesh is an InputError naming
    the scene and the node."""
    torus = MODELS / "torus.off"
    alone = tmp_path / "alone.json"
    alone.write_text('{"field": {"skeleton": {"mesh": "%s"}, "radius": 0.1, "influence": 0.3}}'
                     % torus)
    blend = tmp_path / "blend.json"
    blend.write_text('{"blend": [{"field": {"skeleton": {"mesh": "%s"}, "radius": 0.1, '
                     '"influence": 0.3}}, {"field": {"skeleton": {"point": [1.2, 0, 0.3]}, '
                     '"radius": 0.1, "influence": 0.3}}]}' % torus)
    mesh = cover.load(torus)
    lo, hi = cover.load(alone).bounds()
    P = np.random.default_rng(7).uniform(lo, hi, size=(20000, 3))
    a, m = cover.load(alone).classify(P), mesh.classify(P)
    assert np.array_equal(a, np.where(m >= 2, 2, m))
    assert (a == 1).sum() > 1000
    b = cover.load(blend).classify(P)
    grown = (b == 1) & (a == 0)
    assert grown.sum() > 0 and (b[a == 1] == 1).all()
    assert (np.linalg.norm(P[grown] - [1.2, 0, 0.3], axis=1) < 0.3 + 0.2).all()
    points = tmp_path / "points.txt"
    np.savetxt(points, P[:2000], fmt="%.17g")
    report = cli_json("classify", blend, "--points", points)
    assert [cover.CLASS_NAMES[c] for c in b[:2000]] == report["classes"]
    info = cover.load(alone).info()
    prim = [leaf for leaf in info["leaves_info"] if leaf["kind"] == "field"][0]["primitives"][0]
    assert prim["skeleton"] == "mesh" and prim["triangles"] > 0
    (tmp_path / "open.off").write_text("OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n")
    bad = tmp_path / "bad.json"
    bad.write_text('{"field": {"skeleton": {"mesh": "open.off"}, "radius": 0.1, "influence": 0.3}}')
    with pytest.raises(cover.InputError, match=r"bad\.json.*/field.*not closed"):
        cover.load(bad)
    r = run_cli("info", bad, check=False)
    assert r.returncode == 2 and "not closed" in r.stderr and r.stderr.count("\n") == 1


def test_scene_from_a_dict_equals_the_scene_file(tmp_path):
    """cover.scene takes the dict a scene file holds: the same Model as cover.load of that file
    (classes equal at random points), relative paths against base, errors naming the node."""
    import json
    snake = json.loads(SNAKE.read_text())
    from_dict = cover.scene(snake, base=SNAKE.parent)
    from_file = cover.load(SNAKE)
    P = np.random.default_rng(9).uniform(*from_file.bounds(), size=(20000, 3))
    assert np.array_equal(from_dict.classify(P), from_file.classify(P))
    assert np.array_equal(cover.scene(json.dumps(snake), base=SNAKE.parent).classify(P),
                          from_dict.classify(P))
    blend = cover.scene(json.loads(TWO_POINTS))
    assert blend.classify([[0.85, 0, 0]])[0] == 2  # exactly on the surface: face
    with pytest.raises(cover.InputError, match=r"<scene>: /blend/1/field.*influence"):
        cover.scene({"blend": [json.loads(TWO_POINTS)["blend"][0],
                               {"field": {"skeleton": {"point": [0, 0, 0]}, "radius": 0.5}}]})
