"""Point-set leaves: cover.points against the sphere it samples, and against the CLI's scene node
(the same cloud through a .npy file classifies the same)."""

import json

import numpy as np
import pytest

import cover
from conftest import run_cli


def fibonacci(n):
    i = np.arange(n) + 0.5
    z = 1 - 2 * i / n
    r = np.sqrt(1 - z * z)
    a = np.pi * (3 - np.sqrt(5)) * np.arange(n)
    return np.stack([r * np.cos(a), r * np.sin(a), z], axis=1)


@pytest.mark.parametrize("given", [True, False])
def test_points_classify_as_the_sampled_sphere(given):
    P = fibonacci(2000)
    model = cover.points(P, P if given else None)
    Q = np.random.default_rng(5).uniform(-1.5, 1.5, size=(10000, 3))
    r = np.linalg.norm(Q, axis=1)
    off = np.abs(r - 1) > 0.1
    inside = model.classify(Q) != 0
    assert np.array_equal(inside[off], r[off] < 1)


def test_points_equal_the_scene_node(tmp_path):
    P = fibonacci(800)
    np.save(tmp_path / "cloud.npy", np.hstack([P, P]))
    (tmp_path / "scene.json").write_text(json.dumps({"points": {"file": "cloud.npy"}}))
    Q = np.random.default_rng(6).uniform(-1.5, 1.5, size=(3000, 3))
    np.save(tmp_path / "q.npy", Q)
    run_cli("classify", tmp_path / "scene.json", "--points", tmp_path / "q.npy", "--output",
            tmp_path / "c.npy")
    assert np.array_equal(np.load(tmp_path / "c.npy"), cover.points(P, P).classify(Q))
    assert np.array_equal(cover.load(tmp_path / "scene.json").classify(Q), cover.points(P, P).classify(Q))


def test_points_refuses_bad_input():
    with pytest.raises(cover.InputError, match="at least"):
        cover.points(fibonacci(5))
    with pytest.raises(cover.InputError, match="zero"):
        cover.points(fibonacci(100), np.zeros((100, 3)))
    with pytest.raises(cover.InputError, match="neighbours"):
        cover.points(fibonacci(100), neighbours=2)


def test_distance_of_a_box_is_its_signed_distance_function(tmp_path):
    box = cover.box([0, 0, 0], [1, 2, 3])
    Q = np.random.default_rng(8).uniform(-1, 4, size=(2000, 3))
    lo, hi = np.zeros(3), np.array([1.0, 2.0, 3.0])
    outside = np.linalg.norm(np.maximum(np.maximum(lo - Q, Q - hi), 0), axis=1)
    inside = -np.minimum(Q - lo, hi - Q).min(axis=1)
    expected = np.where(outside > 0, outside, inside)
    got = box.distance(Q)
    assert np.allclose(got, expected, rtol=0, atol=1e-12)
    assert box.distance([[0.5, 1, 3]])[0] == 0  # on a face: exactly 0
    np.save(tmp_path / "q.npy", Q)
    box_file = tmp_path / "box.json"
    box_file.write_text(json.dumps({"box": {"min": [0, 0, 0], "max": [1, 2, 3]}}))
    run_cli("distance", box_file, "--points", tmp_path / "q.npy", "--output", tmp_path / "d.npy")
    assert np.array_equal(np.load(tmp_path / "d.npy"), got)
