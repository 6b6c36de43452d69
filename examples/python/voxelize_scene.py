#!/usr/bin/env python3
"""Voxelizes a mesh or scene into a NumPy .npy grid (bool, [x, y, z]) and prints the grid's
volume estimate next to the solid's volume.

    /usr/bin/python3 examples/python/voxelize_scene.py models/default.json --res 128 -o scene.npy
"""
import argparse
import pathlib

import numpy as np

import cover

ROOT = pathlib.Path(__file__).resolve().parents[2]

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("input", nargs="?", default=ROOT / "models" / "default.json")
parser.add_argument("--res", type=int, default=128, help="voxels per axis")
parser.add_argument("-o", "--output", default="scene.npy", help="output .npy file")
args = parser.parse_args()

model = cover.load(args.input)
grid = model.voxelize(args.res)  # bool (res, res, res), indexed [x, y, z]
xmin, ymin, zmin, size = model.voxel_bounds(args.res)
np.save(args.output, grid)
estimate = grid.sum() * (size / args.res) ** 3
info = model.volume_info()
print(f"{args.output}: {args.res}^3 voxels, {int(grid.sum())} occupied, "
      f"volume estimate {estimate:.6f}")
print(f"volume {info['volume']:.6f} ({info['method']}, error bound {info['error_bound']:.3g})")
