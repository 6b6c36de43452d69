"""Cover on a Dask cluster: lazily voxelized grids and classified point clouds (docs/scale-out.md).

``cover.dask.voxelize(source, res)`` is a lazy ``dask.array`` of bool whose every chunk is one
brick of the global grid, computed by a worker with ``Model.voxelize_brick``: the same centres and
tie rule as the whole grid, so the assembled array is bit-identical to ``Model.voxelize(res)``.
``.to_zarr(...)`` then writes it in parallel, one chunk per brick.

The model travels to each worker once: its bytes (``Model.to_bytes()``: the same doubles and the
same expression as on the client) are one key of the task graph that every brick depends on, so
the scheduler ships them to a worker once and the worker keeps them; each worker process builds
the Model from them once (a cache keyed by the bytes' hash) and reuses it, with its BVH, for every
brick and every block of points it computes.
"""

import hashlib
import os
import threading

import numpy as np

import cover

try:
    import dask.array as _da
    from dask.base import tokenize as _tokenize
except ImportError as _error:  # pragma: no cover - dask is optional for the rest of the package
    raise ImportError("cover.dask needs dask (Debian: python3-dask)") from _error

__all__ = ["voxelize", "classify"]

_models = {}  # key (sha256 of the bytes) -> Model, per process
_builds = {}  # key -> how many times this process built it (1: the cache works)
_models_lock = threading.Lock()


def _model(key, payload):
    """The Model of `payload` (its bytes), built once per process and then reused."""
    with _models_lock:
        model = _models.get(key)
        if model is None:
            model = cover.Model.from_bytes(payload)
            _models[key] = model
            _builds[key] = _builds.get(key, 0) + 1
        return model


def _source_bytes(source):
    if isinstance(source, cover.Model):
        return source.to_bytes()
    if isinstance(source, (str, os.PathLike)):
        return cover.load(source).to_bytes()
    raise TypeError(f"source: expected a path or a cover.Model, got {type(source).__name__}")


def _chunk_sizes(n, c):
    return tuple(min(c, n - i) for i in range(0, n, c))


def _brick(payload, key, res, bounds, box):
    (i0, i1), (j0, j1), (k0, k1) = box
    return _model(key, payload).voxelize_brick(res, (i0, i1, j0, j1, k0, k1), bounds=bounds,
                                               threads=1)


def voxelize(source, res, chunks=128, bounds=None):
    """Lazy voxel grid of `source` (a path or a Model): bool (res, res, res) indexed [x, y, z].

    chunks: the brick side (int) or a (cx, cy, cz) tuple; every chunk is one brick computed by a
    worker. bounds: (xmin, ymin, zmin, size) as in Model.voxelize; default: the model's own
    default cube for `res` (computed once, here). Bit-identical to Model.voxelize(res, bounds).
    """
    res = int(res)
    if not 1 <= res <= 16384:
        raise ValueError(f"res: expected 1 to 16384, got {res}")
    if isinstance(chunks, (int, np.integer)):
        chunks = (int(chunks),) * 3
    chunks = tuple(int(c) for c in chunks)
    if len(chunks) != 3 or min(chunks) <= 0:
        raise ValueError(f"chunks: expected a positive int or 3 positive ints, got {chunks}")
    payload = _source_bytes(source)
    key = hashlib.sha256(payload).hexdigest()
    if bounds is None:
        bounds = tuple(float(b) for b in _model(key, payload).voxel_bounds(res))
    else:
        bounds = tuple(float(b) for b in bounds)
        if len(bounds) != 4:
            raise ValueError(f"bounds: expected (xmin, ymin, zmin, size), got {bounds}")
    name = "cover-voxelize-" + _tokenize(key, res, bounds, chunks)
    payload_key = "cover-model-" + key
    sizes = [_chunk_sizes(res, c) for c in chunks]
    graph = {payload_key: payload}
    starts = [np.concatenate([[0], np.cumsum(s)]).astype(int) for s in sizes]
    for bi in range(len(sizes[0])):
        for bj in range(len(sizes[1])):
            for bk in range(len(sizes[2])):
                box = tuple((int(starts[a][b]), int(starts[a][b + 1]))
                            for a, b in enumerate((bi, bj, bk)))
                graph[(name, bi, bj, bk)] = (_brick, payload_key, key, res, bounds, box)
    return _da.Array(graph, name, chunks=tuple(sizes), dtype=bool,
                     meta=np.empty((0, 0, 0), dtype=bool))


def _classify_block(points, payload, key):
    return _model(key, payload).classify(points, threads=1)


def classify(source, points):
    """Lazy classes of a dask array of points (n, 3): uint8 (n,) codes of cover.CLASS_NAMES.

    Each block of rows is classified by a worker with the Model built there once.
    """
    payload = _source_bytes(source)
    key = hashlib.sha256(payload).hexdigest()
    if not isinstance(points, _da.Array):
        points = _da.from_array(np.asarray(points))
    if points.ndim != 2 or points.shape[1] != 3:
        raise ValueError(f"points: expected shape (n, 3), got {points.shape}")
    points = points.rechunk({1: 3})
    from dask import delayed

    shipped = delayed(payload, pure=True, name="cover-model-" + key)
    return _da.map_blocks(_classify_block, points, shipped, key, dtype=np.uint8, drop_axis=1,
                          meta=np.empty((0,), dtype=np.uint8))
