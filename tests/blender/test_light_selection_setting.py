"""scene.sphrect.light_selection: the items are the module's light selections (POWER, TREE, RIS), TREE by default,
and the setting reaches the renderer (F12 and compare mode build it from renderer_options)."""
import bpy

import sphrect
from conftest import addon_module, ensure_addon


def test_light_selection_items_and_default():
    ensure_addon()
    identifier = addon_module("names").identifier
    scene = bpy.context.scene
    prop = scene.sphrect.bl_rna.properties["light_selection"]
    assert [item.identifier for item in prop.enum_items] == [identifier(n) for n in sphrect.light_selections]
    assert [item.identifier for item in prop.enum_items] == ["POWER", "TREE", "RIS"]
    assert prop.default == "TREE"


def test_light_selection_reaches_the_renderer_options():
    ensure_addon()
    s = bpy.context.scene.sphrect
    for value, name in (("POWER", "power"), ("TREE", "tree"), ("RIS", "ris")):
        s.light_selection = value
        assert s.renderer_options()["light_selection"] == name
