"""Shared fixtures of the Python package tests: paths from CMake (ctest sets them; the defaults
fit a build in build/), the CLI runner, and numpy helpers (an independent classification)."""

import json
import os
import pathlib
import signal
import subprocess
import zlib

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("COVER_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
BUILD_DIR = pathlib.Path(os.environ.get("COVER_BUILD_DIR", SOURCE_DIR / "build"))
COVER_BIN = pathlib.Path(os.environ.get("COVER_BIN", BUILD_DIR / "bin" / "cover"))
CGAL_MESHES = pathlib.Path(
    os.environ.get("COVER_CGAL_MESHES", BUILD_DIR / "cgal-data" / "data" / "meshes"))
MODELS = SOURCE_DIR / "models"

# The interrupt tests send SIGINT to this process. A runner started in the background by a
# non-interactive shell inherits SIGINT ignored, and Python then leaves it ignored: install
# Python's own handler so that the signal raises KeyboardInterrupt as Ctrl-C in a terminal does.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


def run_cli(*args, check=True):
    """Runs the cover CLI; returns the CompletedProcess (text)."""
    r = subprocess.run([str(COVER_BIN), *map(str, args)], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise AssertionError(f"cover {' '.join(map(str, args))}: exit {r.returncode}: {r.stderr}")
    return r


def cli_json(*args):
    """The JSON object that `cover ARGS --json` prints."""
    return json.loads(run_cli(*args, "--json").stdout)


def read_off(path):
    """(V float64 (n, 3), F) of an OFF file: F int64 (m, k) when every face has k vertices,
    else a list of index lists."""
    lines = [line.split("#")[0] for line in pathlib.Path(path).read_text().splitlines()]
    words = " ".join(lines).split()
    assert words[0] == "OFF"
    nv, nf = int(words[1]), int(words[2])
    at = 4
    V = np.array(words[at:at + 3 * nv], dtype=np.float64).reshape(nv, 3)
    at += 3 * nv
    faces = []
    for _ in range(nf):
        k = int(words[at])
        faces.append([int(w) for w in words[at + 1:at + 1 + k]])
        at += 1 + k
    if len({len(f) for f in faces}) > 1:
        return V, faces
    return V, np.array(faces, dtype=np.int64).reshape(nf, -1)


def canonical_triangles(F):
    """Triangles rotated to start at their smallest index, rows sorted: equal for two lists of
    the same oriented triangles in any order."""
    F = np.asarray(F)
    r = np.argmin(F, axis=1)
    rows = np.arange(len(F))[:, None]
    G = F[rows, (r[:, None] + np.arange(3)) % 3]
    return G[np.lexsort(G.T[::-1])]


def read_png_rgb(path):
    """uint8 (height, width, 3) of an 8-bit RGB, non-interlaced PNG (the CLI's render output)."""
    data = pathlib.Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    at, idat = 8, b""
    while at < len(data):
        n = int.from_bytes(data[at:at + 4], "big")
        kind, body = data[at + 4:at + 8], data[at + 8:at + 8 + n]
        if kind == b"IHDR":
            width, height = int.from_bytes(body[:4], "big"), int.from_bytes(body[4:8], "big")
            assert body[8] == 8 and body[9] == 2 and body[12] == 0, "8-bit RGB, no interlace"
        elif kind == b"IDAT":
            idat += body
        at += 12 + n
    raw = np.frombuffer(zlib.decompress(idat), dtype=np.uint8).reshape(height, 1 + 3 * width)
    out = np.zeros((height, 3 * width), dtype=np.int32)
    for y in range(height):
        f, line = raw[y, 0], raw[y, 1:].astype(np.int32)
        up = out[y - 1] if y > 0 else np.zeros(3 * width, dtype=np.int32)
        if f == 0:
            out[y] = line
        elif f == 2:
            out[y] = (line + up) % 256
        else:  # sub, average, Paeth: depend on the left pixel, decoded in order
            row = out[y]
            for x in range(3 * width):
                left = row[x - 3] if x >= 3 else 0
                ul = up[x - 3] if x >= 3 else 0
                if f == 1:
                    pred = left
                elif f == 3:
                    pred = (left + up[x]) // 2
                else:
                    p = left + up[x] - ul
                    pa, pb, pc = abs(p - left), abs(p - up[x]), abs(p - ul)
                    pred = left if pa <= pb and pa <= pc else (up[x] if pb <= pc else ul)
                row[x] = (line[x] + pred) % 256
    return out.astype(np.uint8).reshape(height, width, 3)


def signed_volume(V, F):
    """Signed volume of a closed triangle mesh (divergence theorem)."""
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def parity_inside(V, F, P):
    """Inside test by ray parity along a fixed generic direction, in numpy (points off the
    surface, rays through no edge: the direction is irrational enough for the test meshes)."""
    d = np.array([0.5773502691896258, 0.5163977794943222, 0.6324555320336759])
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    e1, e2 = b - a, c - a
    h = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, h)
    inside = np.zeros(len(P), dtype=bool)
    for start in range(0, len(P), 512):
        Q = P[start:start + 512, None, :]
        s = Q - a[None]
        u = np.einsum("pij,ij->pi", s, h) / det
        q = np.cross(s, e1[None])
        v = np.einsum("k,pik->pi", d, q) / det
        t = np.einsum("pik,ik->pi", q, e2) / det
        hits = (u > 0) & (v > 0) & (u + v < 1) & (t > 0)
        inside[start:start + 512] = hits.sum(axis=1) % 2 == 1
    return inside


@pytest.fixture(scope="session")
def bunny_path():
    path = CGAL_MESHES / "bunny00.off"
    if not path.exists():
        pytest.skip(f"missing {path} (extracted from libcgal-demo at configure time)")
    return path

