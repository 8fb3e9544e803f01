"""Translucent BSDF (kind 'translucent'): a thin surface lit from behind, seen from the front, against Lambert's
closed form for the irradiance of a polygon; every technique and light selection agrees (per-pixel t-tests over
independent replicates, family-wise false-failure rate 1e-4 per test); light on the viewer's side is not
reflected."""
import numpy as np
import pytest

import sphrect
from render_testing import expected_plane_image, pixel_t_test, plane_mesh, polygon_irradiance, replicate_images, \
    top_camera

COLOR = (0.6, 0.8, 0.5)
# A square light below the z = 0 plane, emitting upwards (one-sided), the camera above looking down.
LIGHT_VERTS = [(-0.6, -0.6, -2.5), (0.6, -0.6, -2.5), (0.6, 0.6, -2.5), (-0.6, 0.6, -2.5)]
RADIANCE = 20.0


def square_light(below):
    """cross(edge_x, edge_y) = +z: a one-sided light emitting upwards (below the plane) or, flipped, downwards
    (above it; the orthographic camera at z = 5 sees the plane, not the light from behind)."""
    z = -2.5 if below else 2.5  # far enough that the tree could cull it by the horizon
    ey = (0.0, 1.2, 0.0) if below else (0.0, -1.2, 0.0)
    corner = (-0.6, -0.6, z) if below else (-0.6, 0.6, z)
    return sphrect.RectLight(corner=corner, edge_x=(1.2, 0.0, 0.0), edge_y=ey, radiance=(RADIANCE,) * 3, visible=below)


def scene(material, below=True, above=False):
    lights = [square_light(True)] * below + [square_light(False)] * above
    return sphrect.Scene(camera=top_camera(8, 8, half=1.0), materials=[material], meshes=[plane_mesh(1.0)],
                         lights=lights)


def expected_translucent():
    cam = top_camera(8, 8, half=1.0)
    irradiance = lambda p: RADIANCE * polygon_irradiance(p, (0.0, 0.0, -1.0), LIGHT_VERTS)
    return expected_plane_image(cam, COLOR[0], irradiance)


@pytest.mark.parametrize("light_selection", ["tree", "power"])
def test_light_behind_a_translucent_surface_shows_through(light_selection):
    # The light above reflects nothing but must not take the light below's share: the light tree may not cull
    # lights below the surface's horizon here.
    s = scene(sphrect.Material(kind="translucent", base_color=COLOR), above=True)
    # (rectangle_projected: a translucent hit has no horizon, so the technique samples like rectangle there.)
    techniques = ["area", "rectangle", "rectangle_cosine", "rectangle_projected"]
    reps = replicate_images(s, techniques, replicates=6, samples=16, light_selection=light_selection)
    expected = expected_translucent()
    for t in techniques:
        ok, p, alpha = pixel_t_test(reps[t], expected, 1e-4 / len(techniques))
        assert ok, f"{t}: worst p {p:.2e} < {alpha:.2e}"


def test_light_on_the_viewers_side_is_not_reflected():
    r = sphrect.Renderer(scene(sphrect.Material(kind="translucent", base_color=COLOR), below=False, above=True),
                         techniques="rectangle")
    r.render(8)
    assert np.all(r.image("rectangle")[..., :3] == 0)


def test_mix_of_diffuse_and_translucent_adds_both_sides():
    diffuse = sphrect.Material(base_color=(0.5, 0.5, 0.5))
    translucent = sphrect.Material(kind="translucent", base_color=COLOR)
    mix = sphrect.Material(kind="mix",
                           layers=[sphrect.MaterialLayer(0.5, diffuse), sphrect.MaterialLayer(0.5, translucent)])
    images = {}
    for name, m in (("mix", mix), ("translucent", translucent)):
        r = sphrect.Renderer(scene(m), techniques="rectangle", seed=4)
        r.render(64)
        images[name] = r.image("rectangle")[..., 0]
    # Lit from behind only, the mix shows half the translucent lobe (the diffuse side gets nothing).
    np.testing.assert_allclose(images["mix"].mean(), 0.5 * images["translucent"].mean(), rtol=0.03)


def test_projected_light_samples_reach_behind_a_translucent_surface():
    """Without MIS only light samples light the surface: rectangle_projected, whose horizon would drop the light
    behind it, samples like rectangle at translucent hits (no normal), so the image is still the closed form."""
    s = scene(sphrect.Material(kind="translucent", base_color=COLOR))
    reps = replicate_images(s, ["rectangle_projected"], replicates=6, samples=16, mis="none")
    ok, p, alpha = pixel_t_test(reps["rectangle_projected"], expected_translucent(), 1e-4)
    assert ok, f"worst p {p:.2e} < {alpha:.2e}"


@pytest.mark.parametrize("technique", ["rectangle", "triangles"])
def test_textured_translucent_surface_under_the_tree(technique):
    """Its colour from an image, black without it: whether a hit has the translucent lobe is known only once its
    texture is read, so the light tree chooses at shading (no horizon) -- not with the chunk's early choices,
    whose receiver would be the untextured material's (a horizon, which culls the light below)."""
    texture = sphrect.Texture(name="colour", colorspace="linear",
                              pixels=np.array(COLOR + (1.0,), np.float32).reshape(1, 1, 4))
    material = sphrect.Material(kind="translucent", base_color=(0.0, 0.0, 0.0),
                                textures={"base_color": sphrect.TextureLookup(texture=0)})
    s = sphrect.Scene(camera=top_camera(8, 8, half=1.0), materials=[material], meshes=[plane_mesh(1.0)],
                      lights=[square_light(True), square_light(False)], textures=[texture])
    reps = replicate_images(s, [technique], replicates=6, samples=16, light_selection="tree")
    ok, p, alpha = pixel_t_test(reps[technique], expected_translucent(), 1e-4)
    assert ok, f"worst p {p:.2e} < {alpha:.2e}"
