"""Environment-light references made by Mitsuba 3 (issue 22).

Four scenes, one geometry — a diffuse sphere and block on a grey floor —
lit only by an environment: Mitsuba's `constant` emitter, and its `envmap`
with the procedural sky written here (a blue gradient, a dim ground and a
soft sun: `sky.exr` for Tyndall, `sky-mitsuba.exr` for Mitsuba, see
`sky`), each without and with a box of fog around the
geometry (the camera outside it). For each scene this writes the Tyndall
scene (`<name>.toml`), Mitsuba's render (`<name>.exr`, the mean of two
halves of independent seeds) and `<name>.ref.json` (sample count, time and
the reference's own relMSE estimated from its halves).

Run in the peers' venv (../../../../shared/peers/setup.sh):
    .venv/bin/python scenes/reference/environment/make_references.py [--spp N]

With `--time`, it instead times Mitsuba on the map scenes against the
references it made (relMSE and seconds of `mi.render` at 16 and 64 spp,
after a warm-up render for the JIT), for docs/benchmarks.md; Tyndall's side
is `tyndall render SCENE.toml --spp N -o OUT.exr` under `time`, compared by
`tyndall compare OUT.exr SCENE.exr`.
"""

import argparse
import json
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
WIDTH, HEIGHT = 320, 240

CAMERA = {"position": [0.0, 1.3, 4.2], "look_at": [0.0, 0.45, 0.0], "fov_y_deg": 38.0}
FLOOR = [[-2.0, 0.0, -2.0], [-2.0, 0.0, 2.0], [2.0, 0.0, 2.0], [2.0, 0.0, -2.0]]
SPHERE = {"center": [-0.35, 0.5, 0.1], "radius": 0.5}
BLOCK = {"min": [0.45, 0.0, -0.75], "max": [1.15, 0.7, -0.05]}
REFLECTANCE = {"floor": [0.6, 0.6, 0.6], "sphere": [0.8, 0.5, 0.3], "block": [0.3, 0.55, 0.75]}
CONSTANT = [0.55, 0.7, 0.9]
FOG = {"sigma_t": 0.35, "albedo": [0.9, 0.9, 0.9], "g": 0.3,
       "min": [-2.5, -0.05, -2.5], "max": [2.5, 2.2, 2.5]}

SCENES = {
    "env-constant": {"map": False, "fog": False},
    "env-constant-fog": {"map": False, "fog": True},
    "env-map": {"map": True, "fog": False},
    "env-map-fog": {"map": True, "fog": True},
}


def sky(width=256, height=128, rows="centres"):
    """Linear radiance of the procedural sky, rows from the top (+y), sampled
    where the renderer reads its texels: columns at u = (i + 1/2)/W in both;
    rows at v = (j + 1/2)/H in Tyndall (and Cycles: `rows="centres"`), at
    v = j/(H − 1), the poles included, in Mitsuba 3's envmap (`rows="poles"`,
    found by probing its `eval`). The two files hold one sky, so the
    comparison tests the lighting, not the files' conventions."""
    if rows == "centres":
        v = (np.arange(height) + 0.5) / height
    else:
        v = np.arange(height) / (height - 1)
    u = (np.arange(width) + 0.5) / width
    theta = np.pi * v[:, None]
    phi = 2 * np.pi * u[None, :]
    # Mitsuba's envmap directions (and Tyndall's): u = atan2(x, -z)/2π, v = acos(y)/π.
    d = np.stack([np.sin(theta) * np.sin(phi), np.cos(theta) * np.ones_like(phi),
                  -np.sin(theta) * np.cos(phi)], axis=-1)
    up = np.clip(d[..., 1], 0.0, 1.0)[..., None]
    zenith = np.array([0.25, 0.4, 0.85])
    horizon = np.array([0.8, 0.85, 0.9])
    ground = np.array([0.15, 0.12, 0.09])
    above = horizon + (zenith - horizon) * np.sqrt(up)
    image = np.where(d[..., 1:2] >= 0.0, above, ground)
    sun = np.array([np.cos(np.radians(40)) * np.sin(np.radians(60)), np.sin(np.radians(40)),
                    np.cos(np.radians(40)) * np.cos(np.radians(60))])
    angle = np.arccos(np.clip(d @ sun, -1.0, 1.0))
    glow = np.exp(-0.5 * (angle / np.radians(6.0)) ** 2)[..., None]
    image = image + 40.0 * glow * np.array([1.0, 0.9, 0.75])
    return image.astype(np.float32)


def tyndall_toml(name, spec):
    lines = [f"# {name}: Mitsuba 3 reference (scenes/reference/environment/make_references.py).",
             "", "[camera]"]
    lines += [f"{k} = {json.dumps(v)}" for k, v in CAMERA.items()]
    lines += ["up = [0.0, 1.0, 0.0]", "", "[render]", f"width = {WIDTH}", f"height = {HEIGHT}",
              'integrator = "volpath"', ""]
    if spec["fog"]:
        lines += ["[fog]", f"sigma_t = {FOG['sigma_t']}", f"albedo = {FOG['albedo']}",
                  f"g = {FOG['g']}", f"box = {{ min = {FOG['min']}, max = {FOG['max']} }}", ""]
    for m, r in REFLECTANCE.items():
        lines += [f"[materials.{m}]", 'type = "diffuse"', f"reflectance = {r}", ""]
    lines += ["[[shapes]]", 'type = "quad"', f"corners = {FLOOR}", 'material = "floor"', ""]
    lines += ["[[shapes]]", 'type = "sphere"', f"center = {SPHERE['center']}",
              f"radius = {SPHERE['radius']}", 'material = "sphere"', ""]
    lines += ["[[shapes]]", 'type = "box"', f"min = {BLOCK['min']}", f"max = {BLOCK['max']}",
              'material = "block"', ""]
    lines += ["[[lights]]", 'type = "environment"']
    lines += ['map = "sky.exr"'] if spec["map"] else [f"radiance = {CONSTANT}"]
    return "\n".join(lines) + "\n"


def mitsuba_scene(mi, spec, spp, seed):
    med = None
    if spec["fog"]:
        med = mi.load_dict({"type": "homogeneous", "sigma_t": FOG["sigma_t"],
                            "albedo": {"type": "rgb", "value": FOG["albedo"]},
                            "phase": {"type": "hg", "g": FOG["g"]}})

    def diffuse(r):
        return {"type": "twosided", "bsdf": {"type": "diffuse",
                                             "reflectance": {"type": "rgb", "value": r}}}

    def inside(d):
        if med is not None:
            d["interior"] = med
            d["exterior"] = med
        return d

    T = mi.ScalarTransform4f
    c = np.array(FLOOR)
    centre = c.mean(axis=0)
    d = {"type": "scene",
         "integrator": {"type": "volpath", "max_depth": -1},
         "sensor": {"type": "perspective", "fov": CAMERA["fov_y_deg"], "fov_axis": "y",
                    "to_world": T().look_at(origin=CAMERA["position"], target=CAMERA["look_at"],
                                            up=[0, 1, 0]),
                    "film": {"type": "hdrfilm", "width": WIDTH, "height": HEIGHT,
                             "rfilter": {"type": "box"}, "pixel_format": "rgb"},
                    "sampler": {"type": "independent", "sample_count": spp, "seed": seed}},
         # Mitsuba's rectangle spans [-1, 1]² in xy facing +z: turned to face +y.
         "floor": inside({"type": "rectangle", "bsdf": diffuse(REFLECTANCE["floor"]),
                          "to_world": T().translate(centre.tolist()).rotate([1, 0, 0], -90)
                          .scale([2.0, 2.0, 1.0])}),
         "sphere": inside({"type": "sphere", "center": SPHERE["center"],
                           "radius": SPHERE["radius"], "bsdf": diffuse(REFLECTANCE["sphere"])}),
         "block": inside({"type": "cube", "bsdf": diffuse(REFLECTANCE["block"]),
                          "to_world": T().translate(((np.array(BLOCK["min"]) + BLOCK["max"]) / 2)
                                                    .tolist())
                          .scale(((np.array(BLOCK["max"]) - BLOCK["min"]) / 2).tolist())})}
    if spec["map"]:
        d["emitter"] = {"type": "envmap", "filename": os.path.join(HERE, "sky-mitsuba.exr")}
    else:
        d["emitter"] = {"type": "constant", "radiance": {"type": "rgb", "value": CONSTANT}}
    if med is not None:
        lo, hi = np.array(FOG["min"]), np.array(FOG["max"])
        d["fog"] = {"type": "cube", "bsdf": {"type": "null"}, "interior": med,
                    "to_world": T().translate(((lo + hi) / 2).tolist()).scale(((hi - lo) / 2).tolist())}
    return mi.load_dict(d)


def relmse(a, b):
    return float(np.mean((a - b) ** 2 / (b ** 2 + 1e-2)))


def time_mitsuba(mi, names, spps=(16, 64)):
    """Prints relMSE against each reference and the seconds of one render."""
    for name in names:
        reference = np.asarray(mi.Bitmap(os.path.join(HERE, f"{name}.exr")),
                               dtype=np.float64)[..., :3]
        for spp in spps:
            scene = mitsuba_scene(mi, SCENES[name], spp, 7)
            mi.render(scene, spp=4, seed=1)  # the JIT's warm-up
            start = time.time()
            image = np.asarray(mi.render(scene, spp=spp, seed=7), dtype=np.float64)[..., :3]
            elapsed = time.time() - start
            print(f"{name}, {spp} spp: relMSE {relmse(image, reference):.3e}, {elapsed:.2f} s",
                  flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp", type=int, default=2048, help="samples per pixel of each half")
    ap.add_argument("--pass-spp", type=int, default=64)
    ap.add_argument("--only", nargs="*", default=list(SCENES))
    ap.add_argument("--time", action="store_true",
                    help="time Mitsuba on the map scenes instead of making references")
    args = ap.parse_args()
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    if args.time:
        time_mitsuba(mi, ["env-map", "env-map-fog"])
        return
    mi.Bitmap(sky()).write(os.path.join(HERE, "sky.exr"))
    mi.Bitmap(sky(rows="poles")).write(os.path.join(HERE, "sky-mitsuba.exr"))
    for name in args.only:
        spec = SCENES[name]
        with open(os.path.join(HERE, f"{name}.toml"), "w") as f:
            f.write(tyndall_toml(name, spec))
        start = time.time()
        halves = []
        for half in range(2):
            total = np.zeros((HEIGHT, WIDTH, 3))
            passes = max(1, args.spp // args.pass_spp)
            for k in range(passes):
                seed = 1_000_000 * (half + 1) + k
                scene = mitsuba_scene(mi, spec, args.pass_spp, seed)
                total += np.asarray(mi.render(scene, spp=args.pass_spp, seed=seed),
                                    dtype=np.float64)[..., :3]
            halves.append(total / passes)
        elapsed = time.time() - start
        mean = (halves[0] + halves[1]) / 2
        mi.Bitmap(mean.astype(np.float32)).write(os.path.join(HERE, f"{name}.exr"))
        half_error = relmse(halves[0], halves[1])
        with open(os.path.join(HERE, f"{name}.ref.json"), "w") as f:
            json.dump({"scene": name, "spp": 2 * passes * args.pass_spp, "variant": "llvm_ad_rgb",
                       "mitsuba_version": mi.__version__, "time_render_s": elapsed,
                       "relMSE_half0_vs_half1": half_error,
                       # Each half's error is half the halves' difference; the mean's, a quarter.
                       "est_relMSE_ref_vs_truth": half_error / 4,
                       "mean_rgb": mean.reshape(-1, 3).mean(axis=0).tolist()}, f, indent=1)
        print(f"{name}: {elapsed:.0f} s, halves relMSE {half_error:.2e}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
