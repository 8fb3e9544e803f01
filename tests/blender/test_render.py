"""Rendering through the engine: every blend scene, the Render Result's pixels, the scene-file round trip."""
import bpy
import numpy as np
import pytest

import sphrect
from conftest import SCENES, addon_module, engine_module, lit_test_scene, open_blend, render

# Effects each scene must switch on (named by the renderer and shown in the stats line).
EXPECTED_FEATURES = {"03_glossy_floor": {"glossy"}, "04_foggy_room": {"medium"},
                     "06_mixed_lights": {"ellipse_lights", "delta_lights"}, "09_hall": {"glossy", "ellipse_lights"},
                     "10_night_street": {"delta_lights", "emissive_meshes", "background"},
                     "11_paper_disk": {"ellipse_lights"}, "12_disk_ceiling": {"ellipse_lights"},
                     "13_textured_room": {"glossy", "ellipse_lights", "textures", "normal_maps"},
                     "14_still_life": {"glossy", "ellipse_lights", "textures"},
                     "15_fog_stage": {"volumes", "medium", "delta_lights", "emissive_meshes"},
                     "16_fog_room": {"volumes", "medium", "ellipse_lights"}, "17_warehouse": {"glossy"}}
# The one thing a scene is warned about, if any: what Cycles shows at zero bounces and SPHRECT does not model.
EXPECTED_WARNING = {"14_still_life": "refraction of lights seen through a surface"}


def test_all_blend_scenes_exist():
    assert SCENES == ["01_paper", "02_room", "03_glossy_floor", "04_foggy_room", "05_hard_cases",
                      "06_mixed_lights", "07_studio", "08_disk_room", "09_hall", "10_night_street", "11_paper_disk",
                      "12_disk_ceiling", "13_textured_room", "14_still_life", "15_fog_stage", "16_fog_room",
                      "17_warehouse"]


@pytest.mark.parametrize("name", SCENES)
def test_blend_scene_renders_finite_lit_image(name):
    scene = open_blend(name, 32, 24)
    scene.sphrect.samples, scene.sphrect.passes = 4, 2
    rec = render()
    assert rec["errors"] == []
    if name in EXPECTED_WARNING:
        assert len(rec["warnings"]) == 1 and "; " not in rec["warnings"][0], rec["warnings"]
        assert EXPECTED_WARNING[name] in rec["warnings"][0]
    else:
        assert rec["warnings"] == []
    image = rec["images"]["rectangle"]
    assert image.shape == (24, 32, 4) and image.dtype == np.float32
    assert np.isfinite(image).all()
    assert image[..., :3].mean() > 0.01
    features = set(rec["features"])
    assert EXPECTED_FEATURES.get(name, set()) <= features
    for f in features:
        assert f in rec["stats_line"]
    assert rec["stats"]["rectangle"]["samples"] == 4


def test_render_result_pixels_and_scene_file_round_trip(empty_scene, tmp_path):
    """The Render Result holds the renderer's image (bottom row first in Blender), and the exported scene
    file rendered by sphrect alone, outside the engine, gives the same image."""
    scene = lit_test_scene(empty_scene)
    s = scene.sphrect
    s.technique, s.samples, s.passes, s.seed, s.pattern, s.mis = "RECTANGLE_COSINE", 6, 2, 3, "HAMMERSLEY", "POWER"
    exr = str(tmp_path / "out.exr")
    settings = scene.render.image_settings
    settings.file_format, settings.color_mode, settings.color_depth = "OPEN_EXR", "RGBA", "32"
    scene.render.filepath = exr
    bpy.ops.render.render(write_still=True)
    ours = engine_module().last_render["images"]["rectangle_cosine"]
    blender = addon_module("images").read_image_rgba(exr)
    assert blender.shape == ours.shape == (24, 32, 4)
    assert np.allclose(blender[..., :3], ours[..., :3], rtol=1e-6, atol=1e-7)

    path = str(tmp_path / "scene.sphrect.npz")
    import sphrect_blender
    sphrect_blender.export_scene(bpy.context.evaluated_depsgraph_get(), path)
    loaded = sphrect.load_scene(path)
    r = sphrect.Renderer(loaded, techniques=["rectangle_cosine"], seed=3, pattern="hammersley", mis="power")
    calls = addon_module("engine.schedule").sample_schedule(6, 2, 32 * 24)
    assert calls == [3, 3]  # the engine's two progressive passes
    for samples in calls:
        r.render(samples)
    assert np.allclose(r.image("rectangle_cosine"), ours, rtol=1e-5, atol=1e-6)
