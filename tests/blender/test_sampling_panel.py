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
