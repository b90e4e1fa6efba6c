"""A normal map's orientation in Tyndall against Cycles (issue 22).

Writes two glTF floors lit by one sun from 50° off vertical on the −z side,
one plain and one with a 1×1 normal map that tilts its normal 45° towards
the sun if the map's +y points up its image (against glTF's v, as Blender
and Tyndall read it), and away from it otherwise. Blender's glTF importer
reads both and Cycles renders them; Tyndall renders the same files. The
ratio bumped/plain is the closed form cos 5°/cos 50° = 1.55 when the
orientation agrees, and below 1 when it does not.

Run with the peers' bpy (../../../shared/peers/setup.sh --with-cycles):
    .venv-bpy/bin/python scenes/gltf-samples/normal_map_check.py OUT_DIR
and then `tyndall render OUT_DIR/{flat,bumped}.gltf --spp 64 --width 32
--height 32 -o OUT_DIR/{flat,bumped}-tyndall.exr`.
"""

import json
import math
import os
import struct
import sys
import zlib


def png(path, rgb):
    """A 1×1 8-bit RGB PNG of the codes `rgb`."""
    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 1, 1, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(b"\x00" + bytes(rgb))) + chunk(b"IEND", b""))


def quaternion_from_to(a, b):
    """The unit quaternion (x, y, z, w) turning unit vector a onto b."""
    cross = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    q = (*cross, 1.0 + sum(x * y for x, y in zip(a, b)))
    norm = math.sqrt(sum(x * x for x in q))
    return [x / norm for x in q]


def write_floors(out):
    os.makedirs(out, exist_ok=True)
    png(os.path.join(out, "nmap.png"), [128, 218, 218])
    corners = [(-2, 0, -2), (2, 0, -2), (2, 0, 2), (-2, 0, 2)]
    uvs = [((x + 2) / 4, (z + 2) / 4) for x, _, z in corners]
    data = (b"".join(struct.pack("<3f", *p) for p in corners)
            + b"".join(struct.pack("<3f", 0, 1, 0) for _ in corners)
            + b"".join(struct.pack("<2f", *t) for t in uvs)
            + b"".join(struct.pack("<H", i) for i in [0, 2, 1, 0, 3, 2]))
    with open(os.path.join(out, "floor.bin"), "wb") as f:
        f.write(data)
    gamma = math.radians(50)
    towards_sun = (0.0, math.cos(gamma), -math.sin(gamma))
    sun = quaternion_from_to((0, 0, -1), tuple(-c for c in towards_sun))
    down = [-math.sqrt(0.5), 0, 0, math.sqrt(0.5)]
    for name, bumped in [("flat", False), ("bumped", True)]:
        material = {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1],
                                             "metallicFactor": 0.0, "roughnessFactor": 1.0},
                    "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}
        doc = {
            "asset": {"version": "2.0"},
            "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular"],
            "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional",
                                                                "intensity": 683.0}]}},
            "scenes": [{"nodes": [0, 1, 2]}],
            "nodes": [{"mesh": 0},
                      {"rotation": sun, "extensions": {"KHR_lights_punctual": {"light": 0}}},
                      {"translation": [0, 3, 0], "rotation": down, "camera": 0}],
            "cameras": [{"type": "perspective",
                         "perspective": {"yfov": 0.5, "aspectRatio": 1.0, "znear": 0.1}}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                        "indices": 3, "material": 0}]}],
            "materials": [material],
            "buffers": [{"uri": "floor.bin", "byteLength": len(data)}],
            "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                            {"buffer": 0, "byteOffset": 96, "byteLength": 32},
                            {"buffer": 0, "byteOffset": 128, "byteLength": 12}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                           "min": [-2, 0, -2], "max": [2, 0, 2]},
                          {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                          {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
                          {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}],
        }
        if bumped:
            material["normalTexture"] = {"index": 0}
            doc["images"] = [{"uri": "nmap.png"}]
            doc["textures"] = [{"source": 0}]
        with open(os.path.join(out, f"{name}.gltf"), "w") as f:
            json.dump(doc, f)


def render_in_cycles(out):
    import bpy
    import numpy as np
    means = {}
    for name in ["flat", "bumped"]:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        bpy.ops.import_scene.gltf(filepath=os.path.join(out, f"{name}.gltf"))
        scene = bpy.context.scene
        scene.camera = next(o for o in scene.objects if o.type == "CAMERA")
        scene.render.engine = "CYCLES"
        scene.cycles.samples = 64
        scene.render.resolution_x = scene.render.resolution_y = 32
        scene.render.resolution_percentage = 100
        scene.world = bpy.data.worlds.new("black")
        scene.world.color = (0, 0, 0)
        scene.view_settings.view_transform = "Standard"
        scene.render.image_settings.file_format = "OPEN_EXR"
        scene.render.filepath = os.path.join(out, f"{name}-cycles.exr")
        bpy.ops.render.render(write_still=True)
        image = bpy.data.images.load(scene.render.filepath)
        means[name] = float(np.array(image.pixels[:]).reshape(-1, 4)[:, :3].mean())
    print(f"Cycles: plain {means['flat']:.5f}, bumped {means['bumped']:.5f}, "
          f"ratio {means['bumped'] / means['flat']:.4f} "
          f"(closed form {math.cos(math.radians(5)) / math.cos(math.radians(50)):.4f})")


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "normal-map-check"
    write_floors(out)
    render_in_cycles(out)
