"""examples/python/tour.ipynb runs top to bottom under nbconvert (Debian python3-nbconvert and
python3-ipykernel) with this interpreter's cover, and shows Models inline."""

import sys

import nbformat
from nbconvert.preprocessors import ExecutePreprocessor

from conftest import SOURCE_DIR

NOTEBOOK = SOURCE_DIR / "examples" / "python" / "tour.ipynb"


def test_tour_notebook_runs_and_displays_models(monkeypatch):
    nb = nbformat.read(NOTEBOOK, as_version=4)
    # The kernel is this interpreter (a venv's python in CI's venv run), with its sys.path.
    monkeypatch.setenv("PYTHONPATH", ":".join(p for p in sys.path if p))
    ExecutePreprocessor(timeout=300, kernel_name="python3").preprocess(
        nb, {"metadata": {"path": str(NOTEBOOK.parent)}})
    outputs = [o for cell in nb.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    pngs = [o for o in outputs if "image/png" in o.get("data", {})]
    assert len(pngs) >= 3  # part, block and the blend display themselves
    text = "".join(o.get("text", "") for o in outputs)
    assert "Monte Carlo" in text and "block.ply" in text and "method='bracket'" in text
