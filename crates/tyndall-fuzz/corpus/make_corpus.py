#!/usr/bin/env python3
"""Writes the fuzzer's regression corpus: one minimal reproducer of each
crash, hang and runaway read of the second fuzzing campaign (issue 28),
in the folder of the target that replays it (see ../src/main.rs).

    python3 make_corpus.py            # from this folder; standard library only

The VDB reproducers are made from the OpenVDB-written test file
crates/tyndall-tests/tests/data/sphere.vdb by editing its header fields,
whose offsets follow from OpenVDB's file layout (io/File.cc, Archive.cc):
an 8-byte magic, the file version, the library's major and minor version
(u32 each), a has-grid-offsets byte, a 36-character UUID, then the file's
metadata count (u32) and entries, each a name string (u32 length + bytes).
"""
import base64
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def write(target, name, data):
    folder = os.path.join(HERE, target)
    os.makedirs(folder, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


def triangle_buffer(textured=False):
    """Positions of one triangle (36 bytes), u16 indices (6 + 2 padding),
    and with `textured` f32 texture coordinates (24 bytes)."""
    data = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    data += struct.pack("<3H", 0, 1, 2) + b"\0\0"
    if textured:
        data += struct.pack("<6f", 0, 0, 1, 0, 0, 1)
    return data


def document(textured=False, uri=True):
    """A glTF document of one triangle seen by a camera; the buffer as a
    data: URI (self-contained) or without a uri (a .glb's BIN chunk)."""
    data = triangle_buffer(textured)
    buffer = {"byteLength": len(data)}
    if uri:
        buffer["uri"] = "data:application/octet-stream;base64," + base64.b64encode(data).decode()
    views = [
        {"buffer": 0, "byteOffset": 0, "byteLength": 36},
        {"buffer": 0, "byteOffset": 36, "byteLength": 6},
    ]
    accessors = [
        {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
         "min": [0, 0, 0], "max": [1, 1, 0]},
        {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
    ]
    attributes = {"POSITION": 0}
    if textured:
        views.append({"buffer": 0, "byteOffset": 44, "byteLength": 24})
        accessors.append({"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"})
        attributes["TEXCOORD_0"] = 2
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"translation": [0.2, 0.2, 3.0], "camera": 0}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": 1, "material": 0}]}],
        "materials": [{}],
        "buffers": [buffer],
        "bufferViews": views,
        "accessors": accessors,
    }
    return doc, data


def glb(doc, bin_chunk, claimed_length=None):
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    bin_chunk += b"\0" * (-len(bin_chunk) % 4)
    total = 12 + 8 + len(js) + 8 + len(bin_chunk)
    out = b"glTF" + struct.pack("<II", 2, claimed_length if claimed_length is not None else total)
    out += struct.pack("<I", len(js)) + b"JSON" + js
    out += struct.pack("<I", len(bin_chunk)) + b"BIN\0" + bin_chunk
    return out


def textured(doc, image):
    doc["images"] = [image]
    doc["textures"] = [{"source": 0}]
    doc["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]


def chain(n, fanout):
    """Nodes 0 → 1 → … → n−1, the last carrying the mesh; `fanout` copies
    of each child link (2 makes a DAG of 2^(n−1) paths)."""
    doc, _ = document()
    nodes = [{"children": [i + 1] * fanout} for i in range(n - 1)] + [{"mesh": 0}]
    doc["nodes"] = nodes + [{"translation": [0.2, 0.2, 3.0], "camera": 0}]
    doc["scenes"] = [{"nodes": [0, n]}]
    return json.dumps(doc)


def gltf_cases():
    doc, _ = document()
    doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 7
    write("gltf", "position-names-missing-accessor.gltf", json.dumps(doc))

    doc, _ = document(textured=True)
    textured(doc, {"bufferView": 0})
    write("gltf", "image-view-without-mime-type.gltf", json.dumps(doc))

    doc, _ = document(textured=True)
    textured(doc, {"name": "nothing"})
    write("gltf", "image-without-uri-or-view.gltf", json.dumps(doc))

    doc, _ = document()
    doc["cameras"][0]["type"] = "orthographic"
    write("gltf", "orthographic-type-perspective-object.gltf", json.dumps(doc))

    doc, data = document(textured=True)
    textured(doc, {"uri": "data:image/png;base64,"})
    doc["accessors"][2]["componentType"] = 5125  # u32 TEXCOORD_0
    doc["accessors"][2]["count"] = 3
    write("gltf", "texcoord-u32.gltf", json.dumps(doc))

    doc, _ = document()
    doc["buffers"][0] = {"uri": "/dev/zero", "byteLength": 4}
    write("gltf", "buffer-uri-dev-zero.gltf", json.dumps(doc))

    doc, _ = document()
    doc["cameras"][0]["perspective"]["yfov"] = 3.2
    write("gltf", "camera-yfov-past-pi.gltf", json.dumps(doc))

    write("gltf", "node-chain-30000.gltf", chain(30000, 1))
    write("gltf", "node-dag-2pow26.gltf", chain(27, 2))
    # 2^15 instances of one triangle, all in one place: the BVH build.
    write("render", "node-dag-32768-coincident.gltf", chain(16, 2))


def png_2x2():
    """A 2×2 RGB PNG (red, green, blue, white), written by hand: the
    signature, IHDR, one zlib-compressed IDAT, IEND."""
    import zlib

    def chunk(kind, body):
        crc = zlib.crc32(kind + body) & 0xFFFFFFFF
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", crc)

    rows = b"\0" + bytes([255, 0, 0, 0, 255, 0]) + b"\0" + bytes([0, 0, 255, 255, 255, 255])
    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 2, 0, 0, 0))
        + chunk(b"IDAT", zlib.compress(rows))
        + chunk(b"IEND", b"")
    )


def glb_cases():
    # Valid seeds for the mutations: a plain triangle, and one textured
    # by a PNG inside the BIN chunk.
    doc, data = document(uri=False)
    write("glb", "seed-triangle.glb", glb(doc, data))
    doc, data = document(textured=True, uri=False)
    png = png_2x2()
    doc["bufferViews"].append({"buffer": 0, "byteOffset": len(data), "byteLength": len(png)})
    data += png
    doc["buffers"][0]["byteLength"] = len(data)
    textured(doc, {"bufferView": 3, "mimeType": "image/png"})
    write("glb", "seed-textured-triangle.glb", glb(doc, data))
    write("render", "seed-textured-triangle.glb", glb(doc, data))

    doc, data = document(uri=False)
    write("glb", "header-claims-4gib.glb", glb(doc, data, claimed_length=0xFFFFFFFF))

    doc, data = document(textured=True, uri=False)
    doc["bufferViews"].append({"buffer": 0, "byteOffset": 60, "byteLength": 64})
    textured(doc, {"bufferView": 3, "mimeType": "image/png"})
    write("glb", "image-view-past-its-buffer.glb", glb(doc, data[:8]))


def obj_cases():
    faces = "v 0 0 0\nv 1 0 0\nv 0 1 0\n" + "f 1 2 3\n" * 32768
    write("mesh", "one-triangle-32768-times.obj", faces)
    # The paper's format takes quads: 32,768 copies of one (65,536
    # coincident triangles), lit by a small emitting quad above them.
    scene = (
        "PerspectiveCamera {\ncamera_position < 0.2, 0.2, 3 >\npoint_of_interest < 0.2, 0.2, 0 >\n"
        "up < 0, 1, 0 >\nangle 40\n}\n"
        "material\ndiffuse 0 0 0\nreflective 0 0 0\nemitted 100 100 100\n\n"
        "material\ndiffuse 0.5 0.5 0.5\nreflective 0 0 0\nemitted 0 0 0\n\n"
        "m 0\nv 0 0 2\nv 0.1 0 2\nv 0.1 0.1 2\nv 0 0.1 2\nf 1 2 3 4\n\nm 1\n"
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n" + "f 5 6 7 8\n" * 32768
    )
    write("render", "legacy-one-quad-32768-times.obj", scene)
    write(
        "legacy",
        "camera-angle-179.5.obj",
        "PerspectiveCamera {\ncamera_position < 0, 0, 5 >\npoint_of_interest < 0, 0, 0 >\n"
        "up < 0, 1, 0 >\nangle 179.5\n}\n",
    )


def render_cases():
    write(
        "render",
        "far-emissive-sphere-volpath.toml",
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, -10000]\nfov_y_deg = 0.02\n"
        "[render]\nintegrator = \"volpath\"\n[fog]\nsigma_t = 1e-5\nalbedo = 0.5\n"
        "[materials.e]\ntype = \"emissive\"\nradiance = 100\n"
        "[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, -10000]\nradius = 1\nmaterial = \"e\"\n",
    )
    write(
        "render",
        "endless-lossless-fog-volpath.toml",
        "[camera]\nposition = [0, 2, 7]\nlook_at = [0, 1.4, 0]\nfov_y_deg = 45\n"
        "[render]\nintegrator = \"volpath\"\n[fog]\nsigma_t = 0.1\nalbedo = 1\n"
        "[[lights]]\ntype = \"spot\"\nposition = [0, 4, 0]\ndirection = [0, -1, 0]\n"
        "cutoff_deg = 30\nintensity = 60\n",
    )


def vdb_cases():
    source = os.path.join(HERE, "../../tyndall-tests/tests/data/sphere.vdb")
    with open(source, "rb") as f:
        vdb = f.read()
    metadata_count = 8 + 4 + 4 + 4 + 1 + 36
    first_name = metadata_count + 4

    def patched(at, value):
        return vdb[:at] + struct.pack("<I", value) + vdb[at + 4:]

    write("vdb", "truncated-half.vdb", vdb[: len(vdb) // 2])
    write("vdb", "truncated-header.vdb", vdb[:40])
    write("vdb", "metadata-count-4g.vdb", patched(metadata_count, 0xFFFFFFFF))
    write("vdb", "metadata-name-length-4g.vdb", patched(first_name, 0xFFFFFFFF))
    # Every u32 that could be a count or length, from the tail: the leaf
    # and node data of the grid.
    for k, at in enumerate(range(len(vdb) - 4096, len(vdb) - 4, 997)):
        write("vdb", f"word-{k}-4g.vdb", patched(at, 0xFFFFFFFF))


if __name__ == "__main__":
    gltf_cases()
    glb_cases()
    obj_cases()
    render_cases()
    vdb_cases()
