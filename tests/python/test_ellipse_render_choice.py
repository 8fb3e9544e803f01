"""The renderer's spherical_ellipse choice (native/core/ellipse_map_choice.h): per (shading point, light) it
samples by area where area sampling's solid-angle density is within kEllipseAreaMaxSpread of uniform, by the
map elsewhere.  A one-sided disc of radius 0.1 at 0.03 above a Lambertian plane, seen from above out to 14
radii: in the pixels under the disc the density spread bound is above 38 (the map), in the image's outer ring
below 2 (area), so the switch runs through the image for any threshold between those.

Which pixels are on which side is read off the renders, not recomputed here: where every shading point of a
pixel samples by area, spherical_ellipse's pixel equals ellipse_technique="area"'s bit for bit at the same
seed (same sample sequence), which the test also asserts is the case for the image's outer ring.

Unbiased on both sides: the per-pixel t-test of tests/python/test_render_analytic.py (family-wise false-failure
rate 1e-4 per image), and the mean radiance over each side's pixels within 4 standard errors of the closed
form (two-sided t with REPLICATES - 1 = 31 degrees of freedom beyond 4: 3.7e-4 per check).  Two MIS modes x
(one image test + two side tests): a correct renderer fails this file with probability < 1.7e-3 (fixed seeds,
so the outcome is deterministic).  Power: a 2 % error in the expected radiance is rejected on each side."""
import numpy as np
import pytest

import sphrect
from render_testing import expected_plane_image, pixel_t_test, plane_mesh, replicate_images, top_camera
from test_render_analytic import ALBEDO, FAMILY_ALPHA, disc_irradiance

REPLICATES = 32
SAMPLES = 16
CENTER, RADIUS, RADIANCE = (0.0, 0.0, 0.03), 0.1, 20.0
SIDE_SIGMAS = 4.0


def disc_scene():
    light = sphrect.EllipseLight(center=CENTER, axis_x=(0, RADIUS, 0), axis_y=(RADIUS, 0, 0),  # facing down
                                 radiance=(RADIANCE,) * 3, visible=False)
    return sphrect.Scene(camera=top_camera(width=16, height=16), meshes=[plane_mesh()], lights=[light],
                         materials=[sphrect.Material(base_color=(ALBEDO,) * 3)])


def side_z(reps, expected, mask):
    """(mean over the side's pixels of replicate / expected - 1) / its standard error (relative, so that the
    bright pixels under the disc do not drown the others)."""
    per_rep = (reps[:, mask] / expected[mask]).mean(axis=1)
    return (per_rep.mean() - 1) / (per_rep.std(ddof=1) / np.sqrt(len(per_rep)))


@pytest.mark.parametrize("mis", ["none", "balance"])
def test_renders_are_unbiased_on_both_sides_of_the_switch(mis):
    scene = disc_scene()
    expected = expected_plane_image(scene.camera, ALBEDO, lambda P: disc_irradiance(P, CENTER, RADIUS, RADIANCE))
    # (BSDF samples on the diffuse plane with either ellipse technique, so that both draw the same samples.)
    reps = {k: replicate_images(scene, ["rectangle"], REPLICATES, SAMPLES, mis=mis, ellipse_technique=k,
                                bsdf_samples_on_diffuse=True)["rectangle"]
            for k in sphrect.ellipse_techniques}
    by_area = np.all(reps["spherical_ellipse"] == reps["area"], axis=0)
    by_map = ~by_area  # (a pixel some of whose shading points take the map)
    # Both sides are in the image: the outer ring by area, the middle by the map.
    ring = np.ones_like(by_area)
    ring[1:-1, 1:-1] = False
    assert by_area[ring].all(), "pixels at 7 radii from the disc should be sampled by area"
    assert np.all(reps["spherical_ellipse"][:, 7:9, 7:9] != reps["area"][:, 7:9, 7:9]), "under the disc: the map"
    assert by_area.sum() >= 10 and by_map.sum() >= 10, (by_area.sum(), by_map.sum())
    img = reps["spherical_ellipse"]
    ok, p_min, alpha = pixel_t_test(img, expected, FAMILY_ALPHA)
    assert ok, f"mis={mis}: worst p = {p_min:.3g} < {alpha:.3g}"
    for side, mask in (("area", by_area), ("map", by_map)):
        z = side_z(img, expected, mask)
        assert abs(z) < SIDE_SIGMAS, f"mis={mis}, {side} side: mean off the closed form by {z:.2f} standard errors"
        # Power: 2 % too bright is rejected.
        assert abs(side_z(img, 1.02 * expected, mask)) > SIDE_SIGMAS, f"{side}: the side test has no power"
