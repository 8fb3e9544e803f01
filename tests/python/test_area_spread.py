"""Area light Spread as Cycles 3.4 evaluates it (docs/renderer.md, "Area light spread"): emission attenuated by
max((1 - cot(h) tan(alpha)) N, 0) for light leaving at alpha to the normal (h: half the spread, at least half a
degree; cot(h) and N as Cycles computes them, sphrect._native.area_spread_factors), each shading point sampling
the sub-rectangle it receives light from.

Closed forms on a Lambertian plane under a horizontal light facing it at height d: where the disc of radius
d tan(h) around a point's foot lies on the light, E = pi L N (1 - h' cot(h)) (h' = atan(1 / cot(h)): the
integral of cos(alpha) (1 - cot(h) tan(alpha)) over the cone), whatever d; with the foot on the light's edge,
half of it, on its corner, a quarter (the attenuation is symmetric about the foot).

Under a disc whose rim cuts the cone, the reference integrates the radial closed form over the angle.

False-failure rate: each t-tested image is one family of pixel tests at family-wise rate 1e-4 (Sidak), and the
constant images' means are t-tested once more at 1e-4 (the power: ~0.5 %); there are 2 x (2 scenes x 5 techniques
x 2 MIS settings + 2 discs x 2 ellipse techniques x 2 MIS) + 4 corner/edge x 5 + 4 rim = 80 tests, and 15 image
pairs (Welch, 1e-4 each) on a glossy scene, 5 in a medium and 1 of light selections, so a correct renderer fails
this file with probability < 1.1 % (seeds are fixed: the outcome is deterministic).
test_the_tests_detect_a_1_percent_error shows their power."""
import dataclasses
import math

import numpy as np
import pytest
from scipy import stats

import sphrect
from render_testing import (ALL_TECHNIQUES, pixel_t_test, plane_mesh, replicate_images, save_as_older_version,
                            top_camera)
from sphrect import _native
from test_render_convergence import assert_techniques_and_mis_modes_agree, glossy_scene, welch_agree

FAMILY_ALPHA = 1e-4
ALBEDO = 0.5
REPLICATES = 16
SAMPLES = 32


def pooled_t_test(reps, value, alpha=FAMILY_ALPHA):
    """Two-sided t-test of the replicates' image means (independent) against a constant image's `value`:
    (passed, p, relative error of the mean)."""
    means = reps.reshape(reps.shape[0], -1).mean(axis=1)
    p = stats.ttest_1samp(means, value).pvalue
    return bool(p >= alpha), float(p), float(means.mean() / value - 1)


def full_cone_radiance(spread, radiance=1.0):
    """Lambertian radiance albedo E / pi under a spread light covering the whole cone of every point."""
    cot, norm = _native.area_spread_factors(spread)
    if cot == 0:
        return ALBEDO * radiance
    return ALBEDO * radiance * norm * (1 - math.atan(1 / cot) * cot)


def facing_rect(x0, y0, x1, y1, z, spread, radiance=1.0, **kw):
    """A one-sided rectangle [x0, x1] x [y0, y1] at height z facing down (cross(edge_x, edge_y) = -z)."""
    return sphrect.RectLight(corner=(x0, y0, z), edge_x=(0, y1 - y0, 0), edge_y=(x1 - x0, 0, 0),
                             radiance=(radiance,) * 3, visible=False, spread=spread, **kw)


def plane_scene(light, camera=None):
    return sphrect.Scene(camera=camera or top_camera(), meshes=[plane_mesh()], lights=[light],
                         materials=[sphrect.Material(base_color=(ALBEDO,) * 3)])


def test_spread_factors_are_cycles_3_4s():
    """180 degrees is no spread; below 1 degree Cycles clamps to 1; the normalisation is 1 / (1 - h / tan h)
    up to Cycles' float cancellation, which it keeps (1.245 times at 1 degree)."""
    assert _native.area_spread_factors(math.pi) == (0.0, 1.0)
    assert _native.area_spread_factors(0.0) == _native.area_spread_factors(_native.MIN_AREA_SPREAD)
    for deg in (10, 30, 90, 179):
        h = math.radians(deg) / 2
        cot, norm = _native.area_spread_factors(math.radians(deg))
        assert cot == pytest.approx(1 / math.tan(h), rel=1e-5)
        assert norm == pytest.approx(1 / (1 - h / math.tan(h)), rel=3e-4)
    h = math.radians(1) / 2
    assert _native.area_spread_factors(math.radians(1))[1] * (1 - h / math.tan(h)) == pytest.approx(1.245, abs=2e-3)


def test_spread_pi_is_the_light_without_spread():
    """Spread = 180 degrees renders bit for bit as a light without it, and is no scene feature."""
    light = facing_rect(-0.3, -0.4, 0.6, 0.5, 1.0, math.pi)
    plain = sphrect.RectLight(corner=light.corner, edge_x=light.edge_x, edge_y=light.edge_y,
                              radiance=light.radiance, visible=False)  # the default spread
    a = sphrect.Renderer(plane_scene(light), techniques=ALL_TECHNIQUES, seed=3, mis="balance")
    b = sphrect.Renderer(plane_scene(plain), techniques=ALL_TECHNIQUES, seed=3, mis="balance")
    a.render(4)
    b.render(4)
    assert "area_spread" not in a.features
    for t in ALL_TECHNIQUES:
        np.testing.assert_array_equal(a.image(t), b.image(t))
    c = sphrect.Renderer(plane_scene(facing_rect(-0.3, -0.4, 0.6, 0.5, 1.0, math.radians(170))), seed=3)
    assert "area_spread" in c.features


@pytest.mark.parametrize("spread", [-0.1, math.pi + 1e-3, float("nan")])
def test_spread_is_validated(spread):
    with pytest.raises(ValueError, match="spread"):
        sphrect.Renderer(plane_scene(facing_rect(-1, -1, 1, 1, 1.0, spread)))


# name -> (light, expected radiance).  "spread30": a 10 x 10 light at height 1, spread 30 degrees (cone radius
# 0.27); "spread1_near": spread 1 degree 1e-3 above the plane, each point lit by a 1.7e-5 wide patch.
FULL_CONE_SCENES = {
    "spread30": (facing_rect(-5, -5, 5, 5, 1.0, math.radians(30)), full_cone_radiance(math.radians(30))),
    "spread1_near": (facing_rect(-5, -5, 5, 5, 1e-3, math.radians(1)), full_cone_radiance(math.radians(1))),
}


@pytest.mark.parametrize("mis, bsdf_on_diffuse", [("none", False), ("balance", True)])
@pytest.mark.parametrize("name", list(FULL_CONE_SCENES))
def test_full_cone_is_exact_for_every_technique(name, mis, bsdf_on_diffuse):
    """Every technique samples the clipped sub-rectangle; with MIS and BSDF samples on the diffuse plane the
    BSDF rays that hit the light weigh themselves with that sub-rectangle's pdf."""
    light, value = FULL_CONE_SCENES[name]
    scene = plane_scene(light)
    expected = np.full((scene.camera.height, scene.camera.width), value)
    reps = replicate_images(scene, ALL_TECHNIQUES, REPLICATES, SAMPLES, mis=mis,
                            bsdf_samples_on_diffuse=bsdf_on_diffuse)
    for t in ALL_TECHNIQUES:
        ok, p_min, alpha = pixel_t_test(reps[t], expected, FAMILY_ALPHA)
        rel = np.abs(reps[t].mean(0) / value - 1).max()
        assert ok, f"{name}/{mis}/{t}: worst p = {p_min:.3g} < {alpha:.3g} (max rel. error {rel:.3g})"
        ok, p, rel = pooled_t_test(reps[t], value)
        assert ok, f"{name}/{mis}/{t}: image mean off by {rel:.3g} (p = {p:.3g})"


def test_the_tests_detect_a_1_percent_error():
    light, value = FULL_CONE_SCENES["spread1_near"]
    reps = replicate_images(plane_scene(light), ["rectangle"], REPLICATES, SAMPLES)
    assert pooled_t_test(reps["rectangle"], value)[0]
    assert not pooled_t_test(reps["rectangle"], 1.01 * value)[0]
    assert not pooled_t_test(reps["rectangle"], 0.99 * value)[0]


@pytest.mark.parametrize("degrees, height, half", [(30, 1.0, 1e-4), (1, 1e-3, 1e-8)])
@pytest.mark.parametrize("where, fraction", [("corner", 0.25), ("edge", 0.5)])
def test_foot_on_the_lights_edge_or_corner_gets_its_share(where, fraction, degrees, height, half):
    """One tiny pixel centred where the light's corner (edge) lies above: a quarter (half) of the full cone, up
    to the pixel's second-order variation (half / cone radius)^2: (1e-4 / 0.27)^2, and 1e-3 above a light of 1
    degree (cone radius 8.7e-6, the clip cut to a 8.7e-6 wide strip or square) (1e-8 / 8.7e-6)^2."""
    spread = math.radians(degrees)
    light = facing_rect(0.0, 0.0 if where == "corner" else -5.0, 5.0, 5.0, height, spread)
    scene = plane_scene(light, top_camera(width=1, height=1, half=half))
    expected = np.full((1, 1), fraction * full_cone_radiance(spread))
    reps = replicate_images(scene, ALL_TECHNIQUES, REPLICATES, 4 * SAMPLES)
    for t in ALL_TECHNIQUES:
        ok, p_min, alpha = pixel_t_test(reps[t], expected, FAMILY_ALPHA)
        assert ok, f"{where}/{t}: mean {reps[t].mean():.6g}, expected {expected[0, 0]:.6g}, p = {p_min:.3g}"


def ellipse_sampling_cases():
    return [(t, m) for t in sphrect.ellipse_techniques for m in ("none", "balance")]


@pytest.mark.parametrize("degrees, height", [(60, 1.0), (1, 1e-3)])
@pytest.mark.parametrize("ellipse_technique, mis", ellipse_sampling_cases())
def test_ellipse_full_cone_is_exact(ellipse_technique, mis, degrees, height):
    """An ellipse with spread is sampled on the clip of its bounding rectangle (by area, or by the rectangle
    map under spherical_ellipse), here wholly on the disc."""
    spread = math.radians(degrees)
    light = sphrect.EllipseLight(center=(0, 0, height), axis_x=(0, 5, 0), axis_y=(5, 0, 0), radiance=(1,) * 3,
                                 visible=False, spread=spread)
    scene = plane_scene(light)
    expected = np.full((scene.camera.height, scene.camera.width), full_cone_radiance(spread))
    reps = replicate_images(scene, ["rectangle"], REPLICATES, 4 * SAMPLES, mis=mis,
                            ellipse_technique=ellipse_technique, bsdf_samples_on_diffuse=mis != "none")
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, FAMILY_ALPHA)
    assert ok, f"{ellipse_technique}/{mis}: worst p = {p_min:.3g} < {alpha:.3g}"
    ok, p, rel = pooled_t_test(reps["rectangle"], expected[0, 0])
    assert ok, f"{ellipse_technique}/{mis}: image mean off by {rel:.3g} (p = {p:.3g})"


def disc_spread_radiance(foot, disc_radius, height, spread, radiance=1.0, n=200_000):
    """Lambertian radiance at the plane point `foot` (its distance from the axis of a disc facing down at
    `height`) under the disc with spread: albedo / pi * L N * the integral over phi of F(min(rho(phi), R)), rho the
    distance from the foot to the rim along phi, R = height / cot(h) the cone's radius, F the closed-form radial
    integral of cos^2 (1 - cot(h) tan) / dist^2 (midpoint rule in phi)."""
    cot, norm = _native.area_spread_factors(spread)
    d, R = height, height / cot
    phi = (np.arange(n) + 0.5) * (2 * np.pi / n)
    rho = -foot * np.cos(phi) + np.sqrt(disc_radius ** 2 - (foot * np.sin(phi)) ** 2)
    r = np.minimum(rho, R)
    F = r * r / (2 * (d * d + r * r)) - cot * (np.arctan(r / d) / 2 - d * r / (2 * (d * d + r * r)))
    return ALBEDO / np.pi * radiance * norm * F.mean() * 2 * np.pi


def test_disc_reference_gives_the_full_cone():
    spread = math.radians(30)
    assert disc_spread_radiance(0.0, 5.0, 1.0, spread) == pytest.approx(full_cone_radiance(spread), rel=1e-9)


@pytest.mark.parametrize("ellipse_technique, mis", ellipse_sampling_cases())
def test_disc_rim_cutting_the_cone(ellipse_technique, mis):
    """A point whose cone (radius 0.27) the rim of a unit disc cuts: samples of the clip off the disc are dropped,
    BSDF rays take the clip's pdf."""
    spread = math.radians(30)
    light = sphrect.EllipseLight(center=(0, 0, 1.0), axis_x=(0, 1, 0), axis_y=(1, 0, 0), radiance=(1,) * 3,
                                 visible=False, spread=spread)
    cam = sphrect.Camera(width=1, height=1, type="orthographic", ortho_scale=2e-4,
                         to_world=[[1, 0, 0, 0.97], [0, 1, 0, 0], [0, 0, 1, 5], [0, 0, 0, 1]])
    expected = np.full((1, 1), disc_spread_radiance(0.97, 1.0, 1.0, spread))
    assert 0.3 * full_cone_radiance(spread) < expected[0, 0] < 0.8 * full_cone_radiance(spread)
    reps = replicate_images(plane_scene(light, cam), ["rectangle"], REPLICATES, 4 * SAMPLES, mis=mis,
                            ellipse_technique=ellipse_technique, bsdf_samples_on_diffuse=mis != "none")
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, FAMILY_ALPHA)
    assert ok, f"{ellipse_technique}/{mis}: mean {reps['rectangle'].mean():.6g}, expected {expected[0, 0]:.6g}"


@pytest.mark.parametrize("shape", ["rect", "ellipse"])
@pytest.mark.parametrize("view_deg", [0, 20, 35])
def test_camera_sees_the_attenuated_light(shape, view_deg):
    """An orthographic camera looking at a large light facing it, at view_deg from its normal: every pixel sees
    L N (1 - cot(h) tan(alpha)), 0 past the half spread (30 degrees)."""
    spread = math.radians(60)
    a = math.radians(view_deg)
    Z = np.array([0, math.sin(a), math.cos(a)])  # camera +Z: towards the camera from the scene
    Y = np.array([0, math.cos(a), -math.sin(a)])
    pos = 5 * Z
    cam = sphrect.Camera(width=4, height=4, type="orthographic", ortho_scale=0.5,
                         to_world=[[1, Y[0], Z[0], pos[0]], [0, Y[1], Z[1], pos[1]], [0, Y[2], Z[2], pos[2]],
                                   [0, 0, 0, 1]])
    if shape == "rect":
        light = sphrect.RectLight(corner=(-5, -5, 0), edge_x=(10, 0, 0), edge_y=(0, 10, 0), radiance=(2,) * 3,
                                  spread=spread)
    else:
        light = sphrect.EllipseLight(center=(0, 0, 0), axis_x=(5, 0, 0), axis_y=(0, 5, 0), radiance=(2,) * 3,
                                     spread=spread)
    cot, norm = _native.area_spread_factors(spread)
    expected = 2 * max((1 - cot * math.tan(a)) * norm, 0)
    img = sphrect.Renderer(sphrect.Scene(camera=cam, lights=[light]), techniques=["rectangle"], seed=1)
    img.render(4)
    np.testing.assert_allclose(img.image("rectangle")[:, :, :3], expected, rtol=1e-4, atol=1e-6)


def test_spread_is_saved_and_older_files_load_without_it(tmp_path):
    light = facing_rect(-1, -1, 1, 1, 1.0, 0.5)
    disc = sphrect.EllipseLight(center=(0, 0, 1), axis_x=(1, 0, 0), axis_y=(0, -1, 0), radiance=(1,) * 3,
                                spread=0.25)
    path = str(tmp_path / "s.sphrect.npz")
    sphrect.save_scene(sphrect.Scene(lights=[light, disc], meshes=[plane_mesh()]), path)
    assert [l.spread for l in sphrect.load_scene(path).lights] == [0.5, 0.25]
    old = str(tmp_path / "v10.sphrect.npz")
    save_as_older_version(path, old, 10, lambda meta: [l.pop("spread") for l in meta["lights"]])
    assert [l.spread for l in sphrect.load_scene(old).lights] == [math.pi, math.pi]


def with_spread(scene, degrees):
    """The scene with each rectangle and ellipse light given a spread (degrees, in turn)."""
    lights = [dataclasses.replace(l, spread=math.radians(d)) for l, d in zip(scene.lights, degrees)]
    return dataclasses.replace(scene, lights=lights)


def test_techniques_and_mis_modes_agree_with_spread_on_glossy_surfaces():
    """Occlusion, glossy floor and box, a two-sided rectangle of spread 40 degrees and a camera-visible ellipse
    of 70: BSDF rays that hit the lights weigh themselves with the clipped sub-rectangle's pdf, whichever
    technique, so every technique and MIS mode converges to the same image.  (The closed forms above are the
    sharper check: with the whole light's pdf for the BSDF rays' weights, the spread30 / balance and the corner
    and edge tests fail, this one does not.)"""
    assert_techniques_and_mis_modes_agree(with_spread(glossy_scene(), (40, 70)))


def test_techniques_agree_with_spread_in_a_medium():
    """Scattering points in fog (no normal) sample the sub-rectangle too."""
    light = facing_rect(-0.6, -0.6, 0.6, 0.6, 1.0, math.radians(50), radiance=4.0)
    scene = plane_scene(light, top_camera(width=8, height=8))
    scene.world = sphrect.World(medium=sphrect.Medium(sigma_s=(0.3,) * 3, sigma_a=(0.05,) * 3, g=0.2))
    reference = replicate_images(scene, ["rectangle"], 8, 64, mis="balance")["rectangle"]
    reps = replicate_images(scene, ALL_TECHNIQUES, 8, 32, mis="power")
    for t in ALL_TECHNIQUES:
        ok, p = welch_agree(reps[t], reference)
        assert ok, f"{t}/power differs from rectangle/balance in fog: worst p = {p:.3g}"


def test_light_tree_with_spread_agrees_with_selection_by_power():
    """The tree bounds a light with spread as one without (its cone to pi/2, L A: conservative; narrowing the cone
    to the half spread with the intensity N L A starves the other lights at the spots' rims, where the tree's
    estimate ignores the attenuation's fall to 0: heavy tails this test rejects), so both selections agree."""
    lights = [facing_rect(-0.8, -0.8, -0.4, -0.4, 2.0, math.radians(10), radiance=20.0),
              facing_rect(0.2, -0.6, 0.5, -0.1, 1.0, math.radians(40), radiance=5.0),
              sphrect.EllipseLight(center=(0.3, 0.5, 1.5), axis_x=(0, 0.2, 0), axis_y=(0.2, 0, 0), radiance=(10,) * 3,
                                   visible=False, spread=math.radians(25)),
              facing_rect(-0.9, 0.3, -0.5, 0.9, 1.2, math.pi)]
    scene = sphrect.Scene(camera=top_camera(), meshes=[plane_mesh()], lights=lights,
                          materials=[sphrect.Material(base_color=(ALBEDO,) * 3)])
    tree, power = (replicate_images(scene, ["rectangle"], 8, 32, light_selection=s)["rectangle"]
                   for s in ("tree", "power"))
    assert tree.mean() > 0.01
    ok, p = welch_agree(tree, power)
    assert ok, f"tree and power selection differ: worst p = {p:.3g}"
