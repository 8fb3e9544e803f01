"""SPHRECT: a Blender render engine that samples rectangular area lights by solid angle
(Urena, Fajardo & King, EGSR 2013) and shows the light-sampling techniques side by side.

Python use (inside Blender):
    import sphrect_blender
    sphrect_blender.export_scene(bpy.context.evaluated_depsgraph_get(), "/tmp/scene.sphrect.npz")
From outside Blender (export, Cycles render by command name): headless.py.

Modules: native (finding the `sphrect` package), names (the module's name lists as enum items), images
(image files and the reference cache), properties (settings), ui (panels), material_notes (what the material
panel lists), operators (File > Export),
io/exporter (depsgraph -> sphrect.Scene), engine/ (the render engine), headless and cycles_peer (commands
for programs outside Blender). The add-on depends on the `sphrect` package, never the other way round.
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
