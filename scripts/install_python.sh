#!/usr/bin/env bash
# Installs the Python package `cover` from the build in build/ into Debian's /usr/bin/python3
# (its /usr/local site-packages folder; python/CMakeLists.txt), with sudo when not root. After
# it, `/usr/bin/python3 -c "import cover"` works from any folder.
set -euo pipefail
cd "$(dirname "$0")/.."
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
$sudo cmake --install build --component python
/usr/bin/python3 -c "import cover, sys; sys.stdout.write('python: cover ' + cover.__version__ + ' at ' + cover.__file__ + '\n')"
