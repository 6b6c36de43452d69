#!/usr/bin/env bash
# The pip route of the Python package (docs/python.md "Installing"), as .ci/run checks it: a
# fresh venv made with --system-site-packages (numpy, pytest and the rest from Debian),
# `pip install --no-build-isolation .` reusing the Release build in build/ (COVER_BUILD_DIR),
# `import cover` from the source root resolving to the venv's package, then the pytest suite run
# by the venv's interpreter without PYTHONPATH.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
/usr/bin/python3 -m venv --system-site-packages "$work/venv"
COVER_BUILD_DIR="$root/build" "$work/venv/bin/pip" install --no-build-isolation --no-deps -q .
"$work/venv/bin/python" -c "
import cover, sys
assert cover.__file__.startswith('$work/venv/'), cover.__file__
assert cover.box([0, 0, 0], [1, 2, 3]).volume() == 6.0
print('venv: cover', cover.__version__, 'at', cover.__file__)"
env -u PYTHONPATH PYTHONDONTWRITEBYTECODE=1 COVER_BIN="$root/build/bin/cover" \
  COVER_SOURCE_DIR="$root" COVER_BUILD_DIR="$root/build" \
  COVER_CGAL_MESHES="$root/build/cgal-data/data/meshes" \
  "$work/venv/bin/python" -m pytest -q -p no:cacheprovider python/tests
