"""BoxTextured made to glow with its own texture: writes BoxGlowing.glb,
the Khronos "Box Textured" sample (BoxTextured/BoxTextured.glb, licence in
BoxTextured/LICENSE.md) whose material also has its base colour texture
as its `emissiveTexture`, at `emissiveFactor` 1 — a surface that emits
point by point and reflects as well, as the DamagedHelmet's lamps do:

    python3 scenes/gltf-samples/make_glowing_box.py OUT.glb

Only the JSON chunk of the .glb changes; the binary chunk (the mesh and
the PNG) is copied. Plain Python: no packages needed.
"""
import json
import os
import struct
import sys

GLB_MAGIC = 0x46546C67
JSON_CHUNK = 0x4E4F534A


def glowing(source):
    with open(source, "rb") as f:
        data = f.read()
    magic, version, _ = struct.unpack("<III", data[:12])
    if magic != GLB_MAGIC or version != 2:
        raise SystemExit(f"{source}: not a glTF 2.0 binary")
    json_length, kind = struct.unpack("<II", data[12:20])
    if kind != JSON_CHUNK:
        raise SystemExit(f"{source}: the first chunk is not JSON")
    doc = json.loads(data[20 : 20 + json_length])
    rest = data[20 + json_length :]
    material = doc["materials"][0]
    material["emissiveTexture"] = dict(material["pbrMetallicRoughness"]["baseColorTexture"])
    material["emissiveFactor"] = [1.0, 1.0, 1.0]
    material["name"] = "Glowing"
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    header = struct.pack("<III", GLB_MAGIC, 2, 12 + 8 + len(text) + len(rest))
    return header + struct.pack("<II", len(text), JSON_CHUNK) + text + rest


def main():
    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    here = os.path.dirname(os.path.abspath(__file__))
    out = glowing(os.path.join(here, "BoxTextured", "BoxTextured.glb"))
    with open(sys.argv[1], "wb") as f:
        f.write(out)


if __name__ == "__main__":
    main()
