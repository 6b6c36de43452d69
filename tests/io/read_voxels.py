#!/usr/bin/env python3
"""Independent reader for Cover's voxel exports (tests/io/voxel_io_test.cpp).

Usage: read_voxels.py FILE DUMP

Reads FILE (.npy through numpy.load, .vti through xml.etree + struct, .raw through its
FILE.json sidecar and numpy.fromfile, .zarr through the zarr package, .vdb through pyopenvdb),
checks the format's header, and writes the occupancy as NX*NY*NZ bytes 0/1 in [x][y][z] order
(z fastest) to DUMP. Prints one JSON line:
{"shape": [NX, NY, NZ], "sum": S, "origin": [x, y, z] | null, "spacing": h | null, ...}
(.zarr adds "chunks" and "stored": the chunk files present; .vdb adds "leaves" and "tiles").
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
    if extent[0::2] != [0, 0, 0]:
        fail("expected extent 0 NX 0 NY 0 NZ, got %s" % extent)
    nx, ny, nz = extent[1::2]
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
    if count != nx * ny * nz:
        fail("block holds %d bytes, expected %d" % (count, nx * ny * nz))
    begin = underscore + 9
    cells = np.frombuffer(data[begin:begin + count], dtype=np.uint8)
    tail = data[begin + count:].split()
    if tail != [b"</AppendedData>", b"</VTKFile>"]:
        fail("unexpected bytes after the appended block: %r" % data[begin + count:][:80])
    # VTK cell order: x fastest, then y, then z, i.e. C order [z][y][x].
    return cells.reshape((nz, ny, nx)).transpose(2, 1, 0), origin, spacing[0]


def read_raw(path):
    with open(path + ".json") as f:
        meta = json.load(f)
    dims = meta["dims"]
    if meta["dtype"] != "uint8" or meta["order"] != "xyz (z fastest)" or len(dims) != 3:
        fail("bad sidecar %s" % meta)
    cells = np.fromfile(path, dtype=np.uint8)
    if cells.size != dims[0] * dims[1] * dims[2]:
        fail("file holds %d bytes, sidecar says %s" % (cells.size, dims))
    return cells.reshape(dims), meta["bounds"]["min"], meta["voxel_size"]


def read_zarr(path, extra):
    import os
    import zarr
    with open(os.path.join(path, ".zarray")) as f:
        meta = json.load(f)
    expected = {"zarr_format": 2, "dtype": "|u1", "fill_value": 0, "order": "C", "filters": None,
                "dimension_separator": "."}
    for key, value in expected.items():
        if meta.get(key) != value:
            fail("bad .zarray %s: %r" % (key, meta.get(key)))
    if meta["compressor"].get("id") != "zlib":
        fail("expected the zlib compressor, got %s" % meta["compressor"])
    z = zarr.open(path, mode="r")
    array = z[:]
    if array.dtype != np.uint8:
        fail("expected uint8, got %s" % array.dtype)
    # Chunks whose voxels are all 0 must be absent (fill_value 0); stored ones must hold a 1.
    chunks = meta["chunks"]
    stored = sorted(name for name in os.listdir(path) if not name.startswith("."))
    for name in stored:
        i, j, k = (int(v) for v in name.split("."))
        block = array[i * chunks[0]:(i + 1) * chunks[0], j * chunks[1]:(j + 1) * chunks[1],
                      k * chunks[2]:(k + 1) * chunks[2]]
        if not block.any():
            fail("chunk %s is stored but all 0" % name)
    for i in range(0, array.shape[0], chunks[0]):
        for j in range(0, array.shape[1], chunks[1]):
            for k in range(0, array.shape[2], chunks[2]):
                name = "%d.%d.%d" % (i // chunks[0], j // chunks[1], k // chunks[2])
                if array[i:i + chunks[0], j:j + chunks[1], k:k + chunks[2]].any() and \
                        name not in stored:
                    fail("chunk %s has set voxels but no file" % name)
    attrs = dict(z.attrs)
    extra["chunks"] = chunks
    extra["stored"] = len(stored)
    extra["tie_rule"] = "tie_rule" in attrs
    return array, attrs["origin"], attrs["spacing"]


def read_vdb(path, extra):
    import pyopenvdb as vdb
    grids, _ = vdb.readAll(path)
    if len(grids) != 1 or grids[0].name != "occupancy":
        fail("expected one grid named occupancy, got %s" % [g.name for g in grids])
    grid = grids[0]
    if not isinstance(grid, vdb.BoolGrid):
        fail("expected a BoolGrid, got %s" % type(grid))
    dims = [int(v) for v in grid["cover_dims"]]
    origin = [float(v) for v in grid["cover_origin"]]
    spacing = float(grid["cover_spacing"])
    lo, hi = grid.evalActiveVoxelBoundingBox()
    if grid.activeVoxelCount() and (min(lo) < 0 or any(hi[a] >= dims[a] for a in range(3))):
        fail("active voxels outside [0, dims): %s %s" % (lo, hi))
    # The transform puts index (i, j, k) at the voxel centre origin + (i + 1/2) h.
    for ijk in [(0, 0, 0), (dims[0] - 1, 1, 2)]:
        world = grid.transform.indexToWorld(ijk)
        for a in range(3):
            centre = origin[a] + (ijk[a] + 0.5) * spacing
            if abs(world[a] - centre) > 1e-9 * max(1.0, abs(centre)):
                fail("indexToWorld%s = %s, expected the centre %s" % (ijk, world, centre))
    array = np.zeros(dims, dtype=bool)
    grid.copyToArray(array, ijk=(0, 0, 0))
    if int(array.sum()) != grid.activeVoxelCount():
        fail("%d set voxels but %d active" % (array.sum(), grid.activeVoxelCount()))
    extra["leaves"] = grid.leafCount()
    extra["tiles"] = grid.activeTileCount() if hasattr(grid, "activeTileCount") else None
    return array.astype(np.uint8), origin, spacing


def main():
    if len(sys.argv) != 3:
        fail("usage: read_voxels.py FILE DUMP")
    path, dump = sys.argv[1], sys.argv[2]
    extra = {}
    if path.lower().endswith(".npy"):
        array, origin, spacing = read_npy(path)
    elif path.lower().endswith(".vti"):
        array, origin, spacing = read_vti(path)
    elif path.lower().endswith(".raw"):
        array, origin, spacing = read_raw(path)
    elif path.lower().rstrip("/").endswith(".zarr"):
        array, origin, spacing = read_zarr(path, extra)
    elif path.lower().endswith(".vdb"):
        array, origin, spacing = read_vdb(path, extra)
    else:
        fail("unknown extension: " + path)
    if array.size and array.max() > 1:
        fail("values other than 0/1")
    np.ascontiguousarray(array, dtype=np.uint8).tofile(dump)
    summary = {"shape": list(array.shape), "sum": int(array.sum(dtype=np.int64)),
               "origin": origin, "spacing": spacing}
    summary.update(extra)
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
