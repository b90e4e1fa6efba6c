#!/usr/bin/env python3
"""Renders fire-cycles.json with Blender 5's Cycles, the volume shaded by a
Principled Volume with blackbody emission: the peers' cycles_render.py
(../shared/peers, which sets up the camera, the integrator and the film
exactly as for every other reference) with its `add_vdb_volumes` replaced.

    pip install bpy==5.0.1        # Cycles 5: unbiased null-scattering volumes
    python cycles_fire.py PEERS_DIR fire-cycles.json --spp 1024 --seed 7 --out c1024_7

The node, per Cycles' kernel (intern/cycles/kernel/svm/closure.h,
svm_node_principled_volume; shipped in the wheel under
bpy/5.0/scripts/addons_core/cycles/source/kernel):
  * Density D = sigma_t with the "density" attribute: density = D * grid;
  * Color c = albedo: sigma_s = c * density;
  * Absorption Color black: sigma_a = (1 - c) * (1 - sqrt(0)) * density, so
    sigma_t = density and the albedo is c;
  * Emission Strength 0; Blackbody Intensity b, Blackbody Tint, and
    Temperature T0 with the "temperature" attribute: T = T0 * grid, and the
    emission sigma_SB * 1e-6 / pi * mix(1, T^4, b) * tint * colour(T),
    colour(T) Cycles' fit of the blackbody's Rec. 709 colour at luminance 1.

Tyndall's translation is fire-cycles.toml (`blackbody_law = "cycles"`).
"""
import os
import sys


def principled_vdb_volumes(bpy, scene):
    for i, v in enumerate(scene.get("volumes", [])):
        bb = v["blackbody"]
        vol = bpy.data.volumes.new(f"vol{i}")
        vol.filepath = os.path.join(scene["_dir"], v["file"])
        ob = bpy.data.objects.new(f"vol{i}", vol)
        bpy.context.scene.collection.objects.link(ob)
        mat = bpy.data.materials.new(f"volmat{i}")
        mat.use_nodes = True
        nt = mat.node_tree
        for n in list(nt.nodes):
            nt.nodes.remove(n)
        out = nt.nodes.new("ShaderNodeOutputMaterial")
        pv = nt.nodes.new("ShaderNodeVolumePrincipled")
        inputs = pv.inputs
        inputs["Density"].default_value = float(v["sigma_t"])
        inputs["Density Attribute"].default_value = v.get("grid", "density")
        inputs["Color"].default_value = (*[float(a) for a in v["albedo"]], 1.0)
        inputs["Absorption Color"].default_value = (0.0, 0.0, 0.0, 1.0)
        inputs["Anisotropy"].default_value = float(v.get("g", 0.0))
        inputs["Emission Strength"].default_value = 0.0
        inputs["Blackbody Intensity"].default_value = float(bb["intensity"])
        inputs["Blackbody Tint"].default_value = (*[float(a) for a in bb["tint"]], 1.0)
        inputs["Temperature"].default_value = float(bb["temperature"])
        inputs["Temperature Attribute"].default_value = bb["temperature_grid"]
        nt.links.new(pv.outputs[0], out.inputs["Volume"])
        vol.materials.append(mat)


if __name__ == "__main__":
    peers = os.path.abspath(sys.argv[1])
    sys.path.insert(0, peers)
    import cycles_render

    cycles_render.add_vdb_volumes = principled_vdb_volumes
    cycles_render.main(sys.argv[2:])
