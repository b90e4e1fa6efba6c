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
- affine.vdb: the sphere's voxels under an AffineMap (a rotation, a
  non-uniform scale and a translation: AFFINE below).
- transforms.vdb: one small grid per linear map type OpenVDB writes
  (UniformScaleMap, UniformScaleTranslateMap, ScaleMap, ScaleTranslateMap,
  AffineMap), each named by its map type, and transforms.txt: for each
  grid, index points and the world points OpenVDB's own
  Transform.indexToWorld gives them (the oracle of the transform test).
- grids.vdb: two grids both named "density" (a 2x2x2 box of 1.5, then one
  of 3.0 at another place), "empty" (no active voxels), "velocity" (vec3s)
  and "velocity_half" (vec3s saved as halves), "levelset"
  (vdb.createLevelSetSphere), "background" (background 0.5), "negative"
  (a voxel of -1), "nan" (a NaN voxel), "frustum" (a frustum transform).
- tiles.vdb: grid "density" with an active tile of 128^3 voxels (a tile of
  a level-2 node) of 0.5 from the origin, an active 8^3 tile (a tile of a
  level-1 node) of 0.25 from (128, 0, 0) and one voxel of 0.75 at
  (200, 3, 3).
- instance.vdb: grid "density" (a 2x2x2 box of 2) and "moved", a shallow
  copy sharing its tree (written as an instance) with voxel size 0.5,
  translated by (1, 2, 3).
- bigtiles.vdb: grid "density" filled with 1 over (0..1151) x (0..1023) x
  (0..1023): 576 active tiles of 128^3 voxels, 2.36 M bricks of 8^3, more
  than the reader's bound of 2^21.
- roottile.vdb: grid "density" filled with 1 over (0..4095)^3: one active
  root tile of 4096^3 voxels.

pyopenvdb writes with its default compression, Blosc (LZ4) plus active-mask
compression when OpenVDB is built with Blosc (Debian's is), and file format
224; it offers no way to choose zip, so make_cpp_vdbs.cpp (OpenVDB's C++
API) writes zip and uncompressed copies. Older formats cannot be written:
the tests rewrite the version field of these files instead.
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
    more()


# A rotation by 30 degrees about (1, 1, 0)/sqrt(2), applied after scaling
# index axes by (1, 0.5, 2) voxels and followed by a translation: rows are
# OpenVDB's (row vectors, translation last).
def affine_rows():
    c, s = np.cos(np.pi / 6), np.sin(np.pi / 6)
    u = np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0)
    ux = np.array([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    rot = c * np.eye(3) + s * ux + (1 - c) * np.outer(u, u)  # column vectors
    lin = rot @ np.diag([1.0, 0.5, 2.0]) * VOXEL
    m = np.eye(4)
    m[:3, :3] = lin.T  # row-vector convention
    m[3, :3] = [0.2, -0.1, 0.3]
    return [list(map(float, r)) for r in m]


def box(value, lo, hi):
    g = vdb.FloatGrid(0.0)
    g.fill(lo, hi, value)
    return g


def more():
    affine = sphere_grid()
    affine.transform = vdb.createLinearTransform(affine_rows())
    vdb.write("affine.vdb", grids=[affine])

    points = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (3, -2, 5)]
    transforms = [vdb.createLinearTransform(voxelSize=0.5)]
    t = vdb.createLinearTransform(voxelSize=0.5)
    t.translate((1.0, -2.0, 0.25))
    transforms.append(t)
    transforms.append(vdb.createLinearTransform(
        [[0.5, 0, 0, 0], [0, 0.25, 0, 0], [0, 0, 2, 0], [0, 0, 0, 1]]))
    transforms.append(vdb.createLinearTransform(
        [[0.5, 0, 0, 0], [0, 0.25, 0, 0], [0, 0, 2, 0], [1, 2, 3, 1]]))
    transforms.append(vdb.createLinearTransform(affine_rows()))
    grids, lines = [], []
    for t in transforms:
        g = box(1.0, (0, 0, 0), (1, 1, 1))
        g.transform = t
        g.name = t.typeName
        grids.append(g)
        for p in points:
            w = t.indexToWorld(p)
            lines.append("%s %d %d %d %r %r %r" % ((g.name,) + p + tuple(w)))
    assert len({g.name for g in grids}) == len(grids), [g.name for g in grids]
    vdb.write("transforms.vdb", grids=grids)
    with open("transforms.txt", "w") as f:
        f.write("\n".join(lines) + "\n")

    first = box(1.5, (0, 0, 0), (1, 1, 1))
    first.name = "density"
    second = box(3.0, (10, 0, 0), (11, 1, 1))
    second.name = "density"
    empty = vdb.FloatGrid(0.0)
    empty.name = "empty"
    velocity = vdb.Vec3SGrid()
    velocity.fill((0, 0, 0), (1, 1, 1), (1.0, -2.0, 0.5))
    velocity.name = "velocity"
    vhalf = vdb.Vec3SGrid()
    vhalf.fill((0, 0, 0), (1, 1, 1), (1.0, -2.0, 0.5))
    vhalf.name = "velocity_half"
    vhalf.saveFloatAsHalf = True
    levelset = vdb.createLevelSetSphere(radius=1.0, voxelSize=0.25)
    levelset.name = "levelset"
    background = box(1.0, (0, 0, 0), (1, 1, 1))
    background.background = 0.5
    background.name = "background"
    negative = box(1.0, (0, 0, 0), (1, 1, 1))
    negative.getAccessor().setValueOn((1, 1, 1), -1.0)
    negative.name = "negative"
    nan = box(1.0, (0, 0, 0), (1, 1, 1))
    nan.getAccessor().setValueOn((0, 1, 0), float("nan"))
    nan.name = "nan"
    frustum = box(1.0, (0, 0, 0), (1, 1, 1))
    frustum.transform = vdb.createFrustumTransform(
        (0, 0, 0), (10, 10, 10), 0.5, 2.0, 0.1)
    frustum.name = "frustum"
    vdb.write("grids.vdb", grids=[first, second, empty, velocity, vhalf, levelset,
                                  background, negative, nan, frustum])

    tiles = vdb.FloatGrid(0.0)
    tiles.fill((0, 0, 0), (127, 127, 127), 0.5)
    tiles.fill((128, 0, 0), (135, 7, 7), 0.25)
    tiles.getAccessor().setValueOn((200, 3, 3), 0.75)
    tiles.name = "density"
    vdb.write("tiles.vdb", grids=[tiles])

    density = box(2.0, (0, 0, 0), (1, 1, 1))
    density.name = "density"
    moved = density.copy()
    moved.name = "moved"
    t = vdb.createLinearTransform(voxelSize=0.5)
    t.translate((1.0, 2.0, 3.0))
    moved.transform = t
    assert density.sharesWith(moved)
    vdb.write("instance.vdb", grids=[density, moved])

    big = vdb.FloatGrid(0.0)
    big.fill((0, 0, 0), (1151, 1023, 1023), 1.0)
    big.name = "density"
    vdb.write("bigtiles.vdb", grids=[big])

    root = vdb.FloatGrid(0.0)
    root.fill((0, 0, 0), (4095, 4095, 4095), 1.0)
    root.name = "density"
    vdb.write("roottile.vdb", grids=[root])


if __name__ == "__main__":
    main()
