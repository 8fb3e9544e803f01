"""The add-on registers its engine, settings, panels and operator under the fixed names."""
import bpy

import sphrect
from conftest import addon_module, engine_module


def _engines():
    return {c.bl_idname for c in bpy.types.RenderEngine.__subclasses__() if c.is_registered}


def test_engine_and_settings_registered(empty_scene):
    assert "SPHRECT" in _engines()
    s = empty_scene.sphrect
    for name in ("technique", "samples", "light_samples", "pattern", "mis", "seed", "compare"):
        assert hasattr(s, name), name
    items = lambda prop: {i.identifier for i in s.bl_rna.properties[prop].enum_items}
    assert items("technique") == {"AREA", "TRIANGLES", "RECTANGLE", "RECTANGLE_COSINE", "RECTANGLE_PROJECTED",
                                  "RECTANGLE_LTC"}
    assert items("mis") == {"NONE", "BALANCE", "POWER"}
    assert items("pattern") == {"INDEPENDENT", "STRATIFIED", "LATIN", "HAMMERSLEY", "SOBOL"}
    assert hasattr(bpy.types.Light, "sphrect")
    assert hasattr(bpy.ops.export_scene, "sphrect")


def test_enum_items_follow_the_module_lists(empty_scene):
    """The enums list the module's names in its order (a .blend stores an item's number); the add-on's UI
    text covers exactly those names, so the add-on registers the same items without the module."""
    names = addon_module("names")
    s = empty_scene.sphrect
    for prop, module_names, labels in (("technique", sphrect.techniques, names.TECHNIQUE_LABELS),
                                       ("pattern", sphrect.patterns, names.PATTERN_LABELS),
                                       ("mis", sphrect.mis_modes, names.MIS_LABELS)):
        items = s.bl_rna.properties[prop].enum_items
        assert [(i.identifier, i.value) for i in items] == [(n.upper(), k) for k, n in enumerate(module_names)]
        assert tuple(labels) == tuple(module_names), prop
    assert all(hasattr(s, "compare_" + t) for t in sphrect.techniques)
    assert s.compare_techniques() == list(sphrect.techniques)


def test_blender_light_and_material_panels_shown_for_sphrect(empty_scene):
    for panel in ("DATA_PT_EEVEE_light", "DATA_PT_spot", "EEVEE_MATERIAL_PT_surface", "EEVEE_WORLD_PT_surface",
                  "EEVEE_WORLD_PT_volume", "DATA_PT_lens", "DATA_PT_camera_dof", "RENDER_PT_format",
                  "RENDER_PT_color_management"):
        cls = getattr(bpy.types, panel)
        assert "SPHRECT" in cls.COMPAT_ENGINES, panel
    for panel in ("DATA_PT_light", "DATA_PT_area", "DATA_PT_preview"):  # duplicates of DATA_PT_EEVEE_light
        assert "SPHRECT" not in getattr(bpy.types, panel).COMPAT_ENGINES, panel
    for panel in ("RENDER_PT_sphrect_sampling", "RENDER_PT_sphrect_compare", "DATA_PT_sphrect_light"):
        assert hasattr(bpy.types, panel), panel


def test_compare_mode_declares_a_pass_per_technique(empty_scene):
    s = empty_scene.sphrect
    s.compare = True
    s.compare_area = False
    s.reference = "NONE"
    empty_scene.use_nodes = True  # the Render Layers node lists the passes the engine declares
    layer_node = empty_scene.node_tree.nodes["Render Layers"]
    outputs = {o.name for o in layer_node.outputs if o.enabled}
    expected = {engine_module().technique_pass_name(t) for t in ("triangles", "rectangle", "rectangle_cosine",
                                                                 "rectangle_projected")}
    assert expected <= outputs, outputs
    assert engine_module().technique_pass_name("area") not in outputs


def test_disable_and_enable_again():
    import addon_utils
    addon_utils.disable("sphrect_blender", handle_error=None)
    try:
        assert "SPHRECT" not in _engines()
        assert "SPHRECT" not in bpy.types.DATA_PT_EEVEE_light.COMPAT_ENGINES
        assert not hasattr(bpy.types.Scene, "sphrect")
    finally:
        addon_utils.enable("sphrect_blender", default_set=True, handle_error=None)
    assert "SPHRECT" in bpy.types.DATA_PT_EEVEE_light.COMPAT_ENGINES


def test_settings_default_to_the_renderers_defaults(empty_scene):
    # A new scene's settings are sphrect.RENDER_DEFAULTS (render/options.h), not a copy of their own.
    s, d = empty_scene.sphrect, sphrect.RENDER_DEFAULTS
    assert s.technique == d["techniques"][0].upper()
    for name in ("pattern", "mis", "light_selection", "ellipse_technique"):
        assert getattr(s, name) == d[name].upper(), name
    for name in ("light_samples", "seed", "threads", "analytic_light_coverage", "bsdf_samples_on_diffuse"):
        assert getattr(s, name) == d[name], name
