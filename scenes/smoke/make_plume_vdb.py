#!/usr/bin/python3
"""Converts the smoke plume's voxel grid (plume.tgrid) to an OpenVDB file
(plume.vdb) with the real OpenVDB library (Debian's python3-openvdb 10):

    cd scenes/smoke && /usr/bin/python3 make_plume_vdb.py

The .tgrid's 48×80×48 voxels cover the box [-1.2, 1.2]×[0, 4]×[-1.2, 1.2]
(voxel size 0.05); in the VDB, voxel (i, j, k) sits at its centre,
min + 0.05·(i + ½, j + ½, k + ½), so both files hold the same densities at
the same points. Zero voxels are inactive (background 0); constant leaves
are pruned to tiles. scenes/smoke-vdb.toml renders it.
"""
import numpy as np
import pyopenvdb as vdb

VOXEL = 0.05
BOX_MIN = (-1.2, 0.0, -1.2)

with open("plume.tgrid", "rb") as f:
    header = f.readline().split()
    assert header[:2] == [b"tyndall-grid", b"1"], header
    nx, ny, nz = (int(v) for v in header[2:])
    values = np.frombuffer(f.read(), dtype="<f4")
assert values.size == nx * ny * nz
# x fastest in the file: shape (nz, ny, nx) → index [i][j][k].
dense = values.reshape(nz, ny, nx).transpose(2, 1, 0).astype(np.float32).copy()
grid = vdb.FloatGrid(0.0)
grid.copyFromArray(dense, ijk=(0, 0, 0), tolerance=0)
grid.prune(0.0)
transform = vdb.createLinearTransform(voxelSize=VOXEL)
transform.translate(tuple(m + 0.5 * VOXEL for m in BOX_MIN))
grid.transform = transform
grid.name = "density"
grid.gridClass = vdb.GridClass.FOG_VOLUME
vdb.write("plume.vdb", grids=[grid])
print("active voxels", grid.activeVoxelCount(), "leaves", grid.leafCount())
