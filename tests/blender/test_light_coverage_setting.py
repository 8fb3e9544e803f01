"""scene.sphrect.analytic_light_coverage ("Exact Light Edges"): on by default, shown in the Sampling panel, and
it reaches the renderer: on a scene whose disks are in view, F12 with it on differs from F12 with it off only in
pixels the disks' images partly cover, and there it is closer to a high-sample render."""
import bpy
import numpy as np
import pytest

from conftest import addon_module, ensure_addon, open_blend


def test_default_and_options():
    ensure_addon()
    s = bpy.context.scene.sphrect
    assert s.bl_rna.properties["analytic_light_coverage"].default is True
    for value in (True, False):
        s.analytic_light_coverage = value
        assert s.renderer_options()["analytic_light_coverage"] is value


@pytest.mark.parametrize("pixel_filter", ["BOX", "BLACKMAN_HARRIS"])  # exact, and Blender's default (estimated)
def test_setting_changes_the_disk_edges_in_an_f12_render(pixel_filter):
    scene = open_blend("08_disk_room", 48, 36)
    s = scene.sphrect
    s.technique, s.passes = "RECTANGLE", 1
    s.pixel_filter, s.filter_width = pixel_filter, 1.5
    engine = addon_module("engine.render_engine")
    images = {}
    for value, samples in ((True, 4), (False, 4), (False, 512)):
        s.analytic_light_coverage, s.samples = value, samples
        bpy.ops.render.render(write_still=False)
        assert engine.last_render["errors"] == []
        images[value, samples] = np.asarray(engine.last_render["images"]["rectangle"], np.float64)[..., :3]
    on, off, ref = images[True, 4], images[False, 4], images[False, 512]
    changed = np.any(on != off, axis=-1)
    assert 0 < changed.sum() < changed.size / 4
    # Fixed seeds: deterministic.  The disks' edges are where the 4-sample error is.
    assert ((on - ref) ** 2)[changed].sum() < 0.2 * ((off - ref) ** 2)[changed].sum()
