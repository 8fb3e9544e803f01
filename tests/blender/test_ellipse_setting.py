"""scene.sphrect.ellipse_technique: the items are the module's ellipse techniques (AREA, SPHERICAL_ELLIPSE),
SPHERICAL_ELLIPSE by default, shown in the Sampling panel, and the setting reaches the renderer (F12 and compare
mode build it from renderer_options)."""
import bpy

import sphrect
from conftest import addon_module, ensure_addon, open_blend


def test_ellipse_technique_items_and_default():
    ensure_addon()
    identifier = addon_module("names").identifier
    prop = bpy.context.scene.sphrect.bl_rna.properties["ellipse_technique"]
    assert [item.identifier for item in prop.enum_items] == [identifier(n) for n in sphrect.ellipse_techniques]
    assert [item.identifier for item in prop.enum_items] == ["AREA", "SPHERICAL_ELLIPSE"]
    assert prop.default == "SPHERICAL_ELLIPSE"
    assert set(addon_module("names").ELLIPSE_TECHNIQUE_LABELS) == set(sphrect.ellipse_techniques)


def test_ellipse_technique_reaches_the_renderer_options():
    ensure_addon()
    s = bpy.context.scene.sphrect
    for value, name in (("AREA", "area"), ("SPHERICAL_ELLIPSE", "spherical_ellipse")):
        s.ellipse_technique = value
        assert s.renderer_options()["ellipse_technique"] == name


def test_ellipse_technique_changes_a_disk_render():
    """F12 on a disk-lit scene renders differently with each setting (the same seed and camera samples)."""
    scene = open_blend("11_paper_disk", 32, 24)
    s = scene.sphrect
    s.technique, s.samples, s.passes = "RECTANGLE", 4, 1
    engine = addon_module("engine.render_engine")
    images = {}
    for value in ("AREA", "SPHERICAL_ELLIPSE"):
        s.ellipse_technique = value
        bpy.ops.render.render(write_still=False)
        assert engine.last_render["errors"] == []
        images[value] = engine.last_render["images"]["rectangle"]
        assert engine.last_render["stats"]["rectangle"]["ellipse_technique"] == value.lower()
    assert (images["AREA"] != images["SPHERICAL_ELLIPSE"]).any()
