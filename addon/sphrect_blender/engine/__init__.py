"""The SPHRECT render engine's registration. A module per concern:

    render_engine   the RenderEngine: export, progressive render, passes, the comparison (last_render)
    schedule        renderer calls: the sample split and cancelling (request_cancel)
    compare         the comparison image (pure numpy)
    display         where the comparison image goes and showing it in an Image Editor
    blender_panels  Blender's own panels that SPHRECT also uses
    viewport        Rendered shading in the 3D view (viewport_worker: its render thread, viewport_camera:
                    the view as a camera, viewport_updates: what an edit re-exports)
"""
import bpy

from . import blender_panels, display, viewport
from .render_engine import SphrectRenderEngine, last_render, technique_pass_name  # noqa: F401  (for scripts)
from .schedule import request_cancel  # noqa: F401  (for scripts)


def register():
    bpy.utils.register_class(SphrectRenderEngine)
    blender_panels.register()
    display.register()


def unregister():
    viewport.unregister()  # stops the viewport threads
    display.unregister()
    blender_panels.unregister()
    bpy.utils.unregister_class(SphrectRenderEngine)
