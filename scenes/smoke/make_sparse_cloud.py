#!/usr/bin/python3
"""Writes a sparse cloud for `tyndall bench --only load --vdb FILE` (issue
12's target: a 512³-bounding sparse cloud loads in under 5 s, in memory
proportional to its active voxels) with the real OpenVDB library
(Debian's python3-openvdb 10):

    /usr/bin/python3 scenes/smoke/make_sparse_cloud.py target/tyndall-bench/cloud.vdb

Twelve soft blobs of radius 20 to 60 voxels, scattered (fixed seed) over
index bounds of about 510³ voxels of 0.01, grid "density": a few per cent of
the bounding box is active. Zero voxels stay inactive; constant leaves are
pruned to tiles.
"""
import sys

import numpy as np
import pyopenvdb as vdb

SIDE = 512
rng = np.random.default_rng(7)
grid = vdb.FloatGrid(0.0)
grid.name = "density"
centres = rng.integers(64, SIDE - 64, size=(12, 3))
radii = rng.integers(20, 61, size=12)
# Two blobs of radius 60 in opposite corners span the full 512³ bounds.
centres[0], centres[1] = (60, 60, 60), (SIDE - 61, SIDE - 61, SIDE - 61)
radii[0] = radii[1] = 60
for centre, radius in zip(centres, radii):
    r = int(radius)
    ax = np.arange(-r, r + 1, dtype=np.float32)
    d = np.sqrt(ax[:, None, None] ** 2 + ax[None, :, None] ** 2 + ax[None, None, :] ** 2) / r
    blob = np.clip(1.0 - d, 0.0, None).astype(np.float32) ** 2
    lo = tuple(int(c) - r for c in centre)
    # Add to what earlier blobs left there.
    existing = np.zeros_like(blob)
    grid.copyToArray(existing, ijk=lo)
    grid.copyFromArray(blob + existing, ijk=lo, tolerance=0)
grid.prune(0.0)
grid.transform = vdb.createLinearTransform(voxelSize=0.01)
vdb.write(sys.argv[1], grids=[grid])
print("wrote", sys.argv[1], "active voxels:", grid.activeVoxelCount(),
      "bounds:", grid.evalActiveVoxelBoundingBox())
