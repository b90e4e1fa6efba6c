"""The "Tyndall" render engine: renders the evaluated scene of each frame
(F12, or every frame of an animation render) with Tyndall and hands the
image, and optionally Tyndall's AOVs as passes, to Blender."""

import sys
from typing import Dict, List, Tuple

import bpy
import numpy as np

from . import convert

# Tyndall's AOVs as Blender passes: (AOV, pass name, channels, channel ids, kind).
PASSES: Tuple[Tuple[str, str, int, str, str], ...] = (
    ("albedo", "Albedo", 3, "RGB", "COLOR"),
    ("normal", "Normal", 3, "XYZ", "VECTOR"),
    ("depth", "Depth", 1, "Z", "VALUE"),
    ("position", "Position", 3, "XYZ", "VECTOR"),
    ("emission", "Emission", 3, "RGB", "COLOR"),
    ("direct", "Direct", 3, "RGB", "COLOR"),
    ("indirect", "Indirect", 3, "RGB", "COLOR"),
    ("volume", "Volume", 3, "RGB", "COLOR"),
)

# AOVs whose values are directions or points in Tyndall's Y-up frame.
GEOMETRIC = {"normal", "position"}

# Where Cycles' depth pass puts the background.
BACKGROUND_DEPTH = 1e10


def light_groups(view_layer) -> List[str]:
    """The names of a view layer's light groups."""
    return [g.name for g in getattr(view_layer, "lightgroups", ())]


def group_pass(group: str) -> str:
    """The pass of light group `group`, named as Cycles names it."""
    return f"Combined_{group}"


class Cancelled(Exception):
    """The user cancelled the render (Esc)."""


def blender_pixels(image: np.ndarray, channels: int) -> np.ndarray:
    """A Tyndall H×W(×C) array (row 0 at the top) as Blender's pass
    pixels: rows bottom-up, one row of `channels` values per pixel (RGBA
    for the combined pass)."""
    flipped = image[::-1]
    if flipped.ndim == 2:
        flipped = flipped[:, :, None]
    h, w, c = flipped.shape
    if channels == 4 and c == 3:
        flipped = np.concatenate([flipped, np.ones((h, w, 1), dtype=flipped.dtype)], axis=2)
    return np.ascontiguousarray(flipped.reshape(h * w, channels), dtype=np.float32)


def to_blender_frame(v: np.ndarray) -> np.ndarray:
    """Tyndall's Y-up vectors (H×W×3) in Blender's Z-up frame."""
    return np.stack([v[..., 0], -v[..., 2], v[..., 1]], axis=-1)


class TyndallRenderEngine(bpy.types.RenderEngine):
    bl_idname = "TYNDALL"
    bl_label = "Tyndall"
    bl_use_preview = False
    bl_use_postprocess = True
    bl_use_eevee_viewport = True

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        if scene is not None and scene.tyndall.passes:
            for _, name, channels, ids, kind in PASSES:
                self.register_pass(scene, renderlayer, name, channels, ids, kind)
        # A light group's pass, as Cycles names it, whenever the view
        # layer has light groups.
        for group in light_groups(renderlayer):
            self.register_pass(scene, renderlayer, group_pass(group), 3, "RGB", "COLOR")

    def render(self, depsgraph):
        try:
            self.render_frame(depsgraph)
        except Cancelled:
            pass

    def fail(self, message: str) -> None:
        self.report({"ERROR"}, f"Tyndall: {message}")

    def render_frame(self, depsgraph) -> None:
        scene = depsgraph.scene
        options = scene.tyndall
        try:
            import tyndall
        except ImportError:
            self.fail(
                "the tyndall Python package is not installed in Blender's Python: install Tyndall's "
                f"wheel with '{sys.executable} -m pip install tyndall-*.whl' (blender/README.md)"
            )
            return
        settings = convert.Settings(
            integrator=options.integrator, spp=options.samples, max_depth=options.max_depth, seed=options.seed
        )
        try:
            description = convert.describe(depsgraph, settings)
        except convert.ConversionError as e:
            self.fail(str(e))
            return
        for warning in description.warnings:
            self.report({"WARNING"}, f"Tyndall: {warning}")
        try:
            native = tyndall.Scene.from_dict(description.scene)
        except ValueError as e:
            self.fail(str(e))
            return
        aovs = [aov for aov, *_ in PASSES] if options.passes else []
        groups = light_groups(depsgraph.view_layer)
        if groups:
            aovs.append("light_groups")

        def progress(done: int, total: int) -> None:
            self.update_progress(done / max(total, 1))
            self.update_stats("", f"Tyndall: sample {done}/{total}")
            if self.test_break():
                raise Cancelled()

        try:
            rendered = native.render(
                threads=options.threads or None, progress=progress, aovs=aovs or None, denoise=options.denoise
            )
        except (ValueError, OSError) as e:
            self.fail(str(e))
            return
        outputs: Dict[str, np.ndarray] = rendered if isinstance(rendered, dict) else {"beauty": rendered}
        self.write_result(outputs, native.width, native.height, groups)

    def write_result(self, outputs: Dict[str, np.ndarray], width: int, height: int, groups: List[str]) -> None:
        result = self.begin_result(0, 0, width, height)
        layer = result.layers[0]
        layer.passes["Combined"].rect = blender_pixels(outputs["beauty"], 4)
        for aov, name, channels, _, _ in PASSES:
            if aov not in outputs:
                continue
            values = outputs[aov]
            if aov in GEOMETRIC:
                values = to_blender_frame(values)
            if aov == "depth":
                values = np.where(np.isfinite(values), values, BACKGROUND_DEPTH)
            render_pass = layer.passes.find_by_name(name, "")
            if render_pass is not None:
                render_pass.rect = blender_pixels(values, channels)
        for group in groups:
            # A group no converted emitter is in (or one convert warned
            # about) has no image: its pass stays black.
            values = outputs.get(f"light_group.{group}")
            render_pass = layer.passes.find_by_name(group_pass(group), "")
            if values is not None and render_pass is not None:
                render_pass.rect = blender_pixels(values, 3)
        self.end_result(result)


def compatible_panels() -> List[type]:
    """Blender's own panels that apply to this engine too: output,
    dimensions, camera, lights, materials and world (those that list the
    built-in engines), not the other engines' sampling panels."""
    engines = {"BLENDER_RENDER", "BLENDER_EEVEE", "BLENDER_EEVEE_NEXT"}
    panels = []
    for panel in bpy.types.Panel.__subclasses__():
        compat = getattr(panel, "COMPAT_ENGINES", None)
        if not compat or not (compat & engines):
            continue
        if panel.__name__.startswith(("RENDER_PT_eevee", "RENDER_PT_simplify", "VIEWLAYER_PT_eevee")):
            continue
        panels.append(panel)
    return panels


def register_panels() -> None:
    for panel in compatible_panels():
        panel.COMPAT_ENGINES.add("TYNDALL")


def unregister_panels() -> None:
    for panel in compatible_panels():
        panel.COMPAT_ENGINES.discard("TYNDALL")
