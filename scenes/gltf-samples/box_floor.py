"""A Khronos sample asset lit as a Blender user lights it, rendered by
Cycles with its default light transport, for Tyndall to render the same
scene from Blender's own glTF export (scenes/gltf-samples/README.md):

    python scenes/gltf-samples/box_floor.py ASSET.glb OUT_DIR [--spp N] [--bounces B]

with the Python of a `pip install bpy==4.5.15` environment. It imports
ASSET with Blender's glTF importer, sets it 0.5 m up on an 8 m grey floor
(Principled BSDF, base colour 0.5, roughness 1, Specular IOR Level 0: a
Lambert surface), lights it with one hard spot (400 W, 50°, blend 0,
radius 0, soft falloff off) tilted 30° down and turned 50°, adds a camera,
and writes

- OUT_DIR/scene.glb: the scene by Blender's glTF exporter (default
  "Standard" lighting units), the file Tyndall renders;
- OUT_DIR/cycles.exr: Cycles' render of the same Blender scene (160×120,
  float32), and cycles-half0.exr, cycles-half1.exr: the two halves of its
  samples, whose difference estimates its noise.

Cycles settings as ../shared/peers/cycles_render.py but for the bounces:
CPU, no denoising, no adaptive sampling, no clamping, light threshold 0,
light tree off, box pixel filter, black world, and Cycles' default 12
bounces of every kind (`--bounces`), which is what a Blender user's F12
gives.
"""
import argparse
import math
import os

import bpy


def add_floor():
    """The 8 m grey floor at z = 0: Principled, base 0.5, roughness 1,
    Specular IOR Level 0 (a Lambert surface)."""
    floor = bpy.data.materials.new("floor")
    floor.use_nodes = True
    p = floor.node_tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (0.5, 0.5, 0.5, 1.0)
    p.inputs["Roughness"].default_value = 1.0
    p.inputs["Specular IOR Level"].default_value = 0.0
    bpy.ops.mesh.primitive_plane_add(size=8, location=(0, 0, 0))
    bpy.context.active_object.data.materials.append(floor)


def hard_spot(sc, location):
    """A hard spot at `location`, linked to `sc`: 400 W, 50° cone, blend
    0, radius 0, soft falloff off; the caller turns it."""
    spot = bpy.data.lights.new("spot", "SPOT")
    spot.energy = 400.0
    spot.shadow_soft_size = 0.0
    spot.use_soft_falloff = False
    spot.spot_size = math.radians(50)
    spot.spot_blend = 0.0
    obj = bpy.data.objects.new("spot", spot)
    obj.location = location
    sc.collection.objects.link(obj)
    return obj


def build(asset):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    bpy.ops.import_scene.gltf(filepath=asset)
    for o in bpy.context.selected_objects:
        if o.parent is None:
            o.location.z += 0.5
    add_floor()

    spot = hard_spot(sc, (1.5, -1.0, 3.0))
    spot.rotation_euler = (math.radians(30), 0, math.radians(50))

    cam_data = bpy.data.cameras.new("camera")
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = math.radians(45)
    cam = bpy.data.objects.new("camera", cam_data)
    cam.location = (0, -6, 3.5)
    cam.rotation_euler = (math.radians(60), 0, 0)
    sc.collection.objects.link(cam)
    sc.camera = cam

    world = bpy.data.worlds.new("world")
    sc.world = world
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    return sc


def configure(sc, bounces):
    sc.render.engine = "CYCLES"
    cy = sc.cycles
    cy.device = "CPU"
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.light_sampling_threshold = 0.0
    cy.use_light_tree = False
    cy.pixel_filter_type = "BOX"
    for attr in ("max_bounces", "diffuse_bounces", "glossy_bounces",
                 "transmission_bounces", "volume_bounces"):
        setattr(cy, attr, bounces)
    sc.render.resolution_x = 160
    sc.render.resolution_y = 120
    sc.render.resolution_percentage = 100
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    ims = sc.render.image_settings
    ims.file_format = "OPEN_EXR"
    ims.color_mode = "RGB"
    ims.color_depth = "32"


def render(sc, spp, seed, path):
    sc.cycles.samples = spp
    sc.cycles.seed = seed
    bpy.ops.render.render(write_still=False)
    bpy.data.images["Render Result"].save_render(path, scene=sc)
    img = bpy.data.images.load(path)
    pixels = list(img.pixels)
    bpy.data.images.remove(img)
    return pixels


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("asset")
    ap.add_argument("out_dir")
    ap.add_argument("--spp", type=int, default=2048, help="samples per pixel in all")
    ap.add_argument("--bounces", type=int, default=12)
    args = ap.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    sc = build(os.path.abspath(args.asset))
    configure(sc, args.bounces)
    bpy.ops.export_scene.gltf(filepath=os.path.join(args.out_dir, "scene.glb"),
                              export_format="GLB", export_lights=True, export_cameras=True)
    halves = [render(sc, args.spp // 2, seed, os.path.join(args.out_dir, f"cycles-half{seed - 1}.exr"))
              for seed in (1, 2)]
    # The whole: the mean of the halves, written through Blender's image API.
    whole = bpy.data.images.new("whole", 160, 120, alpha=True, float_buffer=True)
    whole.pixels = [(a + b) / 2 for a, b in zip(*halves)]
    whole.filepath_raw = os.path.join(args.out_dir, "cycles.exr")
    whole.file_format = "OPEN_EXR"
    whole.save_render(whole.filepath_raw, scene=sc)
    print("wrote", args.out_dir)


if __name__ == "__main__":
    main()
