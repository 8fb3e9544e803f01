"""rectangle_projected in the renderer.

- On the analytic plane scenes (test_render_analytic.RECT_SCENES: light parallel, perpendicular,
  distant, grazing; a Lambertian plane, the light unoccluded) ONE sample per pixel already gives
  the closed form within 1e-4 per pixel: with light samples alone at diffuse hits (the default,
  bsdf_samples_on_diffuse=False) the estimator has no variance.  Camera samples land within a
  0.01-pixel box filter around the pixel centre; the irradiance's own variation over that footprint
  (from the closed form, on a grid over the box) is added to the bound.
- In a medium there is no normal: scattering points sample the light with `rectangle` (kMediumTechnique),
  so a fog-only scene renders bit for bit as with `rectangle`.
No statistical tests here: the bounds are deterministic (fixed seeds).
"""
import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh, polygon_irradiance, top_camera
from test_render_analytic import ALBEDO, RECT_SCENES, rect_verts

FOOTPRINT = 0.01  # box filter width in pixels (the renderer's smallest)


def _pixel_centres_and_spread(cam, light):
    """Radiance albedo / pi E at the pixel centres, and the spread (max - min) of that over each
    pixel's FOOTPRINT-wide box (a 5 x 5 grid of the box: E is smooth there)."""
    hw, hh, ox, oy = cam.image_plane()
    verts = rect_verts(light.corner, light.edge_x, light.edge_y)
    offsets = np.linspace(-FOOTPRINT / 2, FOOTPRINT / 2, 5)
    px = np.arange(cam.width)[None, :, None, None] + 0.5 + offsets[None, None, :, None]
    py = np.arange(cam.height)[:, None, None, None] + 0.5 + offsets[None, None, None, :]
    x = (2 * px / cam.width - 1) * hw + ox
    y = (1 - 2 * py / cam.height) * hh + oy
    X, Y = np.broadcast_arrays(x, y)
    P = np.stack([X, Y, np.zeros_like(X)], axis=-1)
    L = ALBEDO / np.pi * light.radiance[0] * polygon_irradiance(P, (0, 0, 1), verts, two_sided=light.two_sided)
    centre = L[:, :, 2, 2]
    spread = L.max(axis=(2, 3)) - L.min(axis=(2, 3))
    return centre, spread


@pytest.mark.parametrize("name", list(RECT_SCENES))
def test_one_sample_per_pixel_is_exact_on_the_plane(name):
    light = RECT_SCENES[name]
    cam = top_camera()
    cam.pixel_filter, cam.filter_width = "box", FOOTPRINT
    scene = sphrect.Scene(camera=cam, meshes=[plane_mesh()], lights=[light],
                          materials=[sphrect.Material(base_color=(ALBEDO,) * 3)])
    expected, spread = _pixel_centres_and_spread(cam, light)
    assert expected.max() > 0.01
    r = sphrect.Renderer(scene, techniques=["rectangle_projected", "rectangle"], light_samples=1, seed=4)
    assert r.render(1)
    image = r.image("rectangle_projected")[:, :, 0].astype(np.float64)
    err = np.abs(image - expected)
    bound = 1e-4 * expected + spread + 1e-7
    assert np.all(err <= bound), (f"{name}: worst |pixel - closed form| / closed form "
                                  f"{np.max(err / np.maximum(expected, 1e-30)):.3g}")
    # ... where rectangle's one-sample image is noisy (it samples the solid angle, not the cosine),
    # but for the distant light (10^-4 rad wide), over which cos hardly varies.
    rect = r.image("rectangle")[:, :, 0].astype(np.float64)
    if name != "distant":
        assert np.max(np.abs(rect - expected) / expected.max()) > 1e-3


def test_medium_falls_back_to_rectangle():
    """A fog-only scene (no surface): every light sample is taken at a scattering point, where the
    technique is `rectangle`; the image is rectangle's, bit for bit."""
    light = sphrect.RectLight(corner=(-0.3, -0.3, 1.0), edge_x=(0, 0.6, 0), edge_y=(0.6, 0, 0), radiance=(3, 3, 3),
                              visible=False)
    scene = sphrect.Scene(camera=top_camera(width=8, height=8), meshes=[], lights=[light],
                          world=sphrect.World(medium=sphrect.Medium(sigma_s=(0.3,) * 3, g=0.2)))
    r = sphrect.Renderer(scene, techniques=["rectangle_projected", "rectangle", "rectangle_cosine"], seed=2)
    assert r.render(8)
    a, b = r.image("rectangle_projected"), r.image("rectangle")
    assert a.max() > 0
    assert np.array_equal(a, b)
