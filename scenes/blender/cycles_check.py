"""Blender's glTF light units against Cycles: a Lambert floor under a 400 W
hard spot and a 30 W point light, built in Blender (bpy 4.5.15), exported
with Blender's glTF exporter (default "Standard" lighting mode) and
rendered by Cycles with direct lighting only:

    /work/bpy-venv/bin/python scenes/blender/cycles_check.py OUT_DIR [SPP [DENSITY ALBEDO G]]

writes OUT_DIR/spot-floor.gltf (+ .bin) and OUT_DIR/cycles.exr. Then

    tyndall render OUT_DIR/spot-floor.gltf --integrator single --spp SPP \
        --width 160 --height 120 [--density D --albedo A --g G] -o OUT_DIR/tyndall.exr
    tyndall compare OUT_DIR/tyndall.exr OUT_DIR/cycles.exr

With DENSITY, ALBEDO, G the world holds homogeneous fog (Volume Scatter of
colour ALBEDO and density DENSITY, Henyey-Greenstein G, plus Volume
Absorption of colour ALBEDO and density DENSITY, so σs = ALBEDO·DENSITY
and σa = (1 − ALBEDO)·DENSITY), sampled by distance + equiangular MIS;
max_bounces 0 is then single scattering, as Tyndall's `single`.

Cycles settings (as shared/peers/cycles_render.py): CPU, no denoising, no
adaptive sampling, no clamping, light threshold 0, light tree off, box
pixel filter, max_bounces 0 (direct light at the first hit), black world,
lights of radius 0 with soft falloff off.
"""
import math
import os
import sys

import bpy

out_dir = sys.argv[1]
spp = int(sys.argv[2]) if len(sys.argv) > 2 else 64
fog = [float(v) for v in sys.argv[3:6]] if len(sys.argv) > 5 else None
bpy.ops.wm.read_factory_settings(use_empty=True)
sc = bpy.context.scene

floor_mat = bpy.data.materials.new("floor")
floor_mat.use_nodes = True
p = floor_mat.node_tree.nodes["Principled BSDF"]
p.inputs["Base Color"].default_value = (0.8, 0.8, 0.8, 1.0)
p.inputs["Roughness"].default_value = 1.0
p.inputs["Specular IOR Level"].default_value = 0.0
bpy.ops.mesh.primitive_plane_add(size=8, location=(0, 0, 0))
bpy.context.active_object.data.materials.append(floor_mat)


def light(kind, name, energy, location, rotation=(0, 0, 0), **props):
    data = bpy.data.lights.new(name, kind)
    data.energy = energy
    data.shadow_soft_size = 0.0
    data.use_soft_falloff = False
    for k, v in props.items():
        setattr(data, k, v)
    obj = bpy.data.objects.new(name, data)
    obj.location = location
    obj.rotation_euler = rotation
    sc.collection.objects.link(obj)


light("SPOT", "spot", 400.0, (0.5, 0, 3), rotation=(math.radians(15), 0, 0),
      spot_size=math.radians(50), spot_blend=0.0)
light("POINT", "bulb", 30.0, (-2, 2, 1.5))

cam_data = bpy.data.cameras.new("camera")
cam_data.sensor_fit = "VERTICAL"
cam_data.angle_y = math.radians(45)
cam = bpy.data.objects.new("camera", cam_data)
cam.location = (0, -7, 4)
cam.rotation_euler = (math.radians(60), 0, 0)
sc.collection.objects.link(cam)
sc.camera = cam

world = bpy.data.worlds.new("world")
sc.world = world
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
if fog:
    density, albedo, g = fog
    nodes, links = world.node_tree.nodes, world.node_tree.links
    scatter = nodes.new("ShaderNodeVolumeScatter")
    scatter.inputs["Color"].default_value = (albedo, albedo, albedo, 1.0)
    scatter.inputs["Density"].default_value = density
    scatter.inputs["Anisotropy"].default_value = g
    absorb = nodes.new("ShaderNodeVolumeAbsorption")
    absorb.inputs["Color"].default_value = (albedo, albedo, albedo, 1.0)
    absorb.inputs["Density"].default_value = density
    add = nodes.new("ShaderNodeAddShader")
    links.new(scatter.outputs[0], add.inputs[0])
    links.new(absorb.outputs[0], add.inputs[1])
    links.new(add.outputs[0], nodes["World Output"].inputs["Volume"])
    world.cycles.volume_sampling = "MULTIPLE_IMPORTANCE"
    world.cycles.homogeneous_volume = True
    cam_data.clip_start = 1e-5
    cam_data.clip_end = 1e5

sc.render.engine = "CYCLES"
cy = sc.cycles
cy.device = "CPU"
cy.samples = spp
cy.seed = 1
cy.use_adaptive_sampling = False
cy.use_denoising = False
cy.sample_clamp_direct = 0.0
cy.sample_clamp_indirect = 0.0
cy.light_sampling_threshold = 0.0
cy.use_light_tree = False
cy.pixel_filter_type = "BOX"
for attr in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces", "volume_bounces"):
    setattr(cy, attr, 0)
sc.render.resolution_x = 160
sc.render.resolution_y = 120
sc.render.resolution_percentage = 100
sc.render.film_transparent = False
sc.view_settings.view_transform = "Standard"
sc.view_settings.look = "None"
sc.view_layers[0].cycles.use_denoising = False

os.makedirs(out_dir, exist_ok=True)
bpy.ops.export_scene.gltf(filepath=os.path.join(out_dir, "spot-floor.gltf"),
                          export_format="GLTF_SEPARATE", export_lights=True, export_cameras=True)
bpy.ops.render.render(write_still=False)
ims = sc.render.image_settings
ims.file_format = "OPEN_EXR"
ims.color_mode = "RGB"
ims.color_depth = "32"
bpy.data.images["Render Result"].save_render(os.path.join(out_dir, "cycles.exr"), scene=sc)
print("wrote", out_dir)
