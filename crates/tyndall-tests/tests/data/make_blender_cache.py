#!/usr/bin/python3
"""Writes blender_cache/data/fluid_data_000{1,2}.vdb: two frames of a
smoke cache laid out as Blender's fluid domain writes one (Cache → type
All, format OpenVDB, precision "16": half floats), with the grids Blender
writes — `density`, `flame`, `heat`, `temperature`, a vec3 `velocity`,
empty `color_r`/`color_g`/`color_b` and a constant `shadow` — for the
frame-sequence and grid-choice tests (crates/tyndall-tests/tests/vdb.rs).

Blender's own bake could not run here (the bpy module's headless
Mantaflow fails with "'LevelsetGrid' object has no attribute 'setConst'",
a known problem since Blender 4.2, and Debian's Blender 3.4 fails in its
Mantaflow bindings), so the real OpenVDB library writes the files, with
Blender's grid names, types, half precision and layout.

    apt-get install python3-openvdb
    /usr/bin/python3 make_blender_cache.py      # from this folder
"""
import os

import numpy as np
import pyopenvdb as vdb

N = 16
VOXEL = 2.0 / N  # a 2 m domain, as Blender's default cube


def half_grid(grid_type, name, values=None, active_tile=None):
    grid = grid_type()
    if values is not None:
        zero = (0.0, 0.0, 0.0) if values.ndim == 4 else 0.0
        grid.copyFromArray(values, ijk=(0, 0, 0), tolerance=zero)
    if active_tile is not None:
        grid.fill((0, 0, 0), (N - 1, N - 1, N - 1), active_tile, active=True)
    grid.transform = vdb.createLinearTransform(voxelSize=VOXEL)
    grid.transform.translate((-1.0, -1.0, 0.0))
    grid.name = name
    grid.saveFloatAsHalf = True
    return grid


def frame(k):
    i, j, l = np.meshgrid(np.arange(N), np.arange(N), np.arange(N), indexing="ij")
    # A plume rising with the frame: Gaussian blob centred higher each frame.
    centre = np.array([N / 2, N / 2, 3 + 2 * k])
    r2 = ((i - centre[0]) ** 2 + (j - centre[1]) ** 2 + (l - centre[2]) ** 2) / 9.0
    density = np.where(r2 < 4, np.exp(-r2), 0).astype(np.float32)
    flame = (0.5 * density * (l < centre[2])).astype(np.float32)
    velocity = np.zeros((N, N, N, 3), np.float32)
    velocity[..., 2] = density
    grids = [
        half_grid(vdb.FloatGrid, "density", density),
        half_grid(vdb.FloatGrid, "flame", flame),
        half_grid(vdb.FloatGrid, "heat", flame * 2),
        half_grid(vdb.FloatGrid, "temperature", flame * 3),
        half_grid(vdb.Vec3SGrid, "velocity", velocity),
        half_grid(vdb.FloatGrid, "color_r"),
        half_grid(vdb.FloatGrid, "color_g"),
        half_grid(vdb.FloatGrid, "color_b"),
        half_grid(vdb.FloatGrid, "shadow", active_tile=1.0),
    ]
    for g in grids:
        g.gridClass = vdb.GridClass.FOG_VOLUME if g.name != "velocity" else vdb.GridClass.STAGGERED
    return grids


def main():
    out = os.path.join("blender_cache", "data")
    os.makedirs(out, exist_ok=True)
    for k in (1, 2):
        vdb.write(os.path.join(out, f"fluid_data_{k:04d}.vdb"), grids=frame(k))


if __name__ == "__main__":
    main()
