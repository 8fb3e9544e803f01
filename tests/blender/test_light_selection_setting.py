"""scene.sphrect.light_selection: the items are the module's light selections (POWER, TREE, RIS), TREE by default,
and the setting reaches the renderer (F12 and compare mode build it from renderer_options); so does RIS Candidates."""
import bpy
import numpy as np

import sphrect
from conftest import addon_module, ensure_addon, lit_test_scene, render


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


def test_ris_candidates_setting_range_and_options():
    ensure_addon()
    s = bpy.context.scene.sphrect
    prop = s.bl_rna.properties["ris_candidates"]
    assert prop.default == sphrect.RENDER_DEFAULTS["ris_candidates"]
    assert (prop.hard_min, prop.hard_max) == (1, sphrect.MAX_RIS_CANDIDATES)
    s.ris_candidates = 7
    assert s.renderer_options()["ris_candidates"] == 7
    s.ris_candidates = sphrect.MAX_RIS_CANDIDATES + 5  # Blender clamps to the module's limit
    assert s.ris_candidates == sphrect.MAX_RIS_CANDIDATES


def test_ris_candidates_reach_the_render(empty_scene):
    """F12 under Light Tree + RIS with one candidate is the light tree's image (each light sample is its one
    candidate), with four it is another estimate: the setting reaches the renderer."""
    scene = lit_test_scene(empty_scene)
    s = scene.sphrect
    s.samples, s.passes, s.mis = 4, 1, "POWER"
    images = {}
    for selection, candidates in (("TREE", 1), ("RIS", 1), ("RIS", 4)):
        s.light_selection, s.ris_candidates = selection, candidates
        images[selection, candidates] = render()["images"]["rectangle"]
    assert np.allclose(images["RIS", 1], images["TREE", 1], rtol=1e-4, atol=1e-6)
    assert not np.allclose(images["RIS", 4], images["TREE", 1], rtol=1e-3, atol=1e-4)
    lit = images["TREE", 1][..., :3].mean()
    assert abs(images["RIS", 4][..., :3].mean() / lit - 1) < 0.1  # the same scene, four times the candidates
