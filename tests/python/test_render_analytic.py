"""Analytic scenes: a Lambertian plane lit by one rectangle (parallel, perpendicular, distant,
grazing), by a disc (under it, distant, near) with each ellipse technique, and by delta lights.  Every
pixel's radiance is albedo / pi times the closed-form irradiance averaged over the pixel (Gauss-Legendre).
Each technique and MIS mode must pass a per-pixel t-test over independent replicates; with MIS, both with the
diffuse plane taking light samples alone (the default) and with its BSDF samples (bsdf_samples_on_diffuse).
Where two of those settings render the same image bit for bit (see image_tested_as), the image is t-tested
once and the other setting's first replicate is checked to be identical.

False-failure rate: each image is one family of pixel tests with family-wise rate 1e-4 (Sidak
correction); there are 4 x (5 + 2 x (1 + 4)) + 3 x 2 x 2 + 1 + 1 + 2 + 4 x 2 + 4 = 88 image tests (rectangles x
(no MIS: every technique; two heuristics x (area, whose image is the same with either setting, and the four
solid-angle techniques with BSDF samples on the diffuse plane: without, theirs is the image without MIS)), discs
x ellipse techniques x MIS, the ellipse techniques against each other in fog, delta lights, the power check's
correct images, several light samples, two lights), so a correct renderer fails this file with probability
< 0.9 % (seeds are fixed, so the outcome is deterministic).  The last test shows the test has power: a 3 %
error in the expected image is rejected."""
import math

import numpy as np
import pytest
from scipy import stats

import sphrect
from chi2 import sidak_alpha
from render_testing import (ALL_TECHNIQUES, expected_plane_image, pixel_t_test, plane_mesh, polygon_irradiance,
                            replicate_images, top_camera)

FAMILY_ALPHA = 1e-4
ALBEDO = 0.5
REPLICATES = 24
SAMPLES = 16


def rect_verts(corner, ex, ey):
    c, ex, ey = (np.asarray(a, np.float64) for a in (corner, ex, ey))
    return np.array([c, c + ex, c + ex + ey, c + ey])


# name -> (RectLight, radiance scale); the edges are ordered so cross(ex, ey) faces the plane
# where the light is one-sided.
RECT_SCENES = {
    # 1 x 1 light at height 1, facing down, off-centre.
    "parallel": sphrect.RectLight(corner=(-0.2, -0.3, 1.0), edge_x=(0, 1, 0), edge_y=(1, 0, 0), radiance=(1, 1, 1),
                                  visible=False),
    # Two-sided light standing on the plane across the image (x = 0.1, z in [0.05, 1.05]).
    "perpendicular": sphrect.RectLight(corner=(0.1, -0.5, 0.05), edge_x=(0, 1, 0), edge_y=(0, 0, 1),
                                       radiance=(1, 1, 1), two_sided=True, visible=False),
    # 1 x 1 light 10^4 above the plane (distance / size = 10^4).
    "distant": sphrect.RectLight(corner=(-0.5, -0.5, 1e4), edge_x=(0, 1, 0), edge_y=(1, 0, 0), radiance=(1e8,) * 3,
                                 visible=False),
    # Low strip standing at x = -1.5 facing +x: light arrives at 0.02-6 degrees above the horizon.
    "grazing": sphrect.RectLight(corner=(-1.5, -0.5, 0.001), edge_x=(0, 1, 0), edge_y=(0, 0, 0.05),
                                 radiance=(40, 40, 40), visible=False),
}


def rect_scene(light):
    return sphrect.Scene(camera=top_camera(), meshes=[plane_mesh()], lights=[light],
                         materials=[sphrect.Material(base_color=(ALBEDO,) * 3)])


def rect_expected(light, cam):
    verts = rect_verts(light.corner, light.edge_x, light.edge_y)
    return expected_plane_image(cam, ALBEDO, lambda P: light.radiance[0] * polygon_irradiance(
        P, (0, 0, 1), verts, two_sided=light.two_sided))


MIS_ON_DIFFUSE = [("none", False)] + [(m, b) for m in sphrect.mis_modes if m != "none" for b in (False, True)]


def image_tested_as(technique, mis, bsdf_on_diffuse):
    """The (mis, bsdf_on_diffuse) whose t-test covers this setting's image of a Lambert-only scene: with MIS, a
    technique sampling by solid angle takes light samples alone at diffuse hits unless bsdf_on_diffuse, so it
    renders as without MIS; area keeps MIS, so bsdf_on_diffuse changes nothing (native LightSamplesAlone, which
    depends only on the option, the material and the technique; test_diffuse_light_samples.py)."""
    if mis == "none":
        return mis, bsdf_on_diffuse
    if technique == "area":
        return mis, False
    return ("none", False) if not bsdf_on_diffuse else (mis, True)


@pytest.mark.slow
@pytest.mark.parametrize("mis, bsdf_on_diffuse", MIS_ON_DIFFUSE)
@pytest.mark.parametrize("name", list(RECT_SCENES))
def test_rectangle_light_on_plane(name, mis, bsdf_on_diffuse):
    light = RECT_SCENES[name]
    scene = rect_scene(light)
    expected = rect_expected(light, scene.camera)
    assert expected.max() > 0.01  # the scene is actually lit
    techniques = [t for t in ALL_TECHNIQUES if image_tested_as(t, mis, bsdf_on_diffuse) == (mis, bsdf_on_diffuse)]
    skipped = [t for t in ALL_TECHNIQUES if t not in techniques]
    if skipped:  # their images are another case's, t-tested there: check that on the first replicate
        (tested_as,) = {image_tested_as(t, mis, bsdf_on_diffuse) for t in skipped}
        ours, tested = (replicate_images(scene, skipped, 1, SAMPLES, mis=m, bsdf_samples_on_diffuse=b)
                        for m, b in ((mis, bsdf_on_diffuse), tested_as))
        for t in skipped:
            assert np.array_equal(ours[t], tested[t]), f"{name}/{mis}/bsdf on diffuse {bsdf_on_diffuse}/{t}"
    reps = replicate_images(scene, techniques, REPLICATES, SAMPLES, mis=mis,
                            bsdf_samples_on_diffuse=bsdf_on_diffuse)
    for t in techniques:
        ok, p_min, alpha = pixel_t_test(reps[t], expected, FAMILY_ALPHA)
        rel = np.abs(reps[t].mean(0) - expected).max() / expected.max()
        assert ok, (f"{name}/{mis}/bsdf on diffuse {bsdf_on_diffuse}/{t}: worst p = {p_min:.3g} < {alpha:.3g} "
                    f"(max rel. error {rel:.3g})")


def disc_irradiance(P, center, radius, radiance):
    """Irradiance on the z = 0 plane (normal +z) from a horizontal disc facing down at height h = center z:
    (pi L / 2) (1 - A / sqrt(A^2 + 4 R^2 h^2)), A = h^2 + rho^2 - R^2 (rho: the offset from the axis), written
    as pi L 2 R^2 h^2 / (s (s + A)) where A > 0 so that it does not cancel for a distant disc."""
    h, R = center[2], radius
    rho2 = (P[..., 0] - center[0]) ** 2 + (P[..., 1] - center[1]) ** 2
    A = h * h + rho2 - R * R
    s = np.sqrt(A * A + 4 * R * R * h * h)
    far = 2 * R * R * h * h / (s * (s + np.abs(A)))
    return np.pi * radiance * np.where(A > 0, far, 0.5 * (1 - A / s))


# name -> (centre, radius, radiance, MIS modes): one-sided discs facing the plane.  "under": the rim in view;
# "distant": a disc 10^4 sizes away; "near": 10^-4 of its radius above the plane, the view under its interior
# (a rim 10^-4 wide in a pixel is beyond the reference's quadrature), where light sampling alone by area has
# a heavy tail (pdf d^2 / (A cos) against an integrand peaked at d ~ h), so it is tested with MIS.
DISC_SCENES = {
    "under": ((0.3, 0.0, 0.8), 0.6, 2.0, ("none", "balance")),
    "distant": ((0.2, -0.1, 1e4), 0.5, 1e8, ("none", "balance")),
    "near": ((0.3, 0.2, 3e-4), 3.0, 1.0, ("balance", "power")),
}


@pytest.mark.parametrize("ellipse_technique", sphrect.ellipse_techniques)
@pytest.mark.parametrize("name", list(DISC_SCENES))
def test_disc_light_on_plane(name, ellipse_technique):
    """A one-sided disc (ellipse light with equal axes) sampled with each ellipse technique; reference: the
    closed form."""
    center, radius, radiance, mis_modes = DISC_SCENES[name]
    light = sphrect.EllipseLight(center=center, axis_x=(0, radius, 0), axis_y=(radius, 0, 0),
                                 radiance=(radiance,) * 3, visible=False)
    scene = sphrect.Scene(camera=top_camera(), meshes=[plane_mesh()], lights=[light],
                          materials=[sphrect.Material(base_color=(ALBEDO,) * 3)])
    expected = expected_plane_image(scene.camera, ALBEDO, lambda P: disc_irradiance(P, center, radius, radiance))
    assert expected.max() > 0.01  # the scene is actually lit
    for mis in mis_modes:
        reps = replicate_images(scene, ["rectangle"], REPLICATES, SAMPLES, mis=mis,
                                ellipse_technique=ellipse_technique)
        ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, FAMILY_ALPHA)
        rel = np.abs(reps["rectangle"].mean(0) - expected).max() / expected.max()
        assert ok, f"disc {name}/{ellipse_technique}/{mis}: worst p = {p_min:.3g} < {alpha:.3g} (max rel. {rel:.3g})"


@pytest.mark.slow
def test_ellipse_techniques_agree_in_a_medium():
    """In fog (single scattering: light samples and phase rays whose MIS pdf is the ellipse technique's) and on
    the plane below, a tilted one-sided disc renders the same expected image with either ellipse technique:
    per-pixel Welch t-test of the two techniques' replicates (family-wise rate FAMILY_ALPHA, Sidak)."""
    light = sphrect.EllipseLight(center=(0.2, 0.1, 1.0), axis_x=(0, 0.5, 0), axis_y=(0.4, 0, -0.3),
                                 radiance=(3, 3, 3), visible=False)
    scene = sphrect.Scene(camera=top_camera(), meshes=[plane_mesh()], lights=[light],
                          materials=[sphrect.Material(base_color=(ALBEDO,) * 3)],
                          world=sphrect.World(medium=sphrect.Medium(sigma_s=(0.4,) * 3, g=0.3)))
    reps = {k: replicate_images(scene, ["rectangle"], 32, 128, mis="balance", ellipse_technique=k)["rectangle"]
            for k in sphrect.ellipse_techniques}
    a, b = reps.values()
    assert a.mean() > 0.01  # the scene is actually lit
    alpha = sidak_alpha(FAMILY_ALPHA, a[0].size)
    p = stats.ttest_ind(a, b, axis=0, equal_var=False).pvalue
    assert p.min() >= alpha, f"worst p = {p.min():.3g} < {alpha:.3g}"
    # The comparison has power: one technique 3 % too bright is rejected.
    assert stats.ttest_ind(1.03 * a, b, axis=0, equal_var=False).pvalue.min() < alpha


def test_delta_lights_on_plane():
    """Point, spot (Cycles 3.4 falloff) and sun together: E = I cos / d^2 + I att cos / d^2 + E_sun cos."""
    point = sphrect.PointLight(position=(0.5, 0.2, 1.0), intensity=(0.7, 0.7, 0.7))
    spot = sphrect.SpotLight(position=(-0.4, 0.1, 1.5), direction=(0, 0, -1), intensity=(2, 2, 2),
                             spot_size=math.radians(60), spot_blend=0.3)
    sun_dir = np.array([0.3, -0.2, -1.0]) / np.linalg.norm([0.3, -0.2, -1.0])
    sun = sphrect.SunLight(direction=tuple(sun_dir), irradiance=(0.9, 0.9, 0.9))
    scene = sphrect.Scene(camera=top_camera(), meshes=[plane_mesh()], lights=[point, spot, sun],
                          materials=[sphrect.Material(base_color=(ALBEDO,) * 3)])

    def irradiance(P):
        e = np.zeros(P.shape[:-1])
        d = np.asarray(point.position) - P
        dist = np.linalg.norm(d, axis=-1)
        e += 0.7 * (d[..., 2] / dist) / dist ** 2
        d = np.asarray(spot.position) - P
        dist = np.linalg.norm(d, axis=-1)
        cos_axis = -d[..., 2] / dist * -1  # dot(-d/|d|, (0,0,-1))
        cos_half = math.cos(spot.spot_size / 2)
        smooth = (1 - cos_half) * spot.spot_blend
        t = np.clip((cos_axis - cos_half) / smooth, 0, 1)
        blend = np.where(cos_axis - cos_half < smooth, t * t * (3 - 2 * t), 1)
        att = np.where(cos_axis > cos_half, cos_axis * blend, 0)
        e += 2 * att * (d[..., 2] / dist) / dist ** 2
        e += 0.9 * -sun_dir[2]
        return e

    expected = expected_plane_image(scene.camera, ALBEDO, irradiance)
    reps = replicate_images(scene, ["rectangle"], REPLICATES, 8)
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, FAMILY_ALPHA, rel_tol=1e-4)
    assert ok, f"delta lights: worst p = {p_min:.3g} < {alpha:.3g}"


@pytest.mark.parametrize("mis", ["none", "balance"])
def test_several_light_samples_with_a_delta_light(mis):
    """light_samples = 3: each camera sample averages three light (and BSDF) samples of the rectangle,
    while the point light is evaluated once; both must come out at their closed-form values."""
    light = RECT_SCENES["parallel"]
    point = sphrect.PointLight(position=(0.5, 0.2, 1.0), intensity=(0.7, 0.7, 0.7))
    scene = sphrect.Scene(camera=top_camera(), meshes=[plane_mesh()], lights=[light, point],
                          materials=[sphrect.Material(base_color=(ALBEDO,) * 3)])
    verts = rect_verts(light.corner, light.edge_x, light.edge_y)

    def irradiance(P):
        d = np.asarray(point.position) - P
        dist = np.linalg.norm(d, axis=-1)
        return polygon_irradiance(P, (0, 0, 1), verts) + 0.7 * (d[..., 2] / dist) / dist ** 2

    expected = expected_plane_image(scene.camera, ALBEDO, irradiance)
    reps = replicate_images(scene, ALL_TECHNIQUES, REPLICATES, 8, mis=mis, light_samples=3)
    for t in ALL_TECHNIQUES:
        ok, p_min, alpha = pixel_t_test(reps[t], expected, FAMILY_ALPHA)
        assert ok, f"{mis}/{t}: worst p = {p_min:.3g} < {alpha:.3g}"


def test_two_rectangle_lights():
    """Two rectangles of different power: one is chosen per light sample by power, and with MIS a
    BSDF ray that finds the other one weighs it with that light's pdf (a setup of its own)."""
    small = sphrect.RectLight(corner=(-0.6, -0.5, 0.6), edge_x=(0, 0.3, 0), edge_y=(0.3, 0, 0), radiance=(4, 4, 4),
                              visible=False)
    big = RECT_SCENES["parallel"]
    scene = sphrect.Scene(camera=top_camera(), meshes=[plane_mesh()], lights=[small, big],
                          materials=[sphrect.Material(base_color=(ALBEDO,) * 3)])
    expected = expected_plane_image(scene.camera, ALBEDO, lambda P: sum(
        l.radiance[0] * polygon_irradiance(P, (0, 0, 1), rect_verts(l.corner, l.edge_x, l.edge_y))
        for l in (small, big)))
    reps = replicate_images(scene, ALL_TECHNIQUES, REPLICATES, 8, mis="balance", light_samples=2)
    for t in ALL_TECHNIQUES:
        ok, p_min, alpha = pixel_t_test(reps[t], expected, FAMILY_ALPHA)
        assert ok, f"two lights/{t}: worst p = {p_min:.3g} < {alpha:.3g}"


@pytest.mark.parametrize("facing_camera, two_sided, visible, seen", [
    (True, False, True, True), (False, False, True, False), (False, True, True, True), (True, False, False, False)])
def test_a_light_seen_by_the_camera(facing_camera, two_sided, visible, seen):
    """Camera rays that meet a light see its radiance exactly (from its emitting side, or either side of a
    two-sided light, and only when it is visible); here over a black plane, on pixels it covers fully."""
    ex, ey = ((1, 0, 0), (0, 1, 0)) if facing_camera else ((0, 1, 0), (1, 0, 0))  # cross(ex, ey) = +z or -z
    light = sphrect.RectLight(corner=(-0.5, -0.5, 1.0), edge_x=ex, edge_y=ey, radiance=(2.0, 3.0, 4.0),
                              two_sided=two_sided, visible=visible)
    scene = sphrect.Scene(camera=top_camera(), meshes=[plane_mesh()], lights=[light],
                          materials=[sphrect.Material(base_color=(0, 0, 0))])
    r = sphrect.Renderer(scene, techniques=ALL_TECHNIQUES)
    assert r.render(4)
    for t in ALL_TECHNIQUES:
        image = r.image(t)[:, :, :3]
        inside = image[3:9, 3:9]  # pixels 1/6 wide: [-0.5, 0.5]^2 is the 6 x 6 block in the middle
        np.testing.assert_array_equal(inside, np.broadcast_to([2.0, 3.0, 4.0] if seen else [0, 0, 0], inside.shape))
        assert np.all(image[:2] == 0) and np.all(image[:, :2] == 0)  # well outside: the black plane


def test_t_test_detects_a_small_error():
    """Power check: the same test rejects an expected image that is 3 % off (light sampling only),
    or 10 % off (MIS, whose BSDF samples make the estimate noisier here)."""
    light = RECT_SCENES["parallel"]
    scene = rect_scene(light)
    expected = rect_expected(light, scene.camera)
    for mis, error in (("none", 1.03), ("balance", 1.10)):
        reps = replicate_images(scene, ["rectangle"], REPLICATES, SAMPLES, mis=mis)
        assert pixel_t_test(reps["rectangle"], expected, FAMILY_ALPHA)[0]
        assert not pixel_t_test(reps["rectangle"], expected * error, FAMILY_ALPHA)[0], mis


@pytest.mark.parametrize("mis", ["none", "balance"])
def test_plane_under_a_constant_sky(mis):
    """The world background lights the plane like Cycles' world: E = pi * L_sky, so the plane's
    radiance is albedo * L_sky.  Cosine-weighted BSDF sampling makes every sample exact."""
    scene = sphrect.Scene(camera=top_camera(), meshes=[plane_mesh(1e4)],
                          materials=[sphrect.Material(base_color=(ALBEDO,) * 3)],
                          world=sphrect.World(background=(0.3, 0.6, 0.9)))
    r = sphrect.Renderer(scene, mis=mis)
    assert r.features == ["orthographic", "background"]
    r.render(4)
    np.testing.assert_allclose(r.image()[:, :, :3], np.broadcast_to([0.15, 0.3, 0.45], (12, 12, 3)), rtol=1e-3)


@pytest.mark.parametrize("medium", [False, True])
@pytest.mark.parametrize("mis", sphrect.mis_modes)
def test_umbra_is_black(mis, medium):
    """Under an opaque board between the plane and the light no light arrives by any strategy: every
    pixel is exactly 0 for every technique -- light samples, BSDF (phase) samples that find the light
    and the sky, and scattering in a medium filling the gap.  The camera hangs between the plane and
    the board; every point it sees is in the board's umbra."""
    light = sphrect.RectLight(corner=(-0.5, 0.5, 2.0), edge_x=(1, 0, 0), edge_y=(0, -1, 0), radiance=(5, 5, 5))
    board = plane_mesh(size=1e4, z=1.0)  # wide enough to hide the sky too (a cosine sample below it: p ~ 1e-8)
    board.name = "board"
    world = sphrect.World(background=(0.5, 0.5, 0.5),
                          medium=sphrect.Medium(sigma_s=(0.3,) * 3, sigma_a=(0.05,) * 3) if medium else None)
    scene = sphrect.Scene(camera=top_camera(half=1.0, height_above=0.5), meshes=[plane_mesh(), board],
                          lights=[light, sphrect.PointLight(position=(0.2, 0.1, 1.8), intensity=(3, 3, 3))],
                          materials=[sphrect.Material(base_color=(ALBEDO,) * 3)], world=world)
    r = sphrect.Renderer(scene, techniques=ALL_TECHNIQUES, mis=mis, light_samples=2)
    assert r.render(8)
    for t in ALL_TECHNIQUES:
        assert r.stats(t)["rays"] > 0
        np.testing.assert_array_equal(r.image(t)[:, :, :3], 0, err_msg=f"{t}, mis={mis}, medium={medium}")
