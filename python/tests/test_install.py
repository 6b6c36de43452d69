"""`cmake --install build --component python` puts an importable package into the
interpreter's site directory (here under a DESTDIR), and a plain install of the C++ package
does not touch Python's directories."""

import os
import pathlib
import shutil
import subprocess
import sys

import pytest

from conftest import BUILD_DIR

CMAKE = shutil.which("cmake")
SITE = os.environ.get("COVER_PYTHON_INSTALL_DIR")


@pytest.mark.skipif(CMAKE is None or SITE is None, reason="needs cmake and the ctest environment")
def test_component_install_is_importable_from_any_folder(tmp_path):
    dest = tmp_path / "root"
    env = dict(os.environ, DESTDIR=str(dest))
    subprocess.run([CMAKE, "--install", str(BUILD_DIR), "--component", "python"], env=env,
                   check=True, capture_output=True)
    site = dest / pathlib.Path(SITE).relative_to("/")
    assert (site / "cover" / "__init__.pyi").exists() and (site / "cover" / "py.typed").exists()
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(site)
    r = subprocess.run([sys.executable, "-c", "import cover; print(cover.__file__, "
                        "cover.box([0, 0, 0], [1, 2, 3]).volume())"],
                       cwd=elsewhere, env=env, capture_output=True, text=True, check=True)
    where, volume = r.stdout.split()
    assert pathlib.Path(where).is_relative_to(site) and float(volume) == 6.0


def test_site_directory_is_on_the_interpreters_path():
    if SITE is None:
        pytest.skip("needs the ctest environment")
    r = subprocess.run([sys.executable, "-S", "-c", "import site, sys; site.main(); print(sys.path)"],
                       env={}, capture_output=True, text=True, check=True)
    assert SITE in r.stdout


@pytest.mark.skipif(CMAKE is None, reason="needs cmake")
def test_plain_install_leaves_python_alone(tmp_path):
    dest = tmp_path / "root"
    env = dict(os.environ, DESTDIR=str(dest))
    subprocess.run([CMAKE, "--install", str(BUILD_DIR), "--prefix", str(tmp_path / "prefix")],
                   env=env, check=True, capture_output=True)
    assert not list(dest.rglob("_cover*")) and not list((tmp_path / "prefix").rglob("_cover*"))
