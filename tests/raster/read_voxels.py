#!/usr/bin/env python3
"""Independent reader for Cover's voxel exports (tests/raster/voxel_io_test.cpp).

Usage: read_voxels.py FILE DUMP

Reads FILE (.npy through numpy.load, .vti through xml.etree + struct, .raw through its
FILE.json sidecar and numpy.fromfile), checks the format's header, and writes the occupancy as
N^3 bytes 0/1 in [x][y][z] order (z fastest) to DUMP. Prints one JSON line:
{"shape": [N, N, N], "sum": S, "origin": [x, y, z] | null, "spacing": h | null}.
Exits with status 1 and a message on stderr when the file is malformed.
"""

import json
import struct
import sys
import xml.etree.ElementTree as ET

import numpy as np


def fail(message):
    sys.stderr.write("read_voxels: " + message + "\n")
    sys.exit(1)


def read_npy(path):
    with open(path, "rb") as f:
        head = f.read(10)
        if head[:8] != b"\x93NUMPY\x01\x00":
            fail("not an NPY 1.0 file")
        (header_len,) = struct.unpack("<H", head[8:10])
        header = f.read(header_len)
        if (10 + header_len) % 64 != 0 or not header.endswith(b"\n"):
            fail("NPY header not padded to 64 bytes / not ended by newline")
    array = np.load(path, allow_pickle=False)
    if array.dtype != np.uint8 or array.ndim != 3:
        fail("expected a 3-D uint8 array, got %s %s" % (array.dtype, array.shape))
    if np.isfortran(array):
        fail("expected C order")
    return array, None, None


def read_vti(path):
    with open(path, "rb") as f:
        data = f.read()
    tag = b'<AppendedData encoding="raw">'
    start = data.find(tag)
    if start < 0:
        fail("no raw AppendedData")
    underscore = data.index(b"_", start + len(tag))
    if data[start + len(tag):underscore].strip() != b"":
        fail("unexpected text before '_'")
    # The XML part without the binary block, closed so that ElementTree can parse it.
    root = ET.fromstring(data[:start] + b"</VTKFile>")
    attrs = root.attrib
    if (root.tag != "VTKFile" or attrs.get("type") != "ImageData" or
            attrs.get("version") != "1.0" or attrs.get("byte_order") != "LittleEndian" or
            attrs.get("header_type") != "UInt64"):
        fail("bad VTKFile attributes %s" % attrs)
    image = root.find("ImageData")
    piece = image.find("Piece")
    extent = [int(v) for v in image.attrib["WholeExtent"].split()]
    if [int(v) for v in piece.attrib["Extent"].split()] != extent:
        fail("Piece Extent differs from WholeExtent")
    if extent[0::2] != [0, 0, 0] or len(set(extent[1::2])) != 1:
        fail("expected extent 0 N 0 N 0 N, got %s" % extent)
    n = extent[1]
    origin = [float(v) for v in image.attrib["Origin"].split()]
    spacing = [float(v) for v in image.attrib["Spacing"].split()]
    if len(origin) != 3 or len(spacing) != 3 or len(set(spacing)) != 1:
        fail("bad Origin/Spacing")
    arrays = piece.find("CellData").findall("DataArray")
    if len(arrays) != 1:
        fail("expected one cell array")
    a = arrays[0].attrib
    if (a.get("Name") != "occupancy" or a.get("type") != "UInt8" or
            a.get("format") != "appended" or a.get("offset") != "0"):
        fail("bad DataArray attributes %s" % a)
    (count,) = struct.unpack("<Q", data[underscore + 1:underscore + 9])
    if count != n ** 3:
        fail("block holds %d bytes, expected %d" % (count, n ** 3))
    begin = underscore + 9
    cells = np.frombuffer(data[begin:begin + count], dtype=np.uint8)
    tail = data[begin + count:].split()
    if tail != [b"</AppendedData>", b"</VTKFile>"]:
        fail("unexpected bytes after the appended block: %r" % data[begin + count:][:80])
    # VTK cell order: x fastest, then y, then z, i.e. C order [z][y][x].
    return cells.reshape((n, n, n)).transpose(2, 1, 0), origin, spacing[0]


def read_raw(path):
    with open(path + ".json") as f:
        meta = json.load(f)
    dims = meta["dims"]
    if (meta["dtype"] != "uint8" or meta["order"] != "xyz (z fastest)" or len(dims) != 3 or
            len(set(dims)) != 1):
        fail("bad sidecar %s" % meta)
    cells = np.fromfile(path, dtype=np.uint8)
    if cells.size != dims[0] * dims[1] * dims[2]:
        fail("file holds %d bytes, sidecar says %s" % (cells.size, dims))
    return cells.reshape(dims), meta["bounds"]["min"], meta["voxel_size"]


def main():
    if len(sys.argv) != 3:
        fail("usage: read_voxels.py FILE DUMP")
    path, dump = sys.argv[1], sys.argv[2]
    if path.lower().endswith(".npy"):
        array, origin, spacing = read_npy(path)
    elif path.lower().endswith(".vti"):
        array, origin, spacing = read_vti(path)
    elif path.lower().endswith(".raw"):
        array, origin, spacing = read_raw(path)
    else:
        fail("unknown extension: " + path)
    if array.size and array.max() > 1:
        fail("values other than 0/1")
    np.ascontiguousarray(array, dtype=np.uint8).tofile(dump)
    print(json.dumps({"shape": list(array.shape), "sum": int(array.sum(dtype=np.int64)),
                      "origin": origin, "spacing": spacing}))


if __name__ == "__main__":
    main()
