"""The Sampling panel's time limit and its note on the lights the Technique does not sample."""
import bpy
import numpy as np

from conftest import addon_module, ensure_addon, open_blend


def test_time_limit_keeps_the_samples_done():
    """A render of a million samples per pixel stops at its 0.2 s limit, completes the samples it rendered (not a
    cancellation) and says so; no limit (the default) renders them all."""
    ensure_addon()
    assert bpy.context.scene.sphrect.bl_rna.properties["time_limit"].default == 0
    scene = open_blend("01_paper", 16, 12)
    s = scene.sphrect
    s.technique, s.passes, s.samples, s.time_limit = "RECTANGLE", 1, 1_000_000, 0.2
    engine = addon_module("engine.render_engine")
    bpy.ops.render.render(write_still=False)
    rec = engine.last_render
    assert rec["errors"] == [] and not rec["cancelled"] and rec["time_limited"]
    assert 0 < rec["stats"]["rectangle"]["samples"] < 1_000_000
    assert "(time limit)" in rec["stats_line"]
    image = np.asarray(rec["images"]["rectangle"])
    assert np.isfinite(image).all() and image[..., :3].max() > 0
    s.samples, s.time_limit = 4, 0.0
    bpy.ops.render.render(write_still=False)
    assert not engine.last_render["time_limited"] and engine.last_render["stats"]["rectangle"]["samples"] == 4


def test_light_notes_name_what_the_technique_does_not_sample():
    notes = addon_module("light_notes")
    scene = open_blend("01_paper")
    assert notes.light_shape_notes(scene, scene.sphrect) == []  # one rectangle light: nothing to say
    scene = open_blend("06_mixed_lights")
    rectangles, disks, delta = notes.count_lights(scene)
    assert rectangles >= 1 and disks >= 1 and delta >= 3
    text = notes.light_shape_notes(scene, scene.sphrect)
    assert any("disk/ellipse" in t and "Solid angle (spherical ellipse)" in t for t in text), text
    assert any(f"{delta} point/spot/sun lights" in t for t in text), text
    scene.sphrect.ellipse_technique = "AREA"
    assert any("Area (uniform)" in t for t in notes.light_shape_notes(scene, scene.sphrect))
    for obj in [o for o in scene.objects if o.type == "LIGHT" and o.data.type == "AREA"
                and o.data.shape in notes.RECTANGLE_SHAPES]:
        bpy.data.objects.remove(obj)
    assert notes.light_shape_notes(scene, scene.sphrect)[0].startswith("No rectangle lights")


def test_light_panel_lists_the_settings_sphrect_ignores():
    """The light panel's list and the exporter's warnings come from one table: every light type has its list;
    a setting away from what SPHRECT assumes is flagged, and only then warned about at export."""
    ensure_addon()
    lights = addon_module("io.exporter.lights")
    for kind in ("POINT", "SPOT", "SUN", "AREA"):
        light = bpy.data.lights.new(f"probe {kind}", kind)
        ignored = lights.ignored_light_settings(light)
        assert "Specular factor" in [label for label, _, _ in ignored]
        # A new light has SPHRECT's assumptions (a point or spot light's radius and a sun's angle are simulated).
        flagged = [label for label, _, differs in ignored if differs]
        assert flagged == [], (kind, ignored)
        bpy.data.lights.remove(light)
    sun = bpy.data.lights.new("probe sun", "SUN")
    sun.angle, sun.specular_factor = 0.0, 0.5
    flagged = [warning for _, warning, differs in lights.ignored_light_settings(sun) if differs]
    assert flagged == ["light specular factor (1 used)"]
    area = bpy.data.lights.new("probe area", "AREA")
    area.spread = 1.0  # simulated (sphrect.RectLight.spread): not among the ignored settings
    assert not [label for label, _, differs in lights.ignored_light_settings(area) if differs]
    assert "Spread (full hemisphere)" not in [label for label, _, _ in lights.ignored_light_settings(area)]
    bpy.data.lights.remove(sun)
    bpy.data.lights.remove(area)
