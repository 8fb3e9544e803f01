"""Colour management's Exposure applies to SPHRECT's renders as to Cycles': the engine writes linear radiance into
the render result (unchanged by Exposure), and Blender's view transform scales it by 2^exposure when it displays or
saves a display-referred image (and the viewport draws through the same display-space shader)."""
import bpy
import numpy as np

from conftest import lit_test_scene, render, set_resolution


def saved_png(scene, path):
    """F12 written as an 8-bit PNG through the scene's view transform, read back decoded to linear."""
    scene.render.filepath = str(path)
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_depth = "8"
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(str(path))
    pixels = np.array(image.pixels[:], dtype=np.float64).reshape(image.size[1], image.size[0], 4)[..., :3]
    bpy.data.images.remove(image)
    return pixels ** 2.2  # about the sRGB curve: enough to see a factor 2


def test_exposure_scales_the_saved_image_not_the_render(empty_scene, tmp_path):
    scene = lit_test_scene(empty_scene)
    set_resolution(scene, 32, 24)
    scene.render.engine = "SPHRECT"
    scene.sphrect.samples, scene.sphrect.passes = 16, 1
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.exposure = 0.0
    linear = render()["images"]["rectangle"][..., :3].copy()
    dark = saved_png(scene, tmp_path / "e0.png")
    scene.view_settings.exposure = 1.0
    assert np.array_equal(render()["images"]["rectangle"][..., :3], linear)  # the render result stays linear
    bright = saved_png(scene, tmp_path / "e1.png")
    usable = (dark > 0.02) & (bright < 0.8)  # neither quantised to nothing nor clipped
    assert usable.mean() > 0.2
    ratio = np.median(bright[usable] / dark[usable])
    assert 1.8 < ratio < 2.2, ratio
