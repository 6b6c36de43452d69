"""The build behind `pip install .` (pyproject.toml): the extension `cover._cover` is the CMake
target `cover_python`, built Release with the tests off and copied where setuptools puts
extensions; the package files come from python/cover. COVER_BUILD_DIR names an existing CMake
build folder to reuse (CI builds once); otherwise a fresh one under setuptools' build_temp. The
extension is built for the interpreter running pip (the venv's, which is Debian's python3)."""

import os
import pathlib
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent
VERSION = re.search(r"project\(Cover VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text())[1]


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        given = os.environ.get("COVER_BUILD_DIR")
        build = pathlib.Path(given) if given else pathlib.Path(self.build_temp).resolve() / "cmake"
        if not (build / "CMakeCache.txt").exists():
            subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                            "-DCOVER_BUILD_TESTS=OFF", "-DCOVER_BUILD_PYTHON=ON",
                            f"-DCOVER_PYTHON_EXECUTABLE={sys.executable}"], check=True)
        subprocess.run(["cmake", "--build", str(build), "--target", "cover_python", "-j",
                        str(os.cpu_count() or 2)], check=True)
        built = sorted((build / "python" / "cover").glob("_cover*.so"))
        if not built:
            raise RuntimeError(f"{build}: the CMake build made no cover/_cover*.so")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built[0], target)


setup(
    version=VERSION,
    packages=["cover"],
    package_dir={"cover": "python/cover"},
    package_data={"cover": ["__init__.pyi", "py.typed"]},
    ext_modules=[Extension("cover._cover", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
