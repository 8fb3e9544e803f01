"""A rectangle or ellipse light's own texture (RectLight.texture, EllipseLight.texture: a Blender light's node tree):
its radiance at a point is `radiance` x the lookup's colour at the point's coordinates along the light's edges, for
light samples, BSDF rays and camera rays alike; a textured rectangle without spread is sampled by its blocks
(core/rectangle_blocks.h), one with spread on the part a point receives from.

Statistical tests use fixed seeds; the per-pixel t-tests (render_testing.pixel_t_test) fail falsely with probability
FAMILY_ALPHA = 1e-4 over all their pixels and configurations."""
import dataclasses
import math

import numpy as np
import pytest

import sphrect
from render_testing import (expected_plane_image, pixel_t_test, plane_mesh, polygon_irradiance, replicate_images,
                            save_as_older_version, top_camera)
from sphrect.render import build_native_scene

FAMILY_ALPHA = 1e-4
ALBEDO = 0.5
RADIANCE = 2.0
# A light 1 above the plane, facing down: edge_x along +y, edge_y along +x (cross(edge_x, edge_y) = -z).
CORNER, EDGE_X, EDGE_Y = (-0.5, -0.4, 1.0), (0.0, 0.9, 0.0), (1.1, 0.0, 0.0)
# Its part a < 1/2 (y < 0.05), white in a 2 x 1 image read 'closest', and the rest, a quarter of it.
FIRST_HALF = [[-0.5, -0.4, 1], [0.6, -0.4, 1], [0.6, 0.05, 1], [-0.5, 0.05, 1]]
SECOND_HALF = [[-0.5, 0.05, 1], [0.6, 0.05, 1], [0.6, 0.5, 1], [-0.5, 0.5, 1]]
TWO_TONE = [[[1, 1, 1], [0.25, 0.25, 0.25]]]


def ground():
    g = plane_mesh()
    g.material_ids = np.zeros(2, np.int32)
    return g


def lit_scene(light, pixels=TWO_TONE, cam=None):
    texture = sphrect.Texture(name="image", pixels=np.asarray(pixels, np.float32), colorspace="linear")
    return sphrect.Scene(camera=cam or top_camera(height_above=0.5), meshes=[ground()], lights=[light],
                         materials=[sphrect.Material(name="ground", base_color=(ALBEDO,) * 3)], textures=[texture])


def textured_rect(**kw):
    return sphrect.RectLight(corner=CORNER, edge_x=EDGE_X, edge_y=EDGE_Y, radiance=(RADIANCE,) * 3,
                             texture=sphrect.TextureLookup(texture=0, interpolation="closest"), **kw)


def two_tone_irradiance(P):
    return RADIANCE * (polygon_irradiance(P, (0, 0, 1), FIRST_HALF) + 0.25 * polygon_irradiance(P, (0, 0, 1),
                                                                                               SECOND_HALF))


def test_a_textured_light_keeps_its_mean_for_selection():
    native, warnings = build_native_scene(lit_scene(textured_rect()))
    assert native.num_area_lights == 1 and not warnings


@pytest.mark.parametrize("blocks", [True, False])
@pytest.mark.parametrize("technique", ["rectangle", "area", "rectangle_projected"])
def test_two_tone_rectangle_light_against_closed_form(technique, blocks):
    """A light whose image is white on its first half along edge_x and 1/4 on the rest lights the plane as its two
    halves of those radiances do (Lambert's polygon formula)."""
    cam = top_camera(height_above=0.5)
    expected = expected_plane_image(cam, ALBEDO, two_tone_irradiance)
    reps = replicate_images(lit_scene(textured_rect(), cam=cam), [technique], 12, 16, emission_blocks=blocks)
    ok, p_min, alpha = pixel_t_test(reps[technique], expected, FAMILY_ALPHA / 12)
    assert ok, f"{technique}, blocks {blocks}: worst p = {p_min:.3g} < {alpha:.3g}"


@pytest.mark.slow
@pytest.mark.parametrize("mis", ["power", "balance"])
def test_bsdf_rays_read_the_image_where_they_cross_the_light(mis):
    """MIS with BSDF samples on the diffuse hits too: BSDF rays that cross the light read its image at their
    crossing (a light that is not a mesh: found by the analytic light finder)."""
    cam = top_camera(height_above=0.5)
    expected = expected_plane_image(cam, ALBEDO, two_tone_irradiance)
    reps = replicate_images(lit_scene(textured_rect(), cam=cam), ["rectangle"], 12, 16, mis=mis,
                            bsdf_samples_on_diffuse=True)
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, FAMILY_ALPHA / 12)
    assert ok, f"{mis}: worst p = {p_min:.3g} < {alpha:.3g}"


def half_disc(center, radius, z, n=512):
    """The half y < center_y of a disc (a polygon of n + 1 vertices: within 1e-5 of its area)."""
    a = np.linspace(math.pi, 2 * math.pi, n)
    return [[center[0] + radius * math.cos(t), center[1] + radius * math.sin(t), z] for t in a]


def test_two_tone_ellipse_light_against_closed_form():
    """A disc whose image is white on its first half along axis_x and black on the rest lights the plane as the
    half disc alone (an ellipse's coordinates: along its bounding rectangle's edges)."""
    cam = top_camera(height_above=0.5)
    light = sphrect.EllipseLight(center=(0.05, 0.05, 1.0), axis_x=(0.0, 0.5, 0.0), axis_y=(0.5, 0.0, 0.0),
                                 radiance=(RADIANCE,) * 3,
                                 texture=sphrect.TextureLookup(texture=0, interpolation="closest"))
    half = half_disc((0.05, 0.05), 0.5, 1.0)
    expected = expected_plane_image(cam, ALBEDO, lambda P: RADIANCE * polygon_irradiance(P, (0, 0, 1), half))
    reps = replicate_images(lit_scene(light, pixels=[[[1, 1, 1], [0, 0, 0]]], cam=cam), ["rectangle"], 12, 16)
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, FAMILY_ALPHA / 12)
    assert ok, f"worst p = {p_min:.3g} < {alpha:.3g}"


def test_camera_sees_the_texels_on_the_emitting_side_only():
    """A camera looking up at a one-sided light (a 4 x 4 image filling the view) sees each texel's radiance; the
    light turned away shows black."""
    pixels = np.random.default_rng(3).uniform(0.1, 1.0, (4, 4, 3)).astype(np.float32)
    cam = sphrect.Camera(width=8, height=8, type="orthographic", ortho_scale=1.0,
                         to_world=[[1, 0, 0, 0], [0, -1, 0, 0], [0, 0, -1, 0.5], [0, 0, 0, 1]])
    # edge_x along +x, edge_y along +y: cross = +z, away from the camera below; swapped, it faces the camera.
    facing = sphrect.RectLight(corner=(-0.5, -0.5, 1.0), edge_x=(0.0, 1.0, 0.0), edge_y=(1.0, 0.0, 0.0),
                               radiance=(RADIANCE,) * 3,
                               texture=sphrect.TextureLookup(texture=0, interpolation="closest"))
    for light, seen in [(facing, True), (dataclasses.replace(facing, corner=(-0.5, -0.5, 1.0), edge_x=(1.0, 0, 0),
                                                             edge_y=(0, 1.0, 0)), False)]:
        r = sphrect.Renderer(lit_scene(light, pixels=pixels, cam=cam), techniques=["rectangle"], seed=1)
        assert r.render(4)
        image = r.image("rectangle")[..., :3]
        if not seen:
            assert image.max() == 0
            continue
        for py in range(8):
            for px in range(8):
                x, y = -0.5 + (px + 0.5) / 8, -(0.5 - (py + 0.5) / 8)  # the camera's y axis is the world's -y
                a, b = y + 0.5, x + 0.5  # along edge_x (+y) and edge_y (+x) from the corner
                np.testing.assert_allclose(image[py, px], RADIANCE * pixels[int(b * 4), int(a * 4)], rtol=1e-5)


def test_a_white_image_is_the_untextured_light_with_spread():
    """With spread (sampled on the clipped part, no blocks), a white image changes nothing but the float rounding of
    the light's mean: the images agree to 1e-5."""
    cam = top_camera(height_above=0.5)
    plain = sphrect.RectLight(corner=CORNER, edge_x=EDGE_X, edge_y=EDGE_Y, radiance=(RADIANCE,) * 3,
                              spread=math.radians(40))
    images = []
    for light in (plain, dataclasses.replace(plain, texture=sphrect.TextureLookup(texture=0))):
        r = sphrect.Renderer(lit_scene(light, pixels=[[[1, 1, 1]]], cam=cam), techniques=["rectangle"], seed=4)
        assert r.render(16)
        images.append(r.image("rectangle"))
    assert images[0].max() > 0
    np.testing.assert_allclose(images[1], images[0], rtol=1e-5, atol=1e-7)


def test_two_tone_light_with_spread_is_unbiased():
    """Spread and a texture together: the rectangle map of the clipped part (no blocks) against uniform area
    sampling of it (`area`), per-pixel t-test of the difference."""
    cam = top_camera(width=8, height=8, height_above=0.5)
    scene = lit_scene(textured_rect(spread=math.radians(60)), cam=cam)
    a = replicate_images(scene, ["rectangle"], 12, 16)["rectangle"]
    b = replicate_images(scene, ["area"], 12, 64)["area"]
    ok, p_min, alpha = pixel_t_test(a - b, np.zeros(a.shape[1:]), FAMILY_ALPHA, rel_tol=0)
    assert ok, f"worst p = {p_min:.3g} < {alpha:.3g}"
    assert a.mean() > 1e-3


def test_light_texture_round_trips_through_the_file(tmp_path):
    scene = lit_scene(textured_rect())
    path = tmp_path / "t.sphrect.npz"
    sphrect.save_scene(scene, path)
    loaded = sphrect.load_scene(path)
    assert loaded.lights[0].texture == scene.lights[0].texture
    a, b = sphrect.Renderer(scene, seed=1), sphrect.Renderer(loaded, seed=1)
    assert a.render(4) and b.render(4)
    np.testing.assert_array_equal(a.image("rectangle"), b.image("rectangle"))
    # A version-15 file (before light textures) loads as before: a uniform light.
    old = tmp_path / "old.sphrect.npz"
    save_as_older_version(path, old, 15, lambda meta: [l.pop("texture") for l in meta["lights"]])
    assert sphrect.load_scene(old).lights[0].texture is None


def test_bad_light_textures_are_refused():
    scene = lit_scene(textured_rect())
    scene.lights[0].texture = {"texture": 0}
    with pytest.raises(ValueError, match="must be a sphrect.TextureLookup"):
        build_native_scene(scene)
    scene.lights[0].texture = sphrect.TextureLookup(texture=3)
    with pytest.raises(ValueError, match="not an index into the scene's 1 textures"):
        build_native_scene(scene)
    scene.lights[0].texture = sphrect.TextureLookup(texture=0, coordinates="generated")
    with pytest.raises(ValueError, match="coordinates must be 'uv'"):
        build_native_scene(scene)
