"""Model.from_bytes validates what it reads as loading validates a file: damaged byte strings
(hand-made non-solids, every truncation, seeded random byte flips) raise cover.InputError naming
the place, or read a valid solid; never a crash (the flips run in a subprocess, so a crash is a
failure, not the end of the test run)."""

import os
import struct
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import cover


def cube_mesh():
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                  [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=np.float64)
    F = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                  [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])
    return V, F


def layout(data):
    """Byte offsets of a one-leaf solid's parts (format in io/serialize.h)."""
    nv, nf, ni, nl, nn = struct.unpack_from("<5Q", data, 12)
    at = 12 + 40 + 4
    out = {"vertices": at}
    at += 24 * nv
    out["face_start"] = at
    at += 4 * (nf + 1)
    out["face_vertices"] = at
    at += 4 * ni
    out["face_leaf"] = at
    at += 4 * nf
    out["face_sign"] = at
    at += nf
    name = struct.unpack_from("<I", data, at)[0]
    at += 4 + name
    origin = struct.unpack_from("<I", data, at)[0]
    at += 4 + origin + 16
    out["flags"] = at
    out.update(nf=nf, ni=ni)
    return out


def with_byte(data, at, value):
    b = bytearray(data)
    b[at] = value
    return bytes(b)


def test_from_bytes_refuses_a_face_with_fewer_than_three_vertices():
    data = cover.mesh(*cube_mesh()).to_bytes()
    at = layout(data)["face_start"] + 4  # face 0 ends after 2 indices, face 1 has 4
    bad = bytearray(data)
    struct.pack_into("<I", bad, at, 2)
    with pytest.raises(cover.InputError, match=r"face 0: 2 vertices \(at least 3 needed\)"):
        cover.Model.from_bytes(bytes(bad))


def test_from_bytes_refuses_a_leaf_flagged_closed_with_a_face_missing():
    V, F = cube_mesh()
    with pytest.warns(UserWarning, match="open mesh"):
        data = cover.mesh(V, F[:-2]).to_bytes()  # open: the face x = 0 missing
    at = layout(data)["flags"]
    assert data[at] == 2
    with pytest.raises(cover.InputError, match=r"leaf 0 \('mesh'\): flagged closed, but its "
                                               r"faces have 4 boundary edge\(s\)"):
        cover.Model.from_bytes(with_byte(data, at, 0))


def test_from_bytes_refuses_a_closed_leaf_flagged_open():
    data = cover.mesh(*cube_mesh()).to_bytes()
    bad = with_byte(data, layout(data)["flags"], 2)  # classify, volume, voxelize crashed on it
    with pytest.raises(cover.InputError, match="flagged open, but its faces are closed"):
        cover.Model.from_bytes(bad)


def test_from_bytes_refuses_an_inside_out_leaf():
    data = cover.mesh(*cube_mesh()).to_bytes()
    lay = layout(data)
    bad = bytearray(data)
    at = lay["face_vertices"]
    idx = np.frombuffer(data, dtype="<u4", count=lay["ni"], offset=at).reshape(-1, 3)
    bad[at:at + 4 * lay["ni"]] = idx[:, ::-1].astype("<u4").tobytes()
    with pytest.raises(cover.InputError, match=r"inside-out \(signed volume -1"):
        cover.Model.from_bytes(bytes(bad))


def test_from_bytes_names_the_byte_offset_of_a_truncation():
    data = cover.box([0, 0, 0], [1, 1, 1]).to_bytes()
    for n in range(len(data)):
        with pytest.raises(cover.InputError, match="not a Cover solid"):
            cover.Model.from_bytes(data[:n])
    with pytest.raises(cover.InputError, match="truncated array at byte 56 of 60"):
        cover.Model.from_bytes(data[:60])
    with pytest.raises(cover.InputError, match=f"trailing bytes at byte {len(data)} of "):
        cover.Model.from_bytes(data + b"\0")


FLIPS = textwrap.dedent("""
    import random, sys
    import numpy as np
    import cover
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                  [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=np.float64)
    F = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                  [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])
    import warnings
    warnings.simplefilter("ignore")
    scene = ((cover.mesh(V, F) - cover.mesh(V[:, [1, 0, 2]] * 0.5 + 0.25, F[:-2]))
             | (cover.box([1.5, 0, 0], [4, 1, 1]) & ~cover.box([-3, 0, -1], [-2, 1, 0]).scale(-1)))
    data = scene.to_bytes()
    P = np.random.default_rng(1).uniform(-0.5, 1.5, (200, 3))
    rng = random.Random(int(sys.argv[1]))
    refused = read = 0
    for trial in range(int(sys.argv[2])):
        b = bytearray(data)
        for _ in range(rng.randint(1, 3)):
            at = rng.randrange(len(b))
            b[at] ^= (1 << rng.randrange(8)) if rng.random() < 0.5 else rng.randint(1, 255)
        if rng.random() < 0.1:
            del b[rng.randrange(len(b)):]
        try:
            m = cover.Model.from_bytes(bytes(b))
        except cover.InputError:
            refused += 1
            continue
        read += 1
        m.classify(P)
        m.windings(P)
        if m.bounded:
            m.volume(rays=8)
            m.voxelize(8)
    print(refused, read)
""")


def test_random_byte_flips_are_refused_or_read_a_valid_solid():
    env = dict(os.environ)
    r = subprocess.run([sys.executable, "-c", FLIPS, "40", "1500"], capture_output=True, text=True,
                       env=env, timeout=600)
    assert r.returncode == 0, f"exit {r.returncode}: {r.stderr[-2000:]}"
    refused, read = map(int, r.stdout.split())
    assert refused > 500 and read > 0
