"""SPHRECT: a Blender render engine that samples rectangular area lights by solid angle
(Urena, Fajardo & King, EGSR 2013) and shows the light-sampling techniques side by side.

Python use (inside Blender):
    import sphrect_blender
    sphrect_blender.export_scene(bpy.context.evaluated_depsgraph_get(), "/tmp/scene.sphrect.npz")
"""

bl_info = {
    "name": "SPHRECT",
    "author": "sphrect project",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Render Properties > Render Engine > SPHRECT",
    "description": "Direct-lighting renderer comparing area-light sampling techniques "
                   "(solid-angle sampling of spherical rectangles)",
    "category": "Render",
}

from .native import load_sphrect  # noqa: E402  (no bpy registration inside)
from .io.exporter import export_scene, scene_from_depsgraph  # noqa: E402

__all__ = ["export_scene", "scene_from_depsgraph", "load_sphrect", "register", "unregister"]


def register():
    from . import properties, engine, ui, operators
    properties.register()
    engine.register()
    operators.register()
    ui.register()


def unregister():
    from . import properties, engine, ui, operators
    ui.unregister()
    operators.unregister()
    engine.unregister()
    properties.unregister()
