"""Tyndall as a Blender render engine: F12 and animation renders of the
current scene with Tyndall (light in participating media), converted
through Tyndall's Python API (`tyndall.Scene.from_dict`), no files in
between. See blender/README.md."""

bl_info = {
    "name": "Tyndall",
    "author": "The Tyndall developers",
    "version": (0, 1, 0),
    "blender": (4, 2, 0),
    "location": "Render Properties > Render Engine > Tyndall",
    "description": "Render with Tyndall: beams, volumetric shadows and multiple scattering in fog and smoke",
    "category": "Render",
}

if "bpy" in locals():
    import importlib

    importlib.reload(convert)  # noqa: F821
    importlib.reload(engine)  # noqa: F821
    importlib.reload(properties)  # noqa: F821
else:
    from . import convert, engine, properties  # noqa: F401

import bpy  # noqa: E402


def register():
    properties.register()
    bpy.utils.register_class(engine.TyndallRenderEngine)
    engine.register_panels()


def unregister():
    engine.unregister_panels()
    bpy.utils.unregister_class(engine.TyndallRenderEngine)
    properties.unregister()
