#!/usr/bin/python3
"""Writes fire.vdb, the small procedural flame of scenes/fire.toml, with the
real OpenVDB library (Debian's python3-openvdb, OpenVDB 10):

    apt-get install python3-openvdb
    cd scenes/fire && /usr/bin/python3 make_fire_vdb.py

Three float grids share one transform (voxel size 0.04, index (0, 0, 0)
at world (-0.6, 0, -0.6)), over 30 x 50 x 30 voxels (1.2 x 2 x 1.2 world
units), zero voxels left inactive:

- "density": soot, thin at the base, thicker and wider up the plume;
- "temperature": kelvin / 1000 (so temperature_scale = 1000), about 1.9
  in the core just above the base, cooling upwards and outwards;
- "flame": the hot core's glow, 0..1, for an `emission` colour.

A few sines make the flame lick (deterministic: no random numbers). The
grids are saved as half floats.
"""
import numpy as np
import pyopenvdb as vdb

VOXEL = 0.04
NX, NY, NZ = 30, 50, 30
ORIGIN = np.array([-0.6, 0.0, -0.6])


def fields():
    i, j, k = np.meshgrid(np.arange(NX), np.arange(NY), np.arange(NZ), indexing="ij")
    x = ORIGIN[0] + (i + 0.5) * VOXEL
    y = ORIGIN[1] + (j + 0.5) * VOXEL
    z = ORIGIN[2] + (k + 0.5) * VOXEL
    h = y / 2.0  # 0 at the base, 1 at the top
    # The plume sways and licks: its axis moves with height.
    ax = 0.08 * np.sin(5.0 * y + 1.0)
    az = 0.06 * np.sin(4.0 * y + 2.5)
    r = np.sqrt((x - ax) ** 2 + (z - az) ** 2)
    lick = 1.0 + 0.25 * np.sin(9.0 * y - 3.0 * np.arctan2(z - az, x - ax))
    width = (0.22 - 0.10 * h) * lick  # the flame narrows upwards
    core = np.exp(-((r / np.maximum(width, 0.03)) ** 2))
    rise = np.clip(y / 0.15, 0.0, 1.0)  # fades in above the base
    temperature = 1.9 * core * rise * np.exp(-1.6 * h)
    flame = np.clip((temperature - 0.9) / 0.9, 0.0, 1.0)
    smoke_width = 0.18 + 0.22 * h
    density = (0.15 + 1.2 * h) * np.exp(-((r / smoke_width) ** 2)) * rise
    for f in (density, temperature, flame):
        f[f < 1e-3] = 0.0
    return density, temperature, flame


def grid(name, values):
    g = vdb.FloatGrid()
    g.copyFromArray(values.astype(np.float32), ijk=(0, 0, 0), tolerance=0.0)
    g.name = name
    g.gridClass = vdb.GridClass.FOG_VOLUME
    xform = vdb.createLinearTransform(voxelSize=VOXEL)
    # Voxel centres at ORIGIN + (index + 0.5)·VOXEL.
    xform.translate(tuple(ORIGIN + 0.5 * VOXEL))
    g.transform = xform
    g.prune()
    # Half floats: 11 significant bits are plenty for a flame, and keep
    # the file small.
    g.saveFloatAsHalf = True
    return g


if __name__ == "__main__":
    density, temperature, flame = fields()
    vdb.write(
        "fire.vdb",
        grids=[grid("density", density), grid("temperature", temperature), grid("flame", flame)],
    )
