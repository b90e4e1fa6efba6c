"""Cycles 4.5 with its own Open Image Denoise, for the side-by-side of
docs/benchmarks.md ("Denoising and AOVs").

Runs the peer script ``cycles_render.py`` (../shared/peers/, which renders
without denoising) with Cycles' denoiser switched on the way a Blender user
switches it on for a final render: OpenImageDenoise, albedo and normal
guides, accurate prefilter. Cycles denoises inside its render call, so the
script's ``time_render_s`` includes the denoising.

    TYNDALL_PEERS=/path/to/peers .venv-bpy/bin/python cycles_denoised.py \\
        ../shared/reference/fog-room-multi.json --spp 16 --seed 7 --out out/c16

Every argument is ``cycles_render.py``'s.
"""

import importlib.util
import os
import sys

peers = os.environ.get("TYNDALL_PEERS")
if not peers:
    raise SystemExit("set TYNDALL_PEERS to the folder holding cycles_render.py (a copy of ../shared/peers)")
spec = importlib.util.spec_from_file_location("cycles_render", os.path.join(peers, "cycles_render.py"))
cycles_render = importlib.util.module_from_spec(spec)
spec.loader.exec_module(cycles_render)
build_scene = cycles_render.build_scene


def build_denoised_scene(*args, **kwargs):
    """The peer script's scene, then Cycles' denoiser on."""
    result = build_scene(*args, **kwargs)
    import bpy

    sc = bpy.context.scene
    cy = sc.cycles
    cy.use_denoising = True
    cy.denoiser = "OPENIMAGEDENOISE"
    cy.denoising_input_passes = "RGB_ALBEDO_NORMAL"
    cy.denoising_prefilter = "ACCURATE"
    sc.view_layers[0].cycles.use_denoising = True
    return result


cycles_render.build_scene = build_denoised_scene
cycles_render.main(sys.argv[1:])
