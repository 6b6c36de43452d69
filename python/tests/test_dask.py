"""cover.dask on a dask.distributed LocalCluster of two worker processes: lazily voxelized grids
bit-identical to Model.voxelize (ragged edge chunks included), written to Zarr in parallel; point
classes equal to Model.classify; the model shipped once per worker; bricks and pickles."""

import pickle

import numpy as np
import pytest

import cover

dask = pytest.importorskip("dask")
distributed = pytest.importorskip("distributed")
zarr = pytest.importorskip("zarr")
import cover.dask  # noqa: E402  (needs dask)

from conftest import MODELS  # noqa: E402


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None, silence_logs=40)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


@pytest.fixture(scope="module")
def scene():
    return cover.load(MODELS / "default.json")


def test_pickle_and_bytes_round_trip(scene):
    points = np.random.default_rng(3).uniform(-4, 5, (20000, 3))
    back = pickle.loads(pickle.dumps(scene))
    assert np.array_equal(back.classify(points), scene.classify(points))
    assert cover.Model.from_bytes(scene.to_bytes()).leaves == scene.leaves
    with pytest.raises(cover.InputError):
        cover.Model.from_bytes(b"not a solid")


def test_bricks_equal_the_whole_grid(scene):
    whole = scene.voxelize(40)
    rng = np.random.default_rng(5)
    for _ in range(25):
        lo = rng.integers(0, 40, 3)
        hi = lo + rng.integers(1, 41 - lo)
        box = (lo[0], hi[0], lo[1], hi[1], lo[2], hi[2])
        brick = scene.voxelize_brick(40, box)
        assert np.array_equal(brick, whole[lo[0]:hi[0], lo[1]:hi[1], lo[2]:hi[2]]), box
    with pytest.raises(cover.InputError):
        scene.voxelize_brick(40, (0, 41, 0, 1, 0, 1))
    with pytest.raises(cover.InputError):
        scene.voxelize_brick(40, (3, 3, 0, 1, 0, 1))


@pytest.mark.parametrize("chunks", [16, (20, 12, 48)])
def test_voxelize_on_two_workers_is_bit_identical(client, scene, chunks):
    lazy = cover.dask.voxelize(MODELS / "default.json", 48, chunks=chunks)
    assert lazy.shape == (48, 48, 48) and lazy.dtype == bool
    assert np.array_equal(lazy.compute(), scene.voxelize(48))
    # A Model as the source, explicit bounds.
    bounds = (-5.0, -4.0, -4.5, 10.0)
    lazy = cover.dask.voxelize(scene, 30, chunks=7, bounds=bounds)
    assert np.array_equal(lazy.compute(), scene.voxelize(30, bounds))


def test_the_model_travels_to_each_worker_once(client, scene):
    lazy = cover.dask.voxelize(scene, 32, chunks=8)  # 64 bricks
    graph = dict(lazy.__dask_graph__())
    payloads = [k for k in graph if isinstance(k, str) and k.startswith("cover-model-")]
    assert len(payloads) == 1
    assert lazy.compute().sum() == scene.voxelize(32).sum()
    # Each worker process built this Model from the shipped bytes once, however many of the 64
    # bricks it computed.
    import hashlib

    key = hashlib.sha256(scene.to_bytes()).hexdigest()
    builds = client.run(lambda: dict(__import__("cover.dask").dask._builds))
    assert len(builds) == 2
    assert all(b.get(key, 0) <= 1 for b in builds.values())
    assert sum(b.get(key, 0) for b in builds.values()) >= 1


def test_to_zarr_in_parallel(client, scene, tmp_path):
    lazy = cover.dask.voxelize(scene, 40, chunks=16)
    lazy.to_zarr(str(tmp_path / "grid.zarr"))
    stored = zarr.open(str(tmp_path / "grid.zarr"), mode="r")
    assert stored.shape == (40, 40, 40)
    assert np.array_equal(stored[:], scene.voxelize(40))


def test_classify_a_dask_array_of_points(client, scene):
    import dask.array as da

    points = np.random.default_rng(9).uniform(-4, 5, (30000, 3))
    lazy = cover.dask.classify(scene, da.from_array(points, chunks=(7000, 3)))
    assert lazy.dtype == np.uint8 and lazy.shape == (30000,)
    assert np.array_equal(lazy.compute(), scene.classify(points))


def test_bad_arguments(scene):
    with pytest.raises(ValueError):
        cover.dask.voxelize(scene, 32, chunks=0)
    with pytest.raises(ValueError):
        cover.dask.voxelize(scene, 0)
    with pytest.raises(TypeError):
        cover.dask.voxelize(42, 32)
    with pytest.raises(ValueError):
        cover.dask.classify(scene, np.zeros((4, 2)))


def test_voxelize_beyond_4096_without_bounds_is_bricks_of_the_default_cube():
    # Model.voxelize stops at 4096; the lazy grid goes to 16384 (only bricks are held).
    m = cover.box([0, 0, 0], [1, 2, 3]) - cover.sphere([1, 2, 3], 0.5)
    lazy = cover.dask.voxelize(m, 8192, chunks=2048)
    assert lazy.shape == (8192, 8192, 8192) and lazy.numblocks == (4, 4, 4)
    task = lazy.dask[(lazy.name, 1, 2, 3)]
    bounds, box = task[4], task[5]
    assert bounds == m.voxel_bounds(8192)
    assert box == ((2048, 4096), (4096, 6144), (6144, 8192))
    small = (2048, 2058, 4096, 4100, 6144, 6150)
    brick = cover.dask._brick(m.to_bytes(), "key-test", 8192, bounds,
                              ((2048, 2058), (4096, 4100), (6144, 6150)))
    assert np.array_equal(brick, m.voxelize_brick(8192, small))
    with pytest.raises(ValueError, match="res: expected 1 to 16384"):
        cover.dask.voxelize(m, 16385)
