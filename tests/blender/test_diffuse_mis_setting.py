"""scene.sphrect.bsdf_samples_on_diffuse ("MIS on Diffuse"): off by default, in the Sampling panel's options, and it
reaches the renderer: on the disk room (diffuse walls, Principled objects, disks sampled by the spherical ellipse
map), F12 with it on renders differently from F12 with it off, and with it off differently from MIS None (the
glossy hits keep their BSDF samples)."""
import bpy
import numpy as np

from conftest import addon_module, ensure_addon, open_blend


def test_default_and_options():
    ensure_addon()
    s = bpy.context.scene.sphrect
    assert s.bl_rna.properties["bsdf_samples_on_diffuse"].default is False
    for value in (True, False):
        s.bsdf_samples_on_diffuse = value
        assert s.renderer_options()["bsdf_samples_on_diffuse"] is value


def test_setting_reaches_an_f12_render():
    scene = open_blend("08_disk_room", 32, 24)
    s = scene.sphrect
    s.technique, s.passes, s.samples = "RECTANGLE", 1, 4
    engine = addon_module("engine.render_engine")
    images = {}
    for mis, on_diffuse in (("POWER", False), ("POWER", True), ("NONE", False)):
        s.mis, s.bsdf_samples_on_diffuse = mis, on_diffuse
        bpy.ops.render.render(write_still=False)
        assert engine.last_render["errors"] == []
        images[mis, on_diffuse] = np.asarray(engine.last_render["images"]["rectangle"], np.float64)[..., :3]
    assert np.isfinite(images["POWER", True]).all() and images["POWER", True].mean() > 0
    assert not np.array_equal(images["POWER", True], images["POWER", False])
    assert not np.array_equal(images["POWER", False], images["NONE", False])
