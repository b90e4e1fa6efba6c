"""Builds a small room in Blender (bpy 4.5.15) and exports it with Blender's
own glTF exporter (default "Standard" lighting mode) to fog-room.gltf:

    /work/bpy-venv/bin/python scenes/blender/make_fog_room.py scenes/blender

Lights and materials are chosen to exercise the loader's conversions:
a 400 W spot (40° cone, blend 0 → hard edge), a 60 W spot with blend 0.5
(smooth), a 30 W point light, a 2 W/m² sun, an emissive panel (strength 4),
a Lambert floor (Principled, IOR level 0 → specularFactor 0), a metal box
and a thin red glass pane (transmission 1). Tyndall renders it with fog
from the command line:

    tyndall render scenes/blender/fog-room.gltf --density 0.05 --albedo 0.9 --g 0.3

This file is the one source of truth for the scene: `build_scene()` makes
it in the current Blender session (optionally without some of its parts,
see `COMPONENTS`), `export_gltf()` writes it. cycles_fog_room.py imports
both to render the same scene with Cycles. Blender units are metres, Z up;
the exporter converts to glTF's Y up. Lights have radius 0, soft falloff
off and the sun an angle of 0, i.e. true point, spot and directional
lights as Tyndall's (these settings do not change the exported file).
"""
import math
import os
import sys

import bpy

# The parts of the scene that build_scene(without=...) can leave out: the
# four lights, the emissive panel (its object), the metal box, the glass pane.
COMPONENTS = ("hard-spot", "soft-spot", "bulb", "sun", "panel", "box", "pane")


def principled(name, color, metallic=0.0, roughness=0.5, ior_level=None,
               transmission=0.0, emission=None, strength=0.0):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    p = m.node_tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (*color, 1.0)
    p.inputs["Metallic"].default_value = metallic
    p.inputs["Roughness"].default_value = roughness
    if ior_level is not None:
        p.inputs["Specular IOR Level"].default_value = ior_level
    p.inputs["Transmission Weight"].default_value = transmission
    if emission is not None:
        p.inputs["Emission Color"].default_value = (*emission, 1.0)
        p.inputs["Emission Strength"].default_value = strength
    return m


def add(obj_op, material, **kw):
    obj_op(**kw)
    obj = bpy.context.active_object
    obj.data.materials.append(material)
    return obj


def light(scene, kind, name, energy, location, rotation=(0, 0, 0), **props):
    data = bpy.data.lights.new(name, kind)
    data.energy = energy
    if kind != "SUN":
        data.use_soft_falloff = False
    for k, v in props.items():
        setattr(data, k, v)
    obj = bpy.data.objects.new(name, data)
    obj.location = location
    obj.rotation_euler = rotation
    scene.collection.objects.link(obj)
    return obj


def build_scene(without=()):
    """Builds the room in a fresh (factory settings, empty) Blender session
    and returns {name: object} for the floor, the COMPONENTS present and
    the camera. `without`: names from COMPONENTS to leave out."""
    unknown = set(without) - set(COMPONENTS)
    if unknown:
        raise ValueError(f"unknown components {sorted(unknown)}; known: {COMPONENTS}")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    objs = {}
    objs["floor"] = add(bpy.ops.mesh.primitive_plane_add,
                        principled("floor", (0.8, 0.8, 0.8), ior_level=0.0),
                        size=8, location=(0, 0, 0))
    if "box" not in without:
        objs["box"] = add(bpy.ops.mesh.primitive_cube_add,
                          principled("metal", (0.9, 0.6, 0.3), metallic=1.0, roughness=0.2),
                          size=1, location=(1.2, 0.5, 0.5))
    if "pane" not in without:
        objs["pane"] = add(bpy.ops.mesh.primitive_plane_add,
                           principled("red-glass", (0.9, 0.1, 0.1), transmission=1.0, ior_level=0.0),
                           size=1.2, location=(-1.0, 0.0, 1.5), rotation=(math.radians(90), 0, 0))
    if "panel" not in without:
        objs["panel"] = add(bpy.ops.mesh.primitive_plane_add,
                            principled("panel", (0.0, 0.0, 0.0), emission=(1.0, 0.9, 0.7), strength=4.0),
                            size=0.5, location=(0, -3.5, 2.0), rotation=(math.radians(-90), 0, 0))

    if "hard-spot" not in without:
        objs["hard-spot"] = light(scene, "SPOT", "hard-spot", 400.0, (0, 0, 4),
                                  spot_size=math.radians(40), spot_blend=0.0, shadow_soft_size=0.0)
    if "soft-spot" not in without:
        objs["soft-spot"] = light(scene, "SPOT", "soft-spot", 60.0, (2, -2, 3),
                                  rotation=(math.radians(30), 0, math.radians(45)),
                                  spot_size=math.radians(50), spot_blend=0.5, shadow_soft_size=0.0)
    if "bulb" not in without:
        objs["bulb"] = light(scene, "POINT", "bulb", 30.0, (-2, 2, 2.5), shadow_soft_size=0.0)
    if "sun" not in without:
        objs["sun"] = light(scene, "SUN", "sun", 2.0, (0, 0, 10),
                            rotation=(math.radians(20), math.radians(10), 0), angle=0.0)

    cam_data = bpy.data.cameras.new("camera")
    cam_data.lens_unit = "FOV"
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = math.radians(45)
    cam = bpy.data.objects.new("camera", cam_data)
    cam.location = (0, -7, 2.5)
    cam.rotation_euler = (math.radians(80), 0, 0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    objs["camera"] = cam
    scene.render.resolution_x = 320
    scene.render.resolution_y = 240
    return objs


def export_gltf(path):
    """Writes the current scene with Blender's glTF exporter (.gltf + .bin,
    lights in the default "Standard" mode, cameras, Y up)."""
    bpy.ops.export_scene.gltf(filepath=path, export_format="GLTF_SEPARATE", export_lights=True,
                              export_cameras=True, export_yup=True)


if __name__ == "__main__":
    out_dir = sys.argv[-1] if len(sys.argv) > 1 else "."
    build_scene()
    path = os.path.join(out_dir, "fog-room.gltf")
    export_gltf(path)
    print("wrote", path)
