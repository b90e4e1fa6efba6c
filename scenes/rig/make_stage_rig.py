#!/usr/bin/env python3
"""Writes a stage lighting rig: N gobo spots on a truss over a stage in
haze (issue 23), and the two gobo images it uses.

    python3 scenes/rig/make_stage_rig.py            # scenes/stage-rig.toml (64 spots) and the gobos
    python3 scenes/rig/make_stage_rig.py 1024 OUT   # the 1024-spot version, to OUT
    python3 scenes/rig/make_stage_rig.py --neutral 64 OUT.json
        # the same heads in shared/peers' renderer-neutral format, for Mitsuba and Cycles

The rig is an n × n grid of moving heads 8 m above a 20 m × 12 m stage,
each aimed at its own point of the floor in a fan, alternating 3200 K
tungsten and 5600 K daylight lamps, two gobos (a break-up of holes and a
star) turned per head; the haze is a fog box over the stage. The 1024-spot
rig has the same total power split over 16× the heads, so its image is
of the same brightness. Pure Python (zlib for the PNGs), so CI needs
nothing else.

The neutral scene (`volbench-scene/1`, ../shared/peers/FORMAT.md) is what
other renderers can read of the rig: the same heads, cones and total
power, but white (no colour temperature), without gobos, and with the
haze filling all space (the format's one global medium) instead of a box;
shared/peers' `to_tyndall.py` translates it back for Tyndall, so all three
render the same scene.
"""

import json
import math
import os
import struct
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.dirname(HERE)


def write_png(path, size, shade):
    """An 8-bit grey PNG of size × size texels, texel (x, y) = shade(u, v)."""
    rows = b"".join(
        b"\x00" + bytes(shade((x + 0.5) / size, (y + 0.5) / size) for x in range(size))
        for y in range(size)
    )

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", size, size, 8, 0, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


def breakup(u, v):
    """Seven round holes in a metal disc: a classic break-up gobo."""
    holes = [(0.5, 0.5, 0.14)] + [
        (0.5 + 0.3 * math.cos(k * math.pi / 3), 0.5 + 0.3 * math.sin(k * math.pi / 3), 0.09) for k in range(6)
    ]
    return 255 if any((u - x) ** 2 + (v - y) ** 2 < r * r for x, y, r in holes) else 0


def star(u, v):
    """A five-pointed star."""
    x, y = u - 0.5, 0.5 - v
    r, a = math.hypot(x, y), math.atan2(y, x)
    edge = 0.2 + 0.25 * abs(math.cos(2.5 * (a - math.pi / 2))) ** 3
    return 255 if r < edge else 0


def rig(n):
    lines = [
        f"# A stage lighting rig (issue 23): {n * n} gobo spots in haze over a stage.",
        "# Written by scenes/rig/make_stage_rig.py; the demo stays scenes/demo.",
        "",
        "[camera]",
        "position = [0.0, 3.5, 17.0]",
        "look_at = [0.0, 3.0, 0.0]",
        "fov_y_deg = 50.0",
        "",
        "[render]",
        "width = 640",
        "height = 360",
        "spp = 16",
        'integrator = "single"',
        "",
        "[fog]",
        "sigma_t = 0.04",
        "albedo = 0.9",
        "g = 0.3",
        "box = { min = [-11.0, 0.0, -7.0], max = [11.0, 9.0, 7.0] }",
        "",
        "[materials.stage]",
        'type = "diffuse"',
        "reflectance = 0.35",
        "",
        "[materials.backdrop]",
        'type = "diffuse"',
        "reflectance = 0.2",
        "",
        "[[shapes]]",
        'type = "quad"',
        "corners = [[-10, 0, -6], [-10, 0, 6], [10, 0, 6], [10, 0, -6]]",
        'material = "stage"',
        "",
        "[[shapes]]",
        'type = "quad"',
        "corners = [[-10, 0, -6], [10, 0, -6], [10, 9, -6], [-10, 9, -6]]",
        'material = "backdrop"',
        "",
    ]
    for k, position, target, cutoff, intensity in heads(n):
        lines += [
            "[[lights]]",
            'type = "spot"',
            f"position = [{position[0]:.3f}, {position[1]:.1f}, {position[2]:.3f}]",
            f"look_at = [{target[0]:.3f}, {target[1]:.1f}, {target[2]:.3f}]",
            f"cutoff_deg = {cutoff:.2f}",
            'profile = "hard"',
            f"intensity = {intensity:.4f}",
            f"temperature_k = {3200 if k % 2 == 0 else 5600}",
            f'gobo = "rig/{"breakup" if (k // 2) % 2 == 0 else "star"}.png"',
            f"gobo_rotate_deg = {(37 * k) % 360}",
            "",
        ]
    return "\n".join(lines)


def heads(n):
    """The n × n heads: (index, position, aim point, cone half-angle in
    degrees, intensity in W/sr), the rig's total intensity the same for
    every n."""
    intensity = 40.0 * 64 / (n * n)
    for i in range(n):
        for j in range(n):
            x = -8.0 + 16.0 * (i + 0.5) / n
            z = -5.0 + 10.0 * (j + 0.5) / n
            k = i * n + j
            # Each head aimed in a fan across the floor.
            tx = 0.6 * x + 2.5 * math.sin(1.7 * k)
            tz = 0.5 * z + 2.0 * math.cos(1.3 * k)
            cutoff = 10.0 + 4.0 * ((k * 7) % 5) / 4
            yield k, (x, 8.0, z), (tx, 0.0, tz), cutoff, intensity


def neutral_rig(n, width=320, height=180):
    """The rig as a `volbench-scene/1` scene (module doc: what differs)."""
    diffuse = lambda r: {"type": "diffuse", "reflectance": [r, r, r]}
    lights = []
    for k, position, target, cutoff, intensity in heads(n):
        # Rounded as the TOML rounds them, so both scenes hold the same heads.
        p = [round(c, 3) for c in position]
        direction = [round(t, 3) - q for t, q in zip(target, p)]
        lights.append({"name": f"head{k}", "type": "spot", "position": p, "direction": direction,
                       "cutoff_deg": round(cutoff, 2), "intensity": [round(intensity, 4)] * 3})
    return {
        "format": "volbench-scene/1",
        "name": f"stage-rig-{n * n}",
        "description": f"The stage rig of issue 23 ({n * n} hard spots in haze over a stage, "
        "scenes/rig/make_stage_rig.py) as other renderers read it: white, no gobos, the haze everywhere. "
        "Single scattering (max_depth 2).",
        "camera": {"position": [0.0, 3.5, 17.0], "look_at": [0.0, 3.0, 0.0], "up": [0, 1, 0],
                   "fov_y_deg": 50.0, "width": width, "height": height},
        "medium": {"sigma_t": 0.04, "albedo": [0.9, 0.9, 0.9], "g": 0.3},
        "shapes": [
            {"name": "stage", "type": "quad",
             "corners": [[-10, 0, -6], [-10, 0, 6], [10, 0, 6], [10, 0, -6]], "material": diffuse(0.35)},
            {"name": "backdrop", "type": "quad",
             "corners": [[-10, 0, -6], [10, 0, -6], [10, 9, -6], [-10, 9, -6]], "material": diffuse(0.2)},
        ],
        "lights": lights,
        "render": {"max_depth": 2},
    }


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "--neutral":
        spots = int(sys.argv[2])
        n = math.isqrt(spots)
        if n * n != spots:
            sys.exit(f"the rig is a square grid: {spots} is not a square")
        with open(sys.argv[3], "w") as f:
            json.dump(neutral_rig(n), f, indent=1)
        print(f"wrote {sys.argv[3]} ({spots} spots, neutral)")
        return
    spots = int(sys.argv[1]) if len(sys.argv) > 1 else 64
    n = math.isqrt(spots)
    if n * n != spots:
        sys.exit(f"the rig is a square grid: {spots} is not a square")
    write_png(os.path.join(HERE, "breakup.png"), 64, breakup)
    write_png(os.path.join(HERE, "star.png"), 64, star)
    out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(SCENES, "stage-rig.toml")
    text = rig(n)
    if len(sys.argv) > 2:
        # Elsewhere than scenes/: name the gobos absolutely.
        text = text.replace('gobo = "rig/', f'gobo = "{HERE}/')
    with open(out, "w") as f:
        f.write(text)
    print(f"wrote {out} ({spots} spots)")


if __name__ == "__main__":
    main()
