"""The fog room of make_fog_room.py rendered by Cycles, for comparison with
Tyndall's render of the glTF file Blender exports from the same scene:

    /work/bpy-venv/bin/python scenes/blender/cycles_fog_room.py OUT_DIR \
        [--density D --albedo A --g G] [--bounces N] [--without PART ...] \
        [--spp-per-pass 64 --passes 16 --seed 1] [--width 160 --height 120] \
        [--glass thin|principled] [--metal principled|glossy] [--glossy-sees-lamps 1|0]

builds the scene with make_fog_room.build_scene (the one source of truth;
`--without` leaves out parts of make_fog_room.COMPONENTS), exports it with
Blender's glTF exporter to OUT_DIR/fog-room.gltf (+ .bin) exactly as
make_fog_room.py does, then renders it with Cycles and writes

    OUT_DIR/cycles.exr        the mean of all passes (linear RGB, float32)
    OUT_DIR/cycles-half0.exr  the mean of the even passes
    OUT_DIR/cycles-half1.exr  the mean of the odd passes
    OUT_DIR/cycles.json       settings, sample counts, times, the halves' relMSE

Each pass renders --spp-per-pass samples with its own seed (seed + pass);
passes are accumulated in float64 (a float32 film loses precision over
many samples). relMSE(half0, half1)/4 estimates the error of cycles.exr
itself (each half has twice its variance; relMSE as tyndall compare and
shared/peers/compare.py: mean((a − b)²/(b² + 0.01))). The Tyndall side:

    tyndall render OUT_DIR/fog-room.gltf --width 160 --height 120 \
        --density D --albedo A --g G --integrator volpath --spp S -o OUT_DIR/tyndall.exr
    tyndall compare OUT_DIR/tyndall.exr OUT_DIR/cycles.exr

Conventions and Cycles settings (as shared/peers/cycles_render.py):
  * CPU, path tracing, no denoising, no adaptive sampling, no clamping
    (direct and indirect), light_sampling_threshold 0, light tree off, no
    path guiding, box pixel filter (1 px: uniform over the pixel, as
    Tyndall), Standard view transform (irrelevant for EXR: linear);
  * --bounces N sets max, diffuse, glossy, transmission and volume bounces
    to N (default 1024 = full multiple scattering, compare with Tyndall's
    volpath); 0 is direct light at the first hit and single scattering in
    the fog (Cycles always does next-event estimation at the first vertex),
    compare with Tyndall's `single`. Transparent crossings do not count:
    transparent_max_bounces 1024;
  * fog: the World's volume = Volume Scatter (colour A, density D,
    Henyey-Greenstein anisotropy G) + Volume Absorption (colour A, density
    D), i.e. sigma_s = A*D, sigma_a = (1 - A)*D, sigma_t = D: Tyndall's
    --density D --albedo A --g G. Homogeneous, sampled by distance +
    equiangular MIS; black background not sampled as a light; camera clip
    start 1e-5 (set after the export) so fog starts at the lens;
  * lights as make_fog_room.py builds them: radius 0, soft falloff off,
    sun angle 0 (a Blender point/spot of power P has I = P/(4 pi) W/sr, as
    Tyndall reads the exported candela / 683);
  * --glass thin (default): the pane's Principled transmission material is
    replaced, for Cycles only, by a Transparent BSDF of colour = its base
    colour: Tyndall's thin glass (glTF transmission without
    KHR_materials_volume → a pane of transmittance = base colour, alpha 1,
    that tints camera and shadow rays and never bends them). --glass
    principled keeps Blender's material: a refracting IOR 1.5 interface
    that bends camera rays and blocks shadow rays from point lights;
  * --metal principled (default) keeps the box's Principled metallic GGX
    (roughness 0.2 → alpha 0.04, F82-tint Fresnel, multiscatter GGX);
    --metal glossy replaces it by a Glossy BSDF (multiscatter GGX, same
    roughness, colour = base colour, no Fresnel): constant reflectance, as
    Tyndall's glossy layer (also a GGX lobe, its multiple scattering
    restored);
  * --glossy-sees-lamps 0 makes the point, spot and sun lights invisible
    to glossy rays (Cycles' per-light ray visibility), which was Tyndall's
    model until its glossy layers became GGX lobes that reflect delta
    lights by next event estimation (scenes/blender/README.md, "Glossy
    layers and delta lights"); the default, 1, is Blender's.
"""
import argparse
import json
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)


def rel_mse(a, b, eps=0.01):
    a = a.astype(np.float64)
    b = b.astype(np.float64)
    return float(np.mean((a - b) ** 2 / (b * b + eps)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out_dir")
    ap.add_argument("--density", type=float, default=0.0)
    ap.add_argument("--albedo", type=float, default=1.0)
    ap.add_argument("--g", type=float, default=0.0)
    ap.add_argument("--bounces", type=int, default=1024)
    ap.add_argument("--without", nargs="*", default=[])
    ap.add_argument("--spp-per-pass", type=int, default=64)
    ap.add_argument("--passes", type=int, default=16)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=120)
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--glass", choices=["thin", "principled"], default="thin")
    ap.add_argument("--metal", choices=["principled", "glossy"], default="principled")
    ap.add_argument("--glossy-sees-lamps", type=int, default=1)
    args = ap.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
    if args.passes < 2 or args.passes % 2:
        raise SystemExit("--passes must be even and at least 2 (two halves)")

    import bpy
    import cycles_settings
    import make_fog_room

    objs = make_fog_room.build_scene(without=args.without)
    sc = bpy.context.scene
    os.makedirs(args.out_dir, exist_ok=True)
    make_fog_room.export_gltf(os.path.join(args.out_dir, "fog-room.gltf"))

    # ---- Cycles-only changes, after the export
    if "pane" in objs and args.glass == "thin":
        mat = objs["pane"].data.materials[0]
        nt = mat.node_tree
        base = nt.nodes["Principled BSDF"].inputs["Base Color"].default_value[:3]
        tr = nt.nodes.new("ShaderNodeBsdfTransparent")
        tr.inputs["Color"].default_value = (*base, 1.0)
        nt.links.new(tr.outputs["BSDF"], nt.nodes["Material Output"].inputs["Surface"])
    if "box" in objs and args.metal == "glossy":
        mat = objs["box"].data.materials[0]
        nt = mat.node_tree
        p = nt.nodes["Principled BSDF"]
        gl = nt.nodes.new("ShaderNodeBsdfGlossy")
        gl.distribution = "MULTI_GGX"
        gl.inputs["Color"].default_value = p.inputs["Base Color"].default_value
        gl.inputs["Roughness"].default_value = p.inputs["Roughness"].default_value
        nt.links.new(gl.outputs["BSDF"], nt.nodes["Material Output"].inputs["Surface"])
    for name in ("hard-spot", "soft-spot", "bulb", "sun"):
        if name in objs:
            objs[name].visible_glossy = bool(args.glossy_sees_lamps)
            objs[name].data.cycles.max_bounces = 1024
    cam = objs["camera"].data
    cam.clip_start = 1e-5
    cam.clip_end = 1e5

    cycles_settings.world_fog(sc, args.density, args.albedo, args.g)
    cycles_settings.unbiased(sc, args.spp_per_pass, args.bounces, args.threads)
    cy = sc.cycles
    sc.render.resolution_x = args.width
    sc.render.resolution_y = args.height
    sc.render.resolution_percentage = 100
    ims = sc.render.image_settings
    ims.file_format = "OPEN_EXR"
    ims.color_mode = "RGB"
    ims.color_depth = "32"
    ims.exr_codec = "ZIP"

    tmp = os.path.join(args.out_dir, "cycles-pass.exr")
    halves = [np.zeros((args.height, args.width, 3), np.float64) for _ in range(2)]
    t0 = time.perf_counter()
    for i in range(args.passes):
        cy.seed = args.seed + i
        bpy.ops.render.render(write_still=False)
        bpy.data.images["Render Result"].save_render(tmp, scene=sc)
        img = bpy.data.images.load(tmp, check_existing=False)
        px = np.empty(args.width * args.height * 4, np.float32)
        img.pixels.foreach_get(px)
        bpy.data.images.remove(img)
        halves[i % 2] += px.reshape(args.height, args.width, 4)[:, :, :3]
        print(f"pass {i + 1}/{args.passes} seed {cy.seed}: {time.perf_counter() - t0:.1f} s",
              flush=True)
    os.remove(tmp)
    render_s = time.perf_counter() - t0
    n_half = args.passes // 2
    h0, h1 = halves[0] / n_half, halves[1] / n_half
    mean = (halves[0] + halves[1]) / args.passes

    def write(name, rgb):
        # bpy image pixels are bottom-up rows, as read above: written back unchanged
        img = bpy.data.images.new(name, args.width, args.height, alpha=True, float_buffer=True)
        px = np.ones((args.height, args.width, 4), np.float32)
        px[:, :, :3] = rgb
        img.pixels.foreach_set(px.ravel())
        img.save_render(os.path.join(args.out_dir, name), scene=sc)
        bpy.data.images.remove(img)

    write("cycles.exr", mean)
    write("cycles-half0.exr", h0)
    write("cycles-half1.exr", h1)
    halves_rel = rel_mse(h0, h1)
    meta = {
        "blender_version": bpy.app.version_string,
        "args": vars(args),
        "spp_total": args.spp_per_pass * args.passes,
        "render_wall_s": render_s,
        "relmse_half0_half1": halves_rel,
        "estimated_relmse_of_mean": halves_rel / 4,
        "mean_rgb": [float(x) for x in mean.reshape(-1, 3).mean(0)],
    }
    with open(os.path.join(args.out_dir, "cycles.json"), "w") as f:
        json.dump(meta, f, indent=1)
    print(json.dumps(meta))


if __name__ == "__main__":
    main()
