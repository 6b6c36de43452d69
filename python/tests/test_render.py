"""Model.render's camera (issue 46): up axis, elevation, azimuth, zoom, fit and the tight default
framing, against the CLI's PNGs and the silhouettes' extents."""

import numpy as np
import pytest

import cover
from conftest import MODELS, read_png_rgb, run_cli


def span(image, background=(255, 255, 255)):
    """(rows, cols): the extent (max - min + 1) of the pixels that differ from the background."""
    fg = np.any(image != np.array(background, dtype=np.uint8), axis=2)
    rows, cols = np.flatnonzero(fg.any(axis=1)), np.flatnonzero(fg.any(axis=0))
    if rows.size == 0:
        return 0, 0
    return int(rows[-1] - rows[0] + 1), int(cols[-1] - cols[0] + 1)


TALL_Y = cover.box([-0.2, -1, -0.2], [0.2, 1, 0.2])  # a Y-up model: tall along y


def test_up_y_stands_a_y_up_model_upright():
    rows, cols = span(TALL_Y.render(120, 90, up="y"))
    assert rows > 2 * cols
    rows, cols = span(TALL_Y.render(120, 90))  # z up: it lies
    assert cols > rows


def test_default_scene_fills_the_frame():
    rows, cols = span(cover.load(MODELS / "default.json").render(800, 600))
    assert rows >= 0.8 * 600 and cols <= 800 - 8


def test_zoom_scales_the_silhouette():
    rows, cols = span(TALL_Y.render(120, 90, up="y"))
    assert abs(span(TALL_Y.render(120, 90, up="y", zoom=2))[1] - 2 * cols) <= 2
    half = span(TALL_Y.render(120, 90, up="y", zoom=0.5))
    assert abs(2 * half[0] - rows) <= 2 and abs(2 * half[1] - cols) <= 2


def test_fit_frames_the_kept_part():
    m = cover.load(MODELS / "default.json")
    cut = (1, 0, 0, -0.5)  # keeps x <= -0.5
    rows, cols = span(m.render(200, 150, section=cut))
    assert rows < 0.8 * 150
    rows, cols = span(m.render(200, 150, section=cut, fit=True))
    assert max(rows / 150, cols / 200) >= 0.8


def test_elevation_90_from_the_front_is_the_top_view():
    m = cover.load(MODELS / "default.json")
    assert np.array_equal(m.render(64, 48, view="front", elevation=90), m.render(64, 48, view="top"))


@pytest.mark.parametrize("perspective", [False, True])
def test_camera_keywords_equal_the_cli_flags(perspective, tmp_path):
    path = MODELS / "default.json"
    out = tmp_path / "r.png"
    flags = ["--up", "y", "--elevation", "20", "--azimuth", "33", "--zoom", "1.5",
             "--section", "1,0,0,-0.5", "--fit"] + (["--perspective"] if perspective else [])
    run_cli("render", path, "-o", out, "--size", "64x48", *flags)
    image = cover.load(path).render(64, 48, section=(1, 0, 0, -0.5), perspective=perspective,
                                    up="y", elevation=20, azimuth=33, zoom=1.5, fit=True)
    assert np.array_equal(image, read_png_rgb(out))
    # Deterministic for any thread count.
    assert np.array_equal(image, cover.load(path).render(
        64, 48, section=(1, 0, 0, -0.5), perspective=perspective, up="y", elevation=20,
        azimuth=33, zoom=1.5, fit=True, threads=1))


@pytest.mark.parametrize("samples", [1, 3])
def test_samples_equal_the_cli_flag(samples, tmp_path):
    """samples= is the CLI's --samples: the same pixels; 1 differs from the default 2 only near
    edges (anti-aliasing), and larger values than 4 are refused naming the keyword."""
    path = MODELS / "default.json"
    out = tmp_path / "r.png"
    run_cli("render", path, "-o", out, "--size", "64x48", "--samples", samples)
    image = cover.load(path).render(64, 48, samples=samples)
    assert np.array_equal(image, read_png_rgb(out))
    default = cover.load(path).render(64, 48)
    assert not np.array_equal(image, default)
    same = (image == default).all(axis=2).mean()
    assert 0.5 < same < 1.0  # small image: edges are a large share of it


def test_bad_camera_keywords_name_the_keyword():
    with pytest.raises(cover.InputError, match=r"^up: expected x, y or z, got 'w'$"):
        TALL_Y.render(8, 8, up="w")
    with pytest.raises(cover.InputError, match=r"^zoom: expected a positive number, got 0$"):
        TALL_Y.render(8, 8, zoom=0)
    with pytest.raises(cover.InputError, match=r"^elevation: expected a number from -90 to 90"):
        TALL_Y.render(8, 8, elevation=100)
    with pytest.raises(cover.InputError, match=r"^fit: needs a section$"):
        TALL_Y.render(8, 8, fit=True)
    with pytest.raises(cover.InputError, match=r"^samples: expected a whole number from 1 to 4"):
        TALL_Y.render(8, 8, samples=5)
