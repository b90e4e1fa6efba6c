"""The engine's settings (Render Properties → Tyndall) and their panel."""

import bpy


class TyndallSettings(bpy.types.PropertyGroup):
    """Per-scene settings of the Tyndall engine (`scene.tyndall`)."""

    integrator: bpy.props.EnumProperty(
        name="Integrator",
        items=[
            ("volpath", "Path tracing", "Volumetric path tracing: multiple scattering in fog and between surfaces"),
            ("single", "Single scattering", "Direct light and single scattering in fog, mirrors and glossy followed"),
            ("march", "Ray march", "The paper's ray march (fixed step)"),
        ],
        default="volpath",
    )
    samples: bpy.props.IntProperty(name="Samples", description="Samples per pixel", default=64, min=1, max=1 << 20)
    max_depth: bpy.props.IntProperty(
        name="Max Depth",
        description="Most scattering events per path (path tracing); 0 is unlimited (Russian roulette ends paths)",
        default=0,
        min=0,
        max=1 << 16,
    )
    seed: bpy.props.IntProperty(name="Seed", description="Seed of the sample sequences", default=0, min=0)
    denoise: bpy.props.BoolProperty(
        name="Denoise",
        description="Denoise with Intel Open Image Denoise (guided by albedo and normal); needs pip install pyoidn",
        default=True,
    )
    threads: bpy.props.IntProperty(name="Threads", description="Render threads; 0 uses every core", default=0, min=0)
    passes: bpy.props.BoolProperty(
        name="AOV Passes",
        description="Also write albedo, normal, depth and the radiance's components as render passes",
        default=False,
    )


class TYNDALL_PT_render(bpy.types.Panel):
    bl_label = "Tyndall"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {"TYNDALL"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        settings = context.scene.tyndall
        for name in ("integrator", "samples", "max_depth", "seed", "denoise", "threads", "passes"):
            layout.prop(settings, name)


CLASSES = (TyndallSettings, TYNDALL_PT_render)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.tyndall = bpy.props.PointerProperty(type=TyndallSettings)


def unregister():
    del bpy.types.Scene.tyndall
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
