"""Blender's own panels that SPHRECT also uses: light, material, world, camera, output, shadow terminator."""
import bpy

from ..names import ENGINE_ID

# Panels that make sense for this engine beyond those made for every engine ('BLENDER_RENDER') ...
_EXTRA_PANELS = (
    "DATA_PT_EEVEE_light", "DATA_PT_spot", "DATA_PT_context_light", "EEVEE_MATERIAL_PT_context_material",
    "EEVEE_MATERIAL_PT_surface", "EEVEE_MATERIAL_PT_volume", "EEVEE_WORLD_PT_surface", "EEVEE_WORLD_PT_volume",
    "WORLD_PT_context_world", "DATA_PT_camera_dof", "DATA_PT_camera_dof_aperture",
    # Cycles' Object > Shading > Shadow Terminator (its Geometry Offset is simulated, docs/renderer.md).
    "CYCLES_OBJECT_PT_shading", "CYCLES_OBJECT_PT_shading_shadow_terminator",
)


# ... and those left out: previews need a preview renderer; the light type/shape panels duplicate
# DATA_PT_EEVEE_light, which shows type, colour, power, shape and size together.
_EXCLUDED_PANELS = ("DATA_PT_preview", "MATERIAL_PT_preview", "WORLD_PT_preview", "DATA_PT_light", "DATA_PT_area")


def _compatible_panels():
    panels = []
    for panel in bpy.types.Panel.__subclasses__():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        names = {c.__name__ for c in panel.__mro__}  # node-editor variants subclass the panels they copy
        if engines is None or names & set(_EXCLUDED_PANELS):
            continue
        if "BLENDER_RENDER" in engines or names & set(_EXTRA_PANELS):
            panels.append(panel)
    return panels


def register():
    for panel in _compatible_panels():
        # Subclasses share their base's set object: give each panel its own, so that adding SPHRECT to a
        # node-editor variant does not also switch on an excluded base panel.
        panel.COMPAT_ENGINES = set(panel.COMPAT_ENGINES) | {ENGINE_ID}


def unregister():
    for panel in _compatible_panels():
        panel.COMPAT_ENGINES.discard(ENGINE_ID)
