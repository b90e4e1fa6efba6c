"""A Khronos sample asset under a camera, a hard spot, a point light and a
grey floor, rendered by Cycles with its default light transport, for
Tyndall to render the same scene from Blender's own glTF export
(scenes/gltf-samples/README.md):

    python scenes/gltf-samples/assets_vs_cycles.py ASSET OUT_DIR \
        [--spp N] [--bounces B] [--max-texture N] [--after-import FILE] \
        [--no-cycles] [--tyndall BIN [--tyndall-spp N]]

with the Python of a `pip install bpy==4.5.15` environment. ASSET is a
.glb or .gltf file. The script

1. imports ASSET with Blender's glTF importer (its default options) and
   deletes any camera or light the asset brings;
2. with `--max-texture N`, downsizes every image of the asset whose
   longer side exceeds N pixels to N on that side (Blender's
   `Image.scale`), saves it as OUT_DIR/textures/NAME.png or .jpg (its own
   format; JPEG at quality 90) and puts the saved file in its place (its
   colour space and alpha mode kept), so that Cycles and the exported file
   both hold the small image; with `--after-import FILE`, then runs the
   Python file FILE (with `bpy` imported) to change the imported asset:
   the variants that take one feature away to find what a difference
   comes from;
3. normalises the asset under one new empty, `asset_root`, the parent of
   its top-level objects: a uniform scale that makes the largest side of
   the axis-aligned box of all its mesh vertices (world space, after
   modifiers) 1 m, and a translation that centres the box over the origin
   in x and y and sets its lowest point 0.3 m above the floor. The
   exporter writes `asset_root` as a node with that scale and translation;
4. adds an 8 m grey floor at z = 0 (Principled BSDF, base colour 0.5,
   roughness 1, Specular IOR Level 0: a Lambert surface), as box_floor.py;
5. lights it with one hard spot, 400 W, 50° cone, blend 0, radius 0,
   soft falloff off, at (1.5, −1.0, 3.0) aimed at the asset's centre
   (0, 0, 0.8) (so tilted about 39° from vertical), and one point light,
   300 W, radius 0, soft falloff off, at (−1.8, −1.6, 1.8), on the other
   side of the camera;
6. adds a camera at (0, −2.0, 1.35) aimed at (0, 0, 0.8), 45° vertical
   field of view (sensor fit vertical), 160×120 pixels: the asset's front
   (glTF +z, Blender −y) faces it;
7. sets a black world (Background strength 0);
8. writes
   - OUT_DIR/scene.glb: the scene by Blender's glTF exporter
     (`export_lights=True`, `export_cameras=True`, the default "Standard"
     lighting mode, every other option at its default): the file Tyndall
     renders;
   - OUT_DIR/cycles-half0.exr, cycles-half1.exr: Cycles' render with
     seeds 1 and 2, `--spp`/2 samples each (float32, linear), whose
     difference estimates its noise, and OUT_DIR/cycles.exr, their mean;
   - OUT_DIR/cycles.json: the settings and the seconds each half took
     (`bpy.ops.render.render` alone, wall clock).

Cycles settings as box_floor.py: CPU, no denoising, no adaptive sampling,
no clamping, light threshold 0, light tree off, box pixel filter, Cycles'
default 12 bounces of every kind (`--bounces`), Standard view transform,
look None (what a Blender user's F12 gives, less the denoiser and the
light tree).

With `--tyndall BIN` the script then renders OUT_DIR/scene.glb with that
Tyndall binary (`tyndall render scene.glb --width 160 --height 120
--spp N --seed S -o OUT_DIR/tyndall-seedS.exr` for seeds 1 and 2, its
default glTF integrator, volpath), keeps its warnings in
OUT_DIR/tyndall-warnings.txt and writes OUT_DIR/compare.json and
OUT_DIR/side-by-side.png:

- mean: the image mean of grey (R + G + B)/3, Tyndall's (mean of its two
  seeds) over Cycles' (mean of the halves);
- relMSE: the mean over pixels and channels of (t − c)²/(c² + 0.01), t
  Tyndall's mean of seeds and c Cycles' mean of halves (the definition of
  crates/tyndall-image/src/metrics.rs, `tyndall compare`);
- noise: relMSE(seed 1, seed 2)/4 for Tyndall and relMSE(half 0,
  half 1)/4 for Cycles, each an estimate of the relMSE its two-render
  mean has against the noiseless image;
- the means of each seed and each half: their spread is the noise of
  the means (Cycles' fireflies can move it by several per cent);
- pass: the mean within 2 % and relMSE ≤ noise(Tyndall) + noise(Cycles)
  + 0.01;
- side-by-side.png: Tyndall | Cycles | |difference| × 4, each clipped to
  [0, 1] and sRGB-encoded, 8 bits.

`--no-cycles` skips the Blender steps and uses the files already in
OUT_DIR (to rerun a new Tyndall against the same references).
"""
import argparse
import json
import math
import os
import re
import struct
import subprocess
import sys
import time
import zlib

import bpy
import numpy as np
from mathutils import Matrix, Vector

# The floor, the spot and Cycles' F12 settings are box_floor.py's (its
# docstring).
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from box_floor import add_floor, configure, hard_spot  # noqa: E402

WIDTH, HEIGHT = 160, 120
ASSET_CENTRE = Vector((0.0, 0.0, 0.8))
EPSILON = 0.01


def downsize_textures(max_side, tex_dir):
    """Every image of the asset at most `max_side` pixels on its longer
    side, saved under `tex_dir` and reloaded in its place."""
    os.makedirs(tex_dir, exist_ok=True)
    changed = []
    for img in list(bpy.data.images):
        if img.source != "FILE" or max(img.size) <= max_side:
            continue
        w, h = img.size
        s = max_side / max(w, h)
        nw, nh = max(1, round(w * s)), max(1, round(h * s))
        ext = ".jpg" if img.file_format == "JPEG" else ".png"
        name = re.sub(r"[^A-Za-z0-9_.-]", "_", img.name)
        path = os.path.join(tex_dir, name + ext)
        img.scale(nw, nh)
        img.save(filepath=path, quality=90)
        small = bpy.data.images.load(path)
        small.colorspace_settings.name = img.colorspace_settings.name
        small.alpha_mode = img.alpha_mode
        img.user_remap(small)
        old = img.name
        bpy.data.images.remove(img)
        small.name = old
        changed.append((old, [w, h], [nw, nh]))
    return changed


def normalise(top_level):
    """Parents the asset's top-level objects to an empty scaled and moved
    so that its vertices' box has largest side 1 m, is centred over the
    origin and starts 0.3 m above the floor."""
    bpy.context.view_layer.update()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    lo = np.full(3, np.inf)
    hi = np.full(3, -np.inf)
    for o in bpy.context.scene.objects:
        if o.type != "MESH":
            continue
        ev = o.evaluated_get(depsgraph)
        mesh = ev.to_mesh()
        n = len(mesh.vertices)
        if n:
            co = np.empty(n * 3, dtype=np.float64)
            mesh.vertices.foreach_get("co", co)
            co = co.reshape(n, 3)
            m = np.array(ev.matrix_world)
            world = co @ m[:3, :3].T + m[:3, 3]
            lo = np.minimum(lo, world.min(axis=0))
            hi = np.maximum(hi, world.max(axis=0))
        ev.to_mesh_clear()
    side = float((hi - lo).max())
    s = 1.0 / side
    t = Vector((-s * (lo[0] + hi[0]) / 2, -s * (lo[1] + hi[1]) / 2, 0.3 - s * lo[2]))
    root = bpy.data.objects.new("asset_root", None)
    bpy.context.scene.collection.objects.link(root)
    for o in top_level:
        world = o.matrix_world.copy()
        o.parent = root
        o.matrix_parent_inverse = Matrix.Identity(4)
        o.matrix_world = world
    root.scale = (s, s, s)
    root.location = t
    bpy.context.view_layer.update()
    return {"box_min": lo.tolist(), "box_max": hi.tolist(), "scale": s, "translation": list(t)}


def aim(obj, target):
    """Turns `obj` (a camera or light, which looks down its −z) towards
    `target`, its up along +z."""
    direction = target - obj.location
    obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()


def build(asset, max_texture, out_dir, after_import=None):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    bpy.ops.import_scene.gltf(filepath=asset)
    imported = list(bpy.context.selected_objects)
    removed = []
    for o in imported:
        if o.type in ("CAMERA", "LIGHT"):
            removed.append(o.name)
            bpy.data.objects.remove(o)
    info = {"removed_from_asset": removed}
    if max_texture:
        info["textures"] = downsize_textures(max_texture, os.path.join(out_dir, "textures"))
    if after_import:
        with open(after_import) as f:
            exec(compile(f.read(), after_import, "exec"), {"bpy": bpy, "__name__": "after_import"})
        info["after_import"] = after_import
    top_level = [o for o in bpy.context.scene.objects if o.parent is None]
    if any(o.type == "MESH" for o in bpy.context.scene.objects):
        info["normalise"] = normalise(top_level)

    add_floor()

    aim(hard_spot(sc, (1.5, -1.0, 3.0)), ASSET_CENTRE)

    point = bpy.data.lights.new("point", "POINT")
    point.energy = 300.0
    point.shadow_soft_size = 0.0
    point.use_soft_falloff = False
    obj = bpy.data.objects.new("point", point)
    obj.location = (-1.8, -1.6, 1.8)
    sc.collection.objects.link(obj)

    cam_data = bpy.data.cameras.new("camera")
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = math.radians(45)
    cam = bpy.data.objects.new("camera", cam_data)
    cam.location = (0.0, -2.0, 1.35)
    aim(cam, ASSET_CENTRE)
    sc.collection.objects.link(cam)
    sc.camera = cam

    world = bpy.data.worlds.new("world")
    sc.world = world
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    return sc, info


def render(sc, spp, seed, path):
    sc.cycles.samples = spp
    sc.cycles.seed = seed
    start = time.perf_counter()
    bpy.ops.render.render(write_still=False)
    seconds = time.perf_counter() - start
    bpy.data.images["Render Result"].save_render(path, scene=sc)
    return seconds


def read_exr(path):
    """The RGB of an OpenEXR file as a HEIGHT × WIDTH × 3 float64 array,
    top row first (read with Blender's image API)."""
    img = bpy.data.images.load(path)
    w, h = img.size
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    return px.reshape(h, w, 4)[::-1, :, :3].astype(np.float64)


def write_exr(path, rgb, sc):
    h, w, _ = rgb.shape
    img = bpy.data.images.new("whole", w, h, alpha=True, float_buffer=True)
    rgba = np.ones((h, w, 4), dtype=np.float32)
    rgba[..., :3] = rgb
    img.pixels.foreach_set(rgba[::-1].ravel())
    img.filepath_raw = path
    img.file_format = "OPEN_EXR"
    img.save_render(path, scene=sc)
    bpy.data.images.remove(img)


def rel_mse(a, b):
    return float(np.mean((a - b) ** 2 / (b * b + EPSILON)))


def write_png(path, rgb):
    """An 8-bit sRGB PNG of linear `rgb` clipped to [0, 1]."""
    x = np.clip(rgb, 0.0, 1.0)
    x = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    codes = np.round(x * 255).astype(np.uint8)
    h, w, _ = codes.shape
    raw = b"".join(b"\x00" + codes[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def compare(out, tyndall, spp):
    scene = os.path.join(out, "scene.glb")
    times = []
    warnings = []
    for seed in (1, 2):
        cmd = [tyndall, "render", scene, "--width", str(WIDTH), "--height", str(HEIGHT),
               "--spp", str(spp), "--seed", str(seed), "-q",
               "-o", os.path.join(out, f"tyndall-seed{seed}.exr")]
        start = time.perf_counter()
        run = subprocess.run(cmd, capture_output=True, text=True)
        times.append(time.perf_counter() - start)
        if run.returncode != 0:
            sys.exit(f"{' '.join(cmd)} failed:\n{run.stderr}")
        if seed == 1:
            warnings = run.stderr.strip().splitlines()
    with open(os.path.join(out, "tyndall-warnings.txt"), "w") as f:
        f.write("\n".join(warnings) + "\n")
    t1, t2 = (read_exr(os.path.join(out, f"tyndall-seed{s}.exr")) for s in (1, 2))
    c0, c1 = (read_exr(os.path.join(out, f"cycles-half{h}.exr")) for h in (0, 1))
    t, c = (t1 + t2) / 2, (c0 + c1) / 2
    result = {
        "tyndall_spp": spp,
        "tyndall_seconds": times,
        "mean_tyndall": float(t.mean()),
        "mean_cycles": float(c.mean()),
        "mean_ratio": float(t.mean() / c.mean()),
        "means_tyndall_seeds": [float(t1.mean()), float(t2.mean())],
        "means_cycles_halves": [float(c0.mean()), float(c1.mean())],
        "rel_mse": rel_mse(t, c),
        "noise_tyndall": rel_mse(t1, t2) / 4,
        "noise_cycles": rel_mse(c0, c1) / 4,
        "warnings": warnings,
    }
    result["pass"] = bool(abs(result["mean_ratio"] - 1) <= 0.02 and result["rel_mse"]
                          <= result["noise_tyndall"] + result["noise_cycles"] + 0.01)
    with open(os.path.join(out, "compare.json"), "w") as f:
        json.dump(result, f, indent=1)
    write_png(os.path.join(out, "side-by-side.png"),
              np.concatenate([t, c, np.abs(t - c) * 4], axis=1))
    return result


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("asset")
    ap.add_argument("out_dir")
    ap.add_argument("--spp", type=int, default=512, help="Cycles' samples per pixel in all")
    ap.add_argument("--bounces", type=int, default=12)
    ap.add_argument("--max-texture", type=int, default=0,
                    help="downsize the asset's images to at most N pixels on their longer side")
    ap.add_argument("--after-import", help="a Python file run on the imported asset (variants)")
    ap.add_argument("--no-cycles", action="store_true",
                    help="reuse OUT_DIR's scene.glb and Cycles renders")
    ap.add_argument("--tyndall", help="a Tyndall binary to render scene.glb with and compare")
    ap.add_argument("--tyndall-spp", type=int, default=64)
    args = ap.parse_args()
    out = os.path.abspath(args.out_dir)
    os.makedirs(out, exist_ok=True)
    if not args.no_cycles:
        sc, info = build(os.path.abspath(args.asset), args.max_texture, out,
                         args.after_import and os.path.abspath(args.after_import))
        configure(sc, args.bounces)
        bpy.ops.export_scene.gltf(filepath=os.path.join(out, "scene.glb"), export_format="GLB",
                                  export_lights=True, export_cameras=True)
        seconds = [render(sc, args.spp // 2, seed, os.path.join(out, f"cycles-half{seed - 1}.exr"))
                   for seed in (1, 2)]
        halves = [read_exr(os.path.join(out, f"cycles-half{h}.exr")) for h in (0, 1)]
        write_exr(os.path.join(out, "cycles.exr"), (halves[0] + halves[1]) / 2, sc)
        info.update(asset=args.asset, spp_per_half=args.spp // 2, bounces=args.bounces,
                    seconds_per_half=seconds)
        with open(os.path.join(out, "cycles.json"), "w") as f:
            json.dump(info, f, indent=1)
        print("cycles", json.dumps(info))
    if args.tyndall:
        print("compare", json.dumps(compare(out, args.tyndall, args.tyndall_spp)))
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)


main()
