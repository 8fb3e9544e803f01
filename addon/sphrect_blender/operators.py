"""File > Export > SPHRECT Scene: the standalone scene file that `sphrect.load_scene` reads without Blender."""
import bpy
from bpy_extras.io_utils import ExportHelper

from .io.exporter import export_scene


class EXPORT_SCENE_OT_sphrect(bpy.types.Operator, ExportHelper):
    """Export the evaluated scene as a sphrect scene file (.sphrect.npz)"""
    bl_idname = "export_scene.sphrect"
    bl_label = "Export SPHRECT Scene"
    filename_ext = ".npz"
    filter_glob: bpy.props.StringProperty(default="*.npz", options={"HIDDEN"})

    def invoke(self, context, event):
        if not self.filepath:
            self.filepath = bpy.path.ensure_ext(bpy.path.display_name_sanitized(
                bpy.path.basename(bpy.data.filepath) or "untitled").rsplit(".", 1)[0] + ".sphrect", ".npz")
        return super().invoke(context, event)

    def execute(self, context):
        try:
            log = export_scene(context.evaluated_depsgraph_get(), self.filepath)
        except (ImportError, ValueError, OSError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        warning = log.warning_text()
        if warning:
            self.report({"WARNING"}, warning)
        self.report({"INFO"}, f"Exported {self.filepath}")
        return {"FINISHED"}


def _menu(self, context):
    self.layout.operator(EXPORT_SCENE_OT_sphrect.bl_idname, text="SPHRECT Scene (.sphrect.npz)")


def register():
    bpy.utils.register_class(EXPORT_SCENE_OT_sphrect)
    bpy.types.TOPBAR_MT_file_export.append(_menu)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(_menu)
    bpy.utils.unregister_class(EXPORT_SCENE_OT_sphrect)
