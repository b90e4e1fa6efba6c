#!/usr/bin/python3
"""Writes the .vdb test files with the real OpenVDB library.

Debian's python3-openvdb (OpenVDB 10.0.1): `apt-get install python3-openvdb`,
then run with the system Python from this directory:

    /usr/bin/python3 make_test_vdbs.py

Files:
- sphere.vdb: grid "density", a fog sphere of radius 1 (world units) centred
  at (0.5, 0.25, -0.25), voxel size 1/16. Each voxel holds the fraction of
  its cell inside the sphere (4x4x4 supersampling), so the interior is 1 and
  the boundary is anti-aliased; zero voxels are inactive and constant leaves
  are pruned to tiles. Background 0.
- multi.vdb: the same "density" grid, a second float grid "temperature"
  (a 0.5 box, voxel size 0.25, translated) and a vector grid "velocity".
- half.vdb: the sphere saved as half floats.
"""
import numpy as np
import pyopenvdb as vdb

RADIUS = 1.0
CENTER = np.array([0.5, 0.25, -0.25])
VOXEL = 1.0 / 16.0
SUB = 4


def sphere_grid():
    # Voxel (i, j, k) is centred at world CENTER-aligned index points:
    # world = index * VOXEL + OFFSET, with OFFSET chosen so that the centre
    # falls on a voxel corner grid of its own (not symmetric on purpose).
    offset = np.array([0.03, -0.02, 0.01])
    lo = np.floor((CENTER - RADIUS - offset) / VOXEL).astype(int) - 1
    hi = np.ceil((CENTER + RADIUS - offset) / VOXEL).astype(int) + 1
    n = hi - lo + 1
    sub = (np.arange(SUB) + 0.5) / SUB - 0.5  # sub-sample offsets in voxels
    ii = [np.arange(lo[a], hi[a] + 1)[:, None] + sub[None, :] for a in range(3)]
    w = [ii[a] * VOXEL + offset[a] - CENTER[a] for a in range(3)]  # (n_a, SUB)
    d2 = (w[0][:, None, None, :, None, None] ** 2
          + w[1][None, :, None, None, :, None] ** 2
          + w[2][None, None, :, None, None, :] ** 2)
    coverage = (d2 <= RADIUS * RADIUS).mean(axis=(3, 4, 5)).astype(np.float32)
    grid = vdb.FloatGrid(0.0)
    grid.copyFromArray(coverage, ijk=tuple(int(x) for x in lo), tolerance=0)
    grid.prune(0.0)
    transform = vdb.createLinearTransform(voxelSize=VOXEL)
    transform.translate(tuple(offset))
    grid.transform = transform
    grid.name = "density"
    grid.gridClass = vdb.GridClass.FOG_VOLUME
    return grid


def main():
    sphere = sphere_grid()
    vdb.write("sphere.vdb", grids=[sphere])

    temperature = vdb.FloatGrid(0.0)
    temperature.fill((0, 0, 0), (1, 1, 1), 2.0)
    t = vdb.createLinearTransform(voxelSize=0.25)
    t.translate((1.0, 2.0, 3.0))
    temperature.transform = t
    temperature.name = "temperature"
    velocity = vdb.Vec3SGrid()
    velocity.fill((0, 0, 0), (1, 1, 1), (1.0, 0.0, 0.0))
    velocity.name = "velocity"
    vdb.write("multi.vdb", grids=[sphere_grid(), temperature, velocity])

    half = sphere_grid()
    half.saveFloatAsHalf = True
    vdb.write("half.vdb", grids=[half])


if __name__ == "__main__":
    main()
