"""Warp leaves from Python (docs/cli.md "Warps: twist, taper, bend"): the same classes, uncertain
counts, volumes, pictures and field values as the CLI, and the exact answers of a taper."""

import pickle

import numpy as np

import cover
from conftest import MODELS, cli_json, read_png_rgb, run_cli

PART = MODELS / "warped_part.json"

TAPERED_BOX = """{"taper": {"axis": {"direction": [0, 1, 0]}, "range": [-0.5, 0.5],
  "scale": [1, 0.5], "child": {"box": {"min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]}}}}"""


def test_part_classify_equals_cli(tmp_path):
    model = cover.load(PART)
    rng = np.random.default_rng(7)
    lo, hi = model.bounds()
    P = rng.uniform(lo, hi, size=(20000, 3))
    points = tmp_path / "points.txt"
    np.savetxt(points, P, fmt="%.17g")
    report = cli_json("classify", PART, "--points", points)
    codes, uncertain = model.classify_counted(P)
    assert [cover.CLASS_NAMES[c] for c in codes] == report["classes"]
    assert uncertain == report["uncertain"]
    assert uncertain <= 20
    assert (codes == 1).sum() > 500


def test_tapered_box_is_exact(tmp_path):
    scene = tmp_path / "taper.json"
    scene.write_text(TAPERED_BOX)
    # y = 0: s = 3/4, so x = 0.375 is on the side face exactly (z = 0.09375 maps to 0.125);
    # y = 0.25: s = 5/8.
    P = np.array([[0.375, 0, 0.09375], [0.374, 0, 0.1], [0.376, 0, 0.1], [0.3125, 0.25, 0.3125]])
    codes, uncertain = cover.load(scene).classify_counted(P)
    assert [cover.CLASS_NAMES[c] for c in codes] == ["face", "inside", "outside", "face"]
    assert uncertain == 0
    info = cover.load(scene).volume_info(tolerance=0.02)
    assert abs(info["volume"] - (9 / 16 + 1 / 48)) <= info["error_bound"]


def test_part_render_equals_cli(tmp_path):
    out = tmp_path / "part.png"
    run_cli("render", PART, "-o", out, "--size", "64x48")
    image = cover.load(PART).render(64, 48)
    assert np.array_equal(image, read_png_rgb(out))
    assert (image.reshape(-1, 3).sum(axis=1) > 0).sum() > 300


def test_twisted_field_values_equal_cli(tmp_path):
    scene = tmp_path / "twist.json"
    scene.write_text("""{"twist": {"axis": {"direction": [0, 0, 1]}, "degrees_per_unit": 90,
      "child": {"field": {"skeleton": {"segment": [[0.3, 0, -1], [0.3, 0, 1]]},
                          "radius": 0.2, "influence": 0.5}}}}""")
    P = np.array([[0, 0.3, 1], [0.1, 0.25, 0.5], [2, 2, 2]])
    points = tmp_path / "points.txt"
    np.savetxt(points, P, fmt="%.17g")
    report = cli_json("field", scene, "--points", points)
    f, g = cover.load(scene).field(P)
    assert f[:, 0].tolist() == report["field"]
    assert g[:, 0, :].tolist() == report["gradient"]
    assert abs(f[0, 0] - 1) < 1e-12 and f[2, 0] == 0


def test_pickled_part_classifies_the_same():
    model = cover.load(PART)
    back = pickle.loads(pickle.dumps(model))
    rng = np.random.default_rng(3)
    lo, hi = model.bounds()
    P = rng.uniform(lo, hi, size=(5000, 3))
    assert np.array_equal(back.classify(P), model.classify(P))
