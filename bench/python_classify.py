#!/usr/bin/env python3
"""Python call time of Model.classify against the C++ kernel time of the same classification.

1,000,000 uniform random points in bunny00's box (libcgal-demo), classified with 2 threads:
  python cold  cover.load() then one Model.classify() call: the call includes the BVH build,
               like the CLI's kernel time;
  python warm  a second call on the same Model (BVH already built);
  C++ kernel   `cover classify bunny00.off --points P.txt --threads 2 --json`, its
               seconds_detail.kernel: BVH build + Model::classify over the same points (the
               text parsing is its `load` time, not counted).
Median of --repeat runs each, Python and CLI alternating. Run from the repository root after the build:

    PYTHONPATH=build/python /usr/bin/python3 bench/python_classify.py
"""
import argparse
import json
import pathlib
import statistics
import subprocess
import tempfile
import time

import numpy as np

import cover

ROOT = pathlib.Path(__file__).resolve().parents[1]
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--model", default=ROOT / "build/cgal-data/data/meshes/bunny00.off")
parser.add_argument("--cover", default=ROOT / "build/bin/cover", help="the CLI")
parser.add_argument("--points", type=int, default=1_000_000)
parser.add_argument("--threads", type=int, default=2)
parser.add_argument("--repeat", type=int, default=11)
args = parser.parse_args()

model = cover.load(args.model)
lo, hi = model.bounds()
P = np.random.default_rng(1).uniform(lo, hi, size=(args.points, 3))

# Python and CLI runs alternate, so that both see the same machine load.
cold, warm, kernel = [], [], []
with tempfile.TemporaryDirectory() as tmp:
    points = pathlib.Path(tmp) / "points.txt"
    np.savetxt(points, P, fmt="%.17g")
    for _ in range(args.repeat):
        fresh = cover.load(args.model)
        t0 = time.perf_counter()
        codes = fresh.classify(P, threads=args.threads)
        t1 = time.perf_counter()
        fresh.classify(P, threads=args.threads)
        t2 = time.perf_counter()
        cold.append(t1 - t0)
        warm.append(t2 - t1)
        r = subprocess.run([str(args.cover), "classify", str(args.model), "--points", str(points),
                            "--threads", str(args.threads), "--json"],
                           capture_output=True, text=True, check=True)
        report = json.loads(r.stdout)
        kernel.append(report["seconds_detail"]["kernel"])
        assert [cover.CLASS_NAMES[c] for c in codes] == report["classes"]

c, w, k = statistics.median(cold), statistics.median(warm), statistics.median(kernel)
print(f"{args.points} points, {pathlib.Path(args.model).name}, threads={args.threads}, "
      f"median of {args.repeat}")
print(f"python cold (BVH + classify)  {c * 1e3:8.1f} ms   {c / k:5.2f}x the C++ kernel")
print(f"python warm (classify)        {w * 1e3:8.1f} ms")
print(f"C++ kernel (cover classify)   {k * 1e3:8.1f} ms")
