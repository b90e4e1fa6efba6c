#!/usr/bin/python3
"""Writes the sparse clouds of `tyndall bench --only load --vdb FILE` with
the real OpenVDB library (Debian's python3-openvdb 10), grid "density":

    /usr/bin/python3 scenes/smoke/make_sparse_cloud.py target/tyndall-bench/cloud.vdb
    /usr/bin/python3 scenes/smoke/make_sparse_cloud.py --big target/tyndall-bench/cloud-100m.vdb

Default (issue 12's target: a 512³-bounding sparse cloud loads in under
5 s): twelve soft blobs of radius 20 to 60 voxels, scattered (fixed seed)
over index bounds of about 510³ voxels of 0.01, full-precision floats; a
few per cent of the bounding box is active.

`--big` (issue 21's target: a half-float cloud of 100 M active voxels
loads in at most 5 s and is held in at most 1.2× its voxel bytes): one
cloud, an ellipsoid of semi-axes 400 × 250 × 240 voxels whose surface is
displaced by a sum of random plane waves and whose density, falling
softly to 0 at that surface, is modulated by another such sum; saved as
half floats (`saveFloatAsHalf`, as Blender's and Houdini's caches are).
About 10⁸ voxels are active inside index bounds of about 800 × 500 × 480.

Zero voxels stay inactive; constant leaves are pruned to tiles.
"""
import sys

import numpy as np
import pyopenvdb as vdb


def blobs(grid):
    side = 512
    rng = np.random.default_rng(7)
    centres = rng.integers(64, side - 64, size=(12, 3))
    radii = rng.integers(20, 61, size=12)
    # Two blobs of radius 60 in opposite corners span the full 512³ bounds.
    centres[0], centres[1] = (60, 60, 60), (side - 61, side - 61, side - 61)
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


def waves(rng, count, wavelengths):
    """`count` plane waves of random directions and phases, wavelengths
    (in voxels) spread log-uniformly over `wavelengths`, amplitude ∝
    wavelength, the sum normalised to amplitude 1 at most."""
    dirs = rng.normal(size=(count, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    lam = np.exp(rng.uniform(np.log(wavelengths[0]), np.log(wavelengths[1]), count))
    amp = lam / lam.sum()
    k = dirs * (2 * np.pi / lam)[:, None]
    phase = rng.uniform(0, 2 * np.pi, count)
    return k.astype(np.float32), amp.astype(np.float32), phase.astype(np.float32)


def wave_sum(x, y, z, w):
    k, amp, phase = w
    out = np.zeros(np.broadcast_shapes(x.shape, y.shape, z.shape), np.float32)
    for (kx, ky, kz), a, p in zip(k, amp, phase):
        out += a * np.sin(kx * x + ky * y + kz * z + p)
    return out


def big_cloud(grid):
    rng = np.random.default_rng(21)
    axes = np.array([400.0, 250.0, 240.0], np.float32)
    surface, inside = waves(rng, 8, (60, 400)), waves(rng, 12, (16, 200))
    margin = 1.15  # the displaced surface stays within 1.15× the axes
    half = np.ceil(axes * margin).astype(int)
    xs = np.arange(-half[0], half[0] + 1, dtype=np.float32)
    ys = np.arange(-half[1], half[1] + 1, dtype=np.float32)
    slab = 32
    for z0 in range(-half[2], half[2] + 1, slab):
        zs = np.arange(z0, min(z0 + slab, half[2] + 1), dtype=np.float32)
        # Indexed [x, y, z], as copyFromArray reads arrays.
        x, y, z = xs[:, None, None], ys[None, :, None], zs[None, None, :]
        r = np.sqrt((x / axes[0]) ** 2 + (y / axes[1]) ** 2 + (z / axes[2]) ** 2)
        r = r / (1.0 + 0.15 * wave_sum(x, y, z, surface))
        edge = np.clip((1.0 - r) / 0.1, 0.0, 1.0)
        density = edge * (0.6 + 0.4 * wave_sum(x, y, z, inside))
        density = np.clip(density, 0.0, None).astype(np.float32)
        grid.copyFromArray(density, ijk=(int(-half[0]), int(-half[1]), int(z0)), tolerance=0)


big = "--big" in sys.argv[1:]
paths = [a for a in sys.argv[1:] if a != "--big"]
if len(paths) != 1:
    sys.exit(__doc__)
grid = vdb.FloatGrid(0.0)
grid.name = "density"
if big:
    big_cloud(grid)
    grid.saveFloatAsHalf = True
else:
    blobs(grid)
grid.prune(0.0)
grid.transform = vdb.createLinearTransform(voxelSize=0.01 if not big else 0.0025)
vdb.write(paths[0], grids=[grid])
print("wrote", paths[0], "active voxels:", grid.activeVoxelCount(),
      "leaves:", grid.leafCount(), "bounds:", grid.evalActiveVoxelBoundingBox())
