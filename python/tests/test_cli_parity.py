"""Every method of cover.Model against the CLI on the same inputs: the same classes, voxel grids,
volumes, evaluated meshes, clip halves, pictures and info."""

import numpy as np
import pytest

import cover
from conftest import CGAL_MESHES, MODELS, canonical_triangles, cli_json, read_off, read_png_rgb, run_cli, signed_volume

INPUTS = [MODELS / "default.json", MODELS / "frame.off", MODELS / "torus.off"]


def sample_points(model, n, seed=1):
    """Random points in the result's box (slightly enlarged) plus mesh vertices and box corners."""
    rng = np.random.default_rng(seed)
    lo, hi = model.bounds()
    pad = 0.1 * (hi - lo)
    return rng.uniform(lo - pad, hi + pad, size=(n, 3))


@pytest.mark.parametrize("path", INPUTS, ids=lambda p: p.name)
def test_classify_equals_cli(path, tmp_path):
    model = cover.load(path)
    P = sample_points(model, 20000)
    V, _ = model.evaluate() if path.suffix == ".json" else read_off(path)
    P = np.vstack([P, V[:500]])  # points on the boundary too (vertices)
    points = tmp_path / "points.txt"
    np.savetxt(points, P, fmt="%.17g")
    expected = cli_json("classify", path, "--points", points)["classes"]
    codes = model.classify(P)
    assert codes.dtype == np.uint8 and codes.shape == (len(P),)
    assert [cover.CLASS_NAMES[c] for c in codes] == expected


@pytest.mark.parametrize("path", INPUTS, ids=lambda p: p.name)
def test_voxelize_equals_cli_npy(path, tmp_path):
    model = cover.load(path)
    out = tmp_path / "grid.npy"
    run_cli("voxelize", path, "--res", 48, "-o", out)
    grid = model.voxelize(48)
    assert grid.dtype == np.bool_ and grid.shape == (48, 48, 48)
    assert np.array_equal(grid, np.load(out).astype(bool))


def test_voxelize_bounds_equals_cli(tmp_path):
    path = MODELS / "default.json"
    out = tmp_path / "grid.npy"
    run_cli("voxelize", path, "--res", 40, "--bounds", "-1,-2,-1.5,3", "-o", out)
    grid = cover.load(path).voxelize(40, bounds=(-1, -2, -1.5, 3))
    assert np.array_equal(grid, np.load(out).astype(bool))


def test_voxel_bounds_equal_cli(tmp_path):
    path = MODELS / "default.json"
    report = cli_json("voxelize", path, "--res", 32, "-o", tmp_path / "grid.npy")
    xmin, ymin, zmin, size = cover.load(path).voxel_bounds(32)
    assert [xmin, ymin, zmin] == report["bounds"]["min"] and size == report["bounds"]["size"]
    grid = cover.load(path).voxelize(32)
    assert int(grid.sum()) == report["occupied"]
    assert grid.sum() * (size / 32) ** 3 == pytest.approx(report["volume_estimate"], rel=1e-12)


@pytest.mark.parametrize("path", INPUTS, ids=lambda p: p.name)
def test_volume_equals_cli(path):
    expected = cli_json("volume", path)
    got = cover.load(path).volume_info()
    for key in ("volume", "area", "method", "error_bound"):
        assert got[key] == expected[key], key
    assert cover.load(path).volume() == expected["volume"]


def test_volume_exact_equals_cli():
    path = MODELS / "default.json"
    expected = cli_json("volume", path, "--exact")
    got = cover.load(path).volume_info(exact=True)
    assert (got["volume"], got["area"], got["method"]) == (
        expected["volume"], expected["area"], expected["method"])


@pytest.mark.parametrize("path", INPUTS, ids=lambda p: p.name)
def test_evaluate_equals_cli_off(path, tmp_path):
    out = tmp_path / "result.off"
    run_cli("evaluate", path, "-o", out)
    V, F = cover.load(path).evaluate()
    V_cli, F_cli = read_off(out)
    assert V.dtype == np.float64 and F.dtype == np.int64 and F.shape[1] == 3
    assert np.array_equal(V, V_cli)
    # The same triangles; their order (and first corner) may differ between runs: evaluate()
    # orders a few faces by thread scheduling (seen on default.json; reported, not fixed here).
    assert np.array_equal(canonical_triangles(F), canonical_triangles(F_cli))


@pytest.mark.parametrize("path", INPUTS, ids=lambda p: p.name)
def test_clip_equals_cli(path, tmp_path):
    above_off, below_off = tmp_path / "above.off", tmp_path / "below.off"
    report = cli_json("clip", path, "--plane", "0.2,0.1,1,0.3", "-o", above_off, "--below",
                      below_off, "--triangulate")
    (Va, Fa), (Vb, Fb) = cover.load(path).clip((0.2, 0.1, 1, 0.3))
    for V, F, off, key in ((Va, Fa, above_off, "above"), (Vb, Fb, below_off, "below")):
        V_cli, _ = read_off(off)
        assert np.array_equal(V, V_cli)
        assert F.dtype == np.int64 and F.shape[1] == 3
        assert signed_volume(V, F) == pytest.approx(report[key]["volume"], rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("view", ["iso", "top"])
def test_render_equals_cli_png(view, tmp_path):
    path = MODELS / "default.json"
    out = tmp_path / "image.png"
    run_cli("render", path, "-o", out, "--size", "64x48", "--view", view, "--section", "0,0,1,0")
    image = cover.load(path).render(64, 48, view=view, section=(0, 0, 1, 0))
    assert image.dtype == np.uint8 and image.shape == (48, 64, 3)
    assert np.array_equal(image, read_png_rgb(out))


@pytest.mark.parametrize("path", [MODELS / "default.json", MODELS / "frame.off", MODELS / "snake.json",
                                  MODELS / "warped_part.json", CGAL_MESHES / "bunny00.off"],
                         ids=lambda p: p.name)
def test_info_equals_cli(path):
    if not path.exists():
        pytest.skip(f"missing {path}")
    expected = cli_json("info", path)
    for key in ("input", "seconds", "seconds_detail"):
        expected.pop(key, None)
    assert cover.load(path).info() == expected


@pytest.mark.parametrize("name", ["not_there.off", "bad.json"])
def test_bad_file_message_equals_cli(name, tmp_path):
    path = tmp_path / name
    if name == "bad.json":
        path.write_text('{"union": [{"box": {"min": [0, 0, 0], "max": [1, 1]}}]}')
    r = run_cli("info", path, check=False)
    assert r.returncode == 2
    with pytest.raises(cover.InputError) as e:
        cover.load(path)
    assert isinstance(e.value, ValueError)
    assert r.stderr.strip() == "cover: error: " + str(e.value)
