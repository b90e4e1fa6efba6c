#!/usr/bin/python3
"""Writes the smoke-grid benchmark scene: a 64³ puff of smoke under a hard
spot, in the peers' format (../shared/peers/FORMAT.md), as the same density
field in two files:

    cd scenes/reference/smoke-grid && /usr/bin/python3 make_smoke_grid.py

- smoke-grid.npy (float32, shape (z, y, x)) and smoke-grid.json: a `grid`
  volume for Mitsuba (mitsuba_render.py) and Tyndall (to_tyndall.py writes
  the .tgrid and the .toml);
- smoke-grid.vdb and smoke-grid-vdb.json: the same voxels as an OpenVDB
  float grid (Debian's python3-openvdb 10) for Cycles (cycles_render.py
  reads only `vdb` volumes).

Voxel (i, j, k) holds the density at its centre, BOX_MIN + VOXEL·(i + ½, j + ½,
k + ½), in both files: Mitsuba's gridvolume puts its samples at cell centres,
and an OpenVDB index point is a voxel centre (the transform below). The two
outermost layers of voxels are zero, so the renderers' differing rules past
the last voxel (Mitsuba clamps, a VDB's background is 0) meet the same zero.

The field is procedural and seeded, so the files are reproducible: a plume
rising from the floor, widening and leaning as it rises, its density broken
up by three octaves of value noise.
"""
import json

import numpy as np

N = 64
# The box floats 2 cm above the floor: a cube face lying in the floor's plane
# darkened Mitsuba's floor below it by 15 % (a null-BSDF face and the floor
# at the same depth; Tyndall and Cycles agreed with each other).
BOX_MIN = np.array([-1.0, 0.02, -1.0])
BOX_MAX = np.array([1.0, 2.02, 1.0])
VOXEL = (BOX_MAX - BOX_MIN) / N  # 1/32 on every axis
SIGMA_T = 12.0
ALBEDO = [0.95, 0.95, 0.95]
G = 0.4


def value_noise(rng, lattice, n):
    """A lattice of uniform values, trilinearly upsampled to n³ voxels."""
    values = rng.random((lattice + 1,) * 3)
    coords = (np.arange(n) + 0.5) / n * lattice
    i0 = np.minimum(coords.astype(int), lattice - 1)
    f = coords - i0
    # Separable trilinear interpolation along z, y, x in turn.
    out = values
    for axis in range(3):
        lo = np.take(out, i0, axis=axis)
        hi = np.take(out, i0 + 1, axis=axis)
        shape = [1, 1, 1]
        shape[axis] = n
        w = f.reshape(shape)
        out = lo * (1 - w) + hi * w
    return out


def density_field():
    centres = [BOX_MIN[a] + VOXEL[a] * (np.arange(N) + 0.5) for a in range(3)]
    z, y, x = np.meshgrid(centres[2], centres[1], centres[0], indexing="ij")
    height = (y - BOX_MIN[1]) / (BOX_MAX[1] - BOX_MIN[1])  # 0 at the floor, 1 at the top
    radius = 0.22 + 0.45 * height
    lean_x = 0.25 * np.sin(2.2 * y)
    lean_z = 0.10 * np.cos(1.7 * y)
    r2 = ((x - lean_x) ** 2 + (z - lean_z) ** 2) / radius**2
    plume = np.exp(-2.0 * r2) * np.clip(1.6 * (1.0 - height), 0.0, 1.0)
    rng = np.random.default_rng(7)
    noise = sum(value_noise(rng, lattice, N) * weight for lattice, weight in ((4, 0.5), (8, 0.3), (16, 0.2)))
    dens = np.clip(plume * (0.3 + 1.4 * noise) - 0.05, 0.0, 1.0).astype(np.float32)
    dens[:2, :, :] = dens[-2:, :, :] = 0.0
    dens[:, :2, :] = dens[:, -2:, :] = 0.0
    dens[:, :, :2] = dens[:, :, -2:] = 0.0
    return dens  # indexed [z][y][x]


def scene(volume):
    spot_position = [-2.6, 3.8, 1.6]
    aim = np.array([0.0, 0.9, 0.0]) - np.array(spot_position)
    return {
        "format": "volbench-scene/1",
        "name": "smoke-grid",
        "description": "A 64³ puff of smoke (sigma_t 12 × density, albedo 0.95, g 0.4) under a hard "
        "spot over a floor and a wall; multiple scattering up to 16 segments.",
        "camera": {"position": [0.0, 1.3, 5.5], "look_at": [0.0, 0.95, 0.0], "up": [0, 1, 0],
                   "fov_y_deg": 36.0, "width": 320, "height": 240},
        "medium": None,
        "volumes": [volume],
        "shapes": [
            {"name": "floor", "type": "quad",
             "corners": [[-5, 0, -3], [-5, 0, 5], [5, 0, 5], [5, 0, -3]],
             "material": {"type": "diffuse", "reflectance": [0.45, 0.45, 0.45]}},
            {"name": "wall", "type": "quad",
             "corners": [[-5, 0, -3], [5, 0, -3], [5, 5, -3], [-5, 5, -3]],
             "material": {"type": "diffuse", "reflectance": [0.5, 0.5, 0.5]}},
        ],
        "lights": [{"name": "spot", "type": "spot", "position": spot_position,
                    "direction": (aim / np.linalg.norm(aim)).tolist(), "cutoff_deg": 24.0,
                    "intensity": [90.0, 80.0, 65.0]}],
        "render": {"max_depth": 16},
    }


def write_vdb(dens, path):
    import pyopenvdb as vdb

    grid = vdb.FloatGrid(0.0)
    # copyFromArray indexes [i][j][k] = [x][y][z].
    grid.copyFromArray(np.ascontiguousarray(dens.transpose(2, 1, 0)), ijk=(0, 0, 0), tolerance=0)
    grid.prune(0.0)
    transform = vdb.createLinearTransform(voxelSize=float(VOXEL[0]))
    transform.translate(tuple(float(m + 0.5 * VOXEL[0]) for m in BOX_MIN))
    grid.transform = transform
    grid.name = "density"
    grid.gridClass = vdb.GridClass.FOG_VOLUME
    vdb.write(path, grids=[grid])


def main():
    assert np.allclose(VOXEL, VOXEL[0]), "the VDB transform needs cubic voxels"
    dens = density_field()
    np.save("smoke-grid.npy", dens)
    write_vdb(dens, "smoke-grid.vdb")
    common = {"sigma_t": SIGMA_T, "albedo": ALBEDO, "g": G}
    with open("smoke-grid.json", "w") as f:
        json.dump(scene({"type": "grid", "density": "smoke-grid.npy",
                         "box": {"min": BOX_MIN.tolist(), "max": BOX_MAX.tolist()}, **common}), f, indent=1)
    with open("smoke-grid-vdb.json", "w") as f:
        json.dump(scene({"type": "vdb", "file": "smoke-grid.vdb", "grid": "density", **common}), f, indent=1)
    print(f"max density {dens.max():.3f}, mean {dens.mean():.4f}, non-zero voxels {np.count_nonzero(dens)}")


if __name__ == "__main__":
    main()
