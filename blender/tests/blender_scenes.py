"""Scenes and renders for the add-on's tests: each scene is built in the
running Blender by script, then rendered by the Tyndall engine and (where
a test compares) by Cycles with the references' settings,
scenes/blender/cycles_settings.py (unbiased path tracing: no denoising,
clamping, adaptive sampling, light tree or guiding; box pixel filter)."""

import os
import sys

import numpy as np

import bpy

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(REPO, "blender"))
sys.path.insert(0, os.path.join(REPO, "scenes", "blender"))

# relMSE as `tyndall compare` computes it, a light object in Blender's
# units, Cycles' settings and the World's fog, and EXRs read as the fog
# room's scripts do them.
import cycles_settings  # noqa: E402
from cycles_fog_room import rel_mse  # noqa: E402,F401
from cycles_settings import world_fog  # noqa: E402,F401
from make_fog_room import light as lamp  # noqa: E402,F401
from side_by_side import read_exr  # noqa: E402,F401


def render(out_dir, name, animation=False):
    """Renders the current scene with its engine to OUT_DIR/NAME.exr
    (float32 RGB) and returns the image; with `animation`, every frame
    to NAME-####.exr and a list of the images."""
    sc = bpy.context.scene
    ims = sc.render.image_settings
    ims.file_format = "OPEN_EXR"
    ims.color_mode = "RGB"
    ims.color_depth = "32"
    sc.render.use_compositing = False
    sc.render.use_sequencer = False
    if animation:
        sc.render.filepath = os.path.join(out_dir, f"{name}-####")
        bpy.ops.render.render(animation=True)
        return [read_exr(os.path.join(out_dir, f"{name}-{f:04d}.exr")) for f in range(sc.frame_start, sc.frame_end + 1)]
    sc.render.filepath = os.path.join(out_dir, f"{name}.exr")
    bpy.ops.render.render(write_still=True)
    return read_exr(sc.render.filepath)


def use_tyndall(spp, seed=0, integrator="volpath"):
    sc = bpy.context.scene
    sc.render.engine = "TYNDALL"
    t = sc.tyndall
    t.samples = spp
    t.seed = seed
    t.integrator = integrator
    t.denoise = False
    t.threads = 0


def use_cycles(spp, seed=1, bounces=1024):
    """Cycles, unbiased, as the references here were rendered."""
    cycles_settings.unbiased(bpy.context.scene, spp, bounces, os.cpu_count() or 2)
    bpy.context.scene.cycles.seed = seed


def register_addon():
    """Registers the add-on from the source folder (once per process)."""
    import tyndall_blender

    if not hasattr(bpy.types.Scene, "tyndall"):
        tyndall_blender.register()


def thin_glass(obj):
    """Replaces a Principled transmission material by a Transparent BSDF of
    its base colour (cycles_fog_room.py --glass thin: Tyndall's pane)."""
    mat = obj.data.materials[0]
    nt = mat.node_tree
    base = nt.nodes["Principled BSDF"].inputs["Base Color"].default_value[:3]
    tr = nt.nodes.new("ShaderNodeBsdfTransparent")
    tr.inputs["Color"].default_value = (*base, 1.0)
    nt.links.new(tr.outputs["BSDF"], nt.nodes["Material Output"].inputs["Surface"])


def camera(scene, location, rotation, lens_mm):
    """A perspective camera (sensor fit AUTO, 36 mm), made the scene's."""
    data = bpy.data.cameras.new("camera")
    data.lens = lens_mm
    data.clip_start = 1e-5
    data.clip_end = 1e5
    obj = bpy.data.objects.new("camera", data)
    obj.location = location
    obj.rotation_euler = rotation
    scene.collection.objects.link(obj)
    scene.camera = obj
    return obj


def write_png_checker(path, size=64):
    """A size × size PNG (sRGB, 8 bits) of four colours in 2×2 blocks:
    texels blend only along the blocks' edges (Cycles and Tyndall blend
    two 8-bit texels differently, see blender/README.md)."""
    colours = np.array([[0.9, 0.2, 0.2], [0.2, 0.8, 0.3], [0.25, 0.3, 0.9], [0.9, 0.9, 0.85]], np.float32)
    block = (np.arange(size) * 2) // size
    rgb = colours[(block[:, None] * 2 + block[None, :])]
    image = bpy.data.images.new(os.path.basename(path), size, size, alpha=True)
    pixels = np.ones((size, size, 4), np.float32)
    pixels[:, :, :3] = rgb[::-1]
    image.pixels.foreach_set(pixels.ravel())
    image.filepath_raw = path
    image.file_format = "PNG"
    image.save()
    bpy.data.images.remove(image)
