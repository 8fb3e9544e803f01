"""Render Properties panels for scene.sphrect, the light panel (two-sided switch, Cast Shadow, Multiple Importance,
settings ignored), the object's Ray Visibility and the material panel (what SPHRECT ignores or approximates in the
active material)."""
import textwrap

import bpy

from . import material_notes
from .io.exporter.geometry import MESH_LIKE
from .io.exporter.lights import ignored_light_settings
from .io.exporter.visibility import PANEL_LIGHT_RAY_KINDS, PANEL_RAY_KINDS
from .light_notes import light_shape_notes
from .names import ELLIPSE_TECHNIQUES, ENGINE_ID, LIGHT_SELECTIONS, TECHNIQUES
from .properties import compare_ellipse_technique_switch, compare_light_selection_switch, compare_switch


class SphrectPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    COMPAT_ENGINES = {ENGINE_ID}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def settings_layout(self, context):
        """(scene.sphrect, the panel's layout with labels split from the properties, as Blender's render panels)."""
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        return context.scene.sphrect, layout


def draw_light_shapes_note(layout, scene, settings):
    """Under the Technique: the scene's lights it does not sample, and what samples them."""
    notes = light_shape_notes(scene, settings)
    if notes:
        box = layout.box().column(align=True)
        for i, note in enumerate(notes):
            box.label(text=note, icon="INFO" if i == 0 else "BLANK1")


class RENDER_PT_sphrect_sampling(SphrectPanel, bpy.types.Panel):
    bl_label = "Sampling"
    bl_context = "render"

    def draw(self, context):
        s, layout = self.settings_layout(context)
        col = layout.column()
        col.prop(s, "technique")
        draw_light_shapes_note(col, context.scene, s)
        col.prop(s, "samples")
        col.prop(s, "time_limit")
        col.prop(s, "light_samples")
        col.prop(s, "pattern")
        col.prop(s, "mis")
        sub = col.column()
        sub.active = s.mis != "NONE"
        sub.prop(s, "bsdf_samples_on_diffuse")
        col.prop(s, "light_selection")
        sub = col.column()
        sub.active = s.light_selection == "RIS" or getattr(s, "compare_light_selection_ris", False)
        sub.prop(s, "ris_candidates")
        col.prop(s, "ellipse_technique")
        col.prop(s, "analytic_light_coverage")
        col.prop(s, "seed")
        col.separator()
        col.prop(s, "passes")
        col.prop(s, "threads")


class RENDER_PT_sphrect_film(SphrectPanel, bpy.types.Panel):
    """Blender's Film > Transparent and Cycles' Pixel Filter, which SPHRECT renders as Cycles does."""
    bl_label = "Film"
    bl_context = "render"

    def draw(self, context):
        s, layout = self.settings_layout(context)
        col = layout.column()
        col.prop(context.scene.render, "film_transparent", text="Transparent")
        col.prop(s, "pixel_filter")
        sub = col.column()
        sub.active = s.pixel_filter != "BOX"  # Cycles renders every box 1 pixel wide
        sub.prop(s, "filter_width")


class RENDER_PT_sphrect_viewport(SphrectPanel, bpy.types.Panel):
    """The 3D view's Rendered shading (the Technique and the light settings are the Sampling panel's)."""
    bl_label = "Viewport"
    bl_context = "render"
    bl_parent_id = "RENDER_PT_sphrect_sampling"

    def draw(self, context):
        s, layout = self.settings_layout(context)
        col = layout.column()
        col.prop(s, "viewport_samples", text="Samples")
        col.prop(context.scene.render, "preview_pixel_size", text="Pixel Size")
        col.prop(s, "viewport_compare", text="Compare")
        sub = col.column()
        sub.active = s.viewport_compare
        sub.prop(s, "viewport_compare_technique")


class RENDER_PT_sphrect_compare(SphrectPanel, bpy.types.Panel):
    bl_label = "Compare Techniques"
    bl_context = "render"

    def draw_header(self, context):
        self.layout.prop(context.scene.sphrect, "compare", text="")

    def draw(self, context):
        s, layout = self.settings_layout(context)
        layout.active = s.compare
        col = layout.column(heading="Techniques", align=True)
        for name in TECHNIQUES:
            col.prop(s, compare_switch(name))
        col = layout.column(heading="Light Selections", align=True)  # none ticked: the Sampling panel's
        for name in LIGHT_SELECTIONS:
            col.prop(s, compare_light_selection_switch(name))
        col = layout.column(heading="Disk Lights", align=True)  # none ticked: the Sampling panel's
        for name in ELLIPSE_TECHNIQUES:
            col.prop(s, compare_ellipse_technique_switch(name))
        col = layout.column()
        col.prop(s, "equal_time")
        sub = col.column()
        sub.active = s.equal_time
        sub.prop(s, "time_budget")
        col.prop(s, "reference")
        if s.reference == "RENDER":
            col.prop(s, "reference_samples")
        elif s.reference == "FILE":
            col.prop(s, "reference_path")


class DATA_PT_sphrect_light(SphrectPanel, bpy.types.Panel):
    """SPHRECT's own light settings (area lights), and the settings of Blender's light panels it ignores."""
    bl_label = "SPHRECT"
    bl_context = "data"

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES and context.light is not None

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        light = context.light
        if light.type == "AREA":
            layout.prop(light.sphrect, "two_sided")
            layout.prop(light, "spread")  # Cycles' (its own panel is not shown for SPHRECT)
            layout.prop(context.object, "visible_camera", text="Visible to Camera")
        if hasattr(light, "cycles"):  # Cycles' own settings (its Light panel is not shown for SPHRECT)
            layout.prop(light.cycles, "cast_shadow")
            layout.prop(light.cycles, "use_multiple_importance_sampling", text="Multiple Importance")
        ignored = ignored_light_settings(light)
        if ignored:
            col = layout.column(align=True)
            col.label(text="Ignored by SPHRECT:")
            for label, _, differs in ignored:
                row = col.row()
                row.alert = differs  # set away from what SPHRECT assumes: the render differs from Cycles'
                row.label(text=label, icon="ERROR" if differs else "DOT")


class OBJECT_PT_sphrect_ray_visibility(SphrectPanel, bpy.types.Panel):
    """Object > Visibility > Ray Visibility, as Cycles shows it (its panel is Cycles' own): SPHRECT honours it."""
    bl_label = "Ray Visibility"
    bl_context = "object"
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context):
        obj = context.object
        return context.engine in cls.COMPAT_ENGINES and obj is not None and obj.type in MESH_LIKE | {"LIGHT"}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        obj = context.object
        col = layout.column()
        for kind in PANEL_RAY_KINDS if obj.type != "LIGHT" else PANEL_LIGHT_RAY_KINDS:
            col.prop(obj, f"visible_{kind}", text=kind.replace("_", " ").title())


class MATERIAL_PT_sphrect_material(SphrectPanel, bpy.types.Panel):
    """What SPHRECT ignores or approximates in the active material: the export's own warnings for it."""
    bl_label = "SPHRECT"
    bl_context = "material"

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES and context.material is not None

    def draw(self, context):
        notes = material_notes.material_notes(context.material)
        col = self.layout.column(align=True)
        if not notes:
            col.label(text="Nothing ignored by SPHRECT", icon="CHECKMARK")
            return
        # Labels do not wrap: break the lines to the panel's width (about 7 pixels a character).
        scale = context.preferences.system.ui_scale or 1.0  # 0 without a window
        columns = max(16, int(context.region.width / (7 * scale)) - 6)
        for line in textwrap.wrap("Ignored or approximated by SPHRECT:", columns + 2):
            col.label(text=line)
        for note in notes:
            for i, line in enumerate(textwrap.wrap(note, columns)):
                col.label(text=line, icon="DOT" if i == 0 else "BLANK1")


classes = (RENDER_PT_sphrect_sampling, RENDER_PT_sphrect_film, RENDER_PT_sphrect_viewport, RENDER_PT_sphrect_compare,
           DATA_PT_sphrect_light, OBJECT_PT_sphrect_ray_visibility, MATERIAL_PT_sphrect_material)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    material_notes.register()


def unregister():
    material_notes.unregister()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
