#!/usr/bin/env bash
# Installs Cover's build and test dependencies from Debian packages.
# Does nothing (no apt call at all) when everything is already present.
set -euo pipefail

packages=(
  build-essential cmake pkg-config clang-format
  libeigen3-dev libtbb-dev
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libgtest-dev libgmock-dev
  nlohmann-json3-dev libcli11-dev libpng-dev liboctomap-dev python3-numpy python3-vtk9
  libtinygltf-dev lib3mf-dev libnanoflann-dev
  pybind11-dev python3-pybind11 python3-dev python3-pytest
  libcgal-demo assimp-testmodels
  zlib1g-dev libopenvdb-dev libboost-iostreams-dev python3-openvdb python3-zarr
  python3-dask python3-distributed python3-nbconvert python3-ipykernel
  libcpp-httplib-dev chromium chromium-driver python3-selenium
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "setup: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
