"""The scripts in examples/python/ run and write what they say."""

import json
import subprocess
import sys

import numpy as np

import cover
from conftest import MODELS, SOURCE_DIR

EXAMPLES = SOURCE_DIR / "examples" / "python"


def run(script, *args, cwd):
    r = subprocess.run([sys.executable, str(EXAMPLES / script), *map(str, args)], cwd=cwd,
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r.stdout


def test_voxelize_scene(tmp_path):
    out = run("voxelize_scene.py", MODELS / "default.json", "--res", 64, "-o", "scene.npy",
              cwd=tmp_path)
    grid = np.load(tmp_path / "scene.npy")
    assert np.array_equal(grid, cover.load(MODELS / "default.json").voxelize(64))
    assert f"{int(grid.sum())} occupied" in out and "volume estimate" in out


def test_classify_cloud(tmp_path):
    out = run("classify_cloud.py", MODELS / "torus.off", "--points", 200000, "-o", "counts.json",
              cwd=tmp_path)
    result = json.loads((tmp_path / "counts.json").read_text())
    assert sum(result["counts"].values()) == 200000
    volume = cover.load(MODELS / "torus.off").volume()
    assert abs(result["volume_estimate"] - volume) < 0.05 * volume
    assert "Monte Carlo volume" in out
