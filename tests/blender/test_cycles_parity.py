"""Cycles parity: on a diffuse scene lit directly by a rectangle light, SPHRECT's converged render
matches Cycles 3.4's (Diffuse BSDF, max_bounces = 0, denoising off, SPHRECT's pixel filter, EXR output).

Both images still hold Monte Carlo noise, so they are compared after averaging 4x4-pixel blocks; the
residual noise of the 2048-sample Cycles image is then well under 1% (estimated from its spread), far
below the 2% bound. Fixed seeds: the test is deterministic."""
import importlib

import bpy
import numpy as np
import pytest

from conftest import addon_module, lit_test_scene, open_blend, render, set_resolution

pytestmark = pytest.mark.slow

WIDTH, HEIGHT, BLOCK = 48, 36, 4


def cycles_peer():
    return importlib.import_module("sphrect_blender.cycles_peer")  # not imported by registering the add-on


def render_cycles(scene, path, samples, seed=0):
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.use_adaptive_sampling = False
    c.use_denoising = False          # Debian's Cycles has no OpenImageDenoise: the render fails otherwise
    c.max_bounces = 0                # direct light only
    c.seed = seed
    cycles_peer().use_pixel_filter(scene)  # SPHRECT's pixel filter (its Film panel's), like for like
    c.light_sampling_threshold = 0.0
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    scene.render.film_transparent = False
    settings = scene.render.image_settings
    settings.file_format, settings.color_mode, settings.color_depth = "OPEN_EXR", "RGBA", "32"
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    return addon_module("images").read_image_rgba(path)  # row 0 = top, like sphrect


def blocks(image):
    rgb = image[..., :3].astype(np.float64)
    return rgb.reshape(HEIGHT // BLOCK, BLOCK, WIDTH // BLOCK, BLOCK, 3).mean(axis=(1, 3))


def mean_relative_difference(ours, theirs):
    """Mean over lit 4x4 blocks and channels of |ours - theirs| / theirs."""
    a, b = blocks(ours), blocks(theirs)
    lit = b > 0.02 * b.max()
    return float(np.mean(np.abs(a[lit] - b[lit]) / b[lit]))


def difference_to_cycles(scene, label, tmp_path, light_samples=2, cycles=None):
    """Render `scene` with Cycles (2048 spp; or take `cycles`, Cycles' image of this scene an earlier call returned:
    its render is deterministic) and with SPHRECT (512 spp, rectangle); print and return the mean relative
    difference, and both images."""
    if cycles is None:
        cycles = render_cycles(scene, str(tmp_path / "cycles.exr"), samples=2048)
    scene.render.engine = "SPHRECT"
    scene.sphrect.samples, scene.sphrect.passes, scene.sphrect.light_samples = 512, 1, light_samples
    ours = render()["images"]["rectangle"]
    difference = mean_relative_difference(ours, cycles)
    print(f"{label}: mean relative difference to Cycles (4x4 blocks): {difference:.4f}")
    return difference, ours, cycles


def test_diffuse_scene_matches_cycles(empty_scene, tmp_path):
    scene = lit_test_scene(empty_scene)
    bpy.data.objects["Light"].visible_camera = False
    set_resolution(scene, WIDTH, HEIGHT)
    scene.sphrect.technique = "RECTANGLE"
    difference, ours, cycles = difference_to_cycles(scene, "diffuse scene", tmp_path, light_samples=4)
    assert cycles[..., :3].max() > 0
    assert np.isfinite(ours).all() and np.isfinite(cycles).all()
    assert difference <= 0.02
    # The comparison can fail: a 5% error in the light's power is caught.
    assert mean_relative_difference(1.05 * ours, cycles) > 0.03


def test_world_filtered_out_of_the_view_layer_lights_nothing_in_either(empty_scene, tmp_path):
    """With the view layer's Filter > Environment off, Cycles 3.4 neither shows the world nor is lit by it (its
    background shader is then the empty one), and neither is SPHRECT; on, both are (the check can fail)."""
    scene = lit_test_scene(empty_scene)
    bpy.data.objects.remove(bpy.data.objects["Light"])  # the world alone lights the scene
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.5, 0.5, 0.5, 1)
    set_resolution(scene, 16, 12)
    scene.sphrect.samples, scene.sphrect.passes = 16, 1
    images = {}
    for use_sky in (False, True):
        bpy.context.view_layer.use_sky = use_sky
        cycles = render_cycles(scene, str(tmp_path / f"cycles_{use_sky}.exr"), samples=16)
        scene.render.engine = "SPHRECT"
        images[use_sky] = cycles[..., :3], render()["images"]["rectangle"][..., :3]
    assert images[False][0].max() == 0 and images[False][1].max() == 0
    assert images[True][0].min() > 0 and images[True][1].min() > 0


@pytest.mark.parametrize("light", ["Square", "Rectangle", "Disk", "Ellipse", "Point", "Spot", "Sun"])
def test_every_light_type_matches_cycles(light, tmp_path):
    """Cycles' conventions for each light (power -> radiance / intensity / irradiance, shapes, object scale,
    spot cone and blend) on the mixed-lights scene (modifiers, instances, smooth shading), one light at a
    time."""
    scene = open_blend("06_mixed_lights", WIDTH, HEIGHT)
    for obj in bpy.data.objects:
        if obj.type == "LIGHT":
            obj.visible_camera = False
            obj.hide_render = obj.name != light
    difference, _, _ = difference_to_cycles(scene, light, tmp_path)
    assert difference <= 0.02


# name -> (light shape, spread in degrees, seen by the camera): Cycles 3.4's Spread on the smallest scene's light
# (2 m above the ground, tilted): the light's cone a soft spot on the ground, its image attenuated.  No disk of
# small spread: Cycles samples disks whole by area, and at 10 degrees its 2048- and 8192-sample images still differ
# by 9 % per block (ours is within 4 % of the latter, the lit total within 1.2 %).
SPREADS = {"rect_30": ("RECTANGLE", 30.0, False), "rect_90_seen": ("RECTANGLE", 90.0, True),
           "square_5": ("SQUARE", 5.0, False), "disk_60": ("DISK", 60.0, False)}


@pytest.mark.parametrize("case", sorted(SPREADS))
def test_area_light_spread_matches_cycles(empty_scene, case, tmp_path):
    """Area light Spread as Cycles 3.4 evaluates it: the attenuation and its normalisation (float cancellation at
    small spreads included), on the ground and, for the light the camera sees, on its image.  Cycles' 2048-sample
    image of these spots is noisier than of the diffuse scene (two of its seeds differ by 0.6-1.8 % per block,
    as much as ours differs from it), so the lit total is checked to 1 % besides the blocks to 2 %."""
    shape, degrees, seen = SPREADS[case]
    scene = lit_test_scene(empty_scene)
    light = bpy.data.objects["Light"]
    light.visible_camera = seen
    light.data.shape = shape
    light.data.spread = np.radians(degrees)
    set_resolution(scene, WIDTH, HEIGHT)
    difference, ours, cycles = difference_to_cycles(scene, f"spread {case}", tmp_path, light_samples=4)
    assert difference <= 0.02
    a, b = blocks(ours), blocks(cycles)
    lit = b > 0.02 * b.max()
    total = a[lit].sum() / b[lit].sum()
    print(f"spread {case}: lit total / Cycles' {total:.4f}")
    assert abs(total - 1) <= 0.01
    light.data.spread = np.pi  # the comparison sees the spread
    assert mean_relative_difference(render()["images"]["rectangle"], cycles) > 2 * difference


CAMERAS = {
    "shift_vertical_fit": dict(lens=28.0, sensor_fit="VERTICAL", sensor_height=20.0, shift_x=0.15, shift_y=-0.1),
    "orthographic": dict(type="ORTHO", ortho_scale=6.0, shift_x=0.05),
    # f/0.4 at 50 mm: a 6 cm aperture radius focused at 2 m, the objects 6 m away are strongly blurred.
    "depth_of_field": dict(lens=50.0, dof=dict(use_dof=True, focus_distance=2.0, aperture_fstop=0.4)),
}


@pytest.mark.parametrize("camera", sorted(CAMERAS))
def test_camera_models_match_cycles(empty_scene, camera, tmp_path):
    """Blender's camera conventions (sensor fit, shift, orthographic, depth of field) as Cycles renders them."""
    scene = lit_test_scene(empty_scene)
    bpy.data.objects["Light"].visible_camera = False
    cam = scene.camera.data
    for k, v in CAMERAS[camera].items():
        if k == "dof":
            for dk, dv in v.items():
                setattr(cam.dof, dk, dv)
        else:
            setattr(cam, k, v)
    set_resolution(scene, WIDTH, HEIGHT)
    difference, _, cycles = difference_to_cycles(scene, camera, tmp_path)
    assert difference <= 0.02
    if camera == "depth_of_field":  # the comparison sees the blur: without it we are further from Cycles
        cam.dof.use_dof = False
        assert mean_relative_difference(render()["images"]["rectangle"], cycles) > difference


@pytest.mark.parametrize("name", ["02_room", "03_glossy_floor", "04_foggy_room", "15_fog_stage", "16_fog_room"])
def test_blend_scenes_match_cycles(name, tmp_path):
    """The exporter's conversions end to end: a closed room, Principled BSDF (metallic floor, plastic
    sphere: base colour, metallic, roughness, specular), the world Volume Scatter as a homogeneous
    medium (density, colour, anisotropy), and object volumes: a fog box seen from outside with a spot light's cone, a
    point light and an emissive globe in it, and a Principled Volume box holding the camera and the lights.
    (01_paper's two-sided light and 05's tiny/grazing lights are outside what Cycles 3.4 renders correctly or at all;
    see test_analytic.py.) Measured when written: room 0.2%, fog 0.8%, glossy 1.6%, fog stage 0.84%, fog room 0.35%
    -- the glossy residual is systematic (it stays with 4x the samples: Cycles' Principled BSDF is not exactly the
    renderer's GGX + Lambert model), the others are noise."""
    scene = open_blend(name, WIDTH, HEIGHT)
    for obj in bpy.data.objects:
        if obj.type == "LIGHT":
            obj.visible_camera = False
    difference, _, _ = difference_to_cycles(scene, name, tmp_path)
    assert difference <= 0.02
