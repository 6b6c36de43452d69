#!/usr/bin/python3
"""cover.dask.voxelize on a dask.distributed LocalCluster with 1 and with 2 worker processes.

Usage: PYTHONPATH=build/python bench/dask_voxelize.py MESH_OR_SCENE [--res 2048] [--chunks 256]
       [--rounds 3]

Each round, for 1 and then 2 workers (one thread each): the time to compute every brick of the
res³ grid and reduce it to its voxel count (np.count_nonzero per brick on the worker, then a sum:
every brick is computed by a worker and never gathered, as a `.to_zarr` would do it), cluster
start-up excluded. Rounds interleave the
two settings (this machine is noisy); the median of each and the speed-up are printed, and the
counts must agree.
"""
import argparse
import statistics
import time

import distributed
import numpy as np

import cover
import cover.dask


def run(path, res, chunks, workers):
    cluster = distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                       dashboard_address=None, silence_logs=40)
    with distributed.Client(cluster) as client:
        client.run(lambda: None)  # workers up
        start = time.perf_counter()
        lazy = cover.dask.voxelize(path, res, chunks=chunks if len(chunks) == 3 else chunks[0])
        per_brick = lazy.map_blocks(lambda b: np.full((1, 1, 1), np.count_nonzero(b)),
                                    chunks=(1, 1, 1), dtype=np.int64)
        count = int(per_brick.sum().compute())
        seconds = time.perf_counter() - start
    cluster.close()
    return seconds, count


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("source")
    ap.add_argument("--res", type=int, default=2048)
    ap.add_argument("--chunks", type=lambda t: tuple(int(x) for x in t.split(",")), default=(256,),
                    help="brick side, or cx,cy,cz")
    ap.add_argument("--rounds", type=int, default=3)
    a = ap.parse_args()
    times = {1: [], 2: []}
    counts = set()
    for r in range(a.rounds):
        for w in (1, 2):
            s, c = run(a.source, a.res, a.chunks, w)
            times[w].append(s)
            counts.add(c)
            print(f"round {r}: {w} worker(s) {s:.2f} s, {c} voxels", flush=True)
    assert len(counts) == 1, counts
    m1, m2 = statistics.median(times[1]), statistics.median(times[2])
    print(f"median: 1 worker {m1:.2f} s, 2 workers {m2:.2f} s, speed-up {m1 / m2:.2f}x "
          f"({a.res}^3, chunks {a.chunks}, {cover.__version__})")


if __name__ == "__main__":
    main()
