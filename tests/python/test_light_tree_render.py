"""The renderer with light_selection="tree": the light tree picks one emitter per light sample among
rectangles and emissive triangles (the point/spot lights, fewer than MAX_DELTA_LIGHTS_BESIDE_TREE, and the sun
stay evaluated once; test_render.cpp's RenderLights tests the tree choosing point lights), and the MIS pdf of an
emitter a BSDF ray finds is the tree's pmf at the shading point.

- unbiased: a Lambertian plane under three rectangles of different power, an emissive triangle, two
  point lights and a spot light (and a sun), every technique x MIS mode, against Lambert's polygon
  formula and I cos / d^2 (render_testing.pixel_t_test);
- the same in a medium (test_render_medium's scene and quadrature);
- MIS: on a glossy plane, MIS balance / power and no MIS have the same expectation (two-sample t-test);
- variance: on 100 small rectangles at unequal distances the tree beats power selection at equal samples.

False-failure rate: every image is one family with family-wise rate FAMILY_ALPHA = 1e-4 (Sidak over its
pixels); 3 x 4 + 2 + 2 = 16 families, so a correct renderer fails this file with probability < 0.16 %
(seeds are fixed: the outcome is deterministic, the rate is that of a seed set drawn at random).  The
variance test compares a ratio measured as 0.03 (tree / power) against 0.5.

Run as a script to print the variance figures: PYTHONPATH=build/python python3 tests/python/test_light_tree_render.py
"""
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
SAMPLES = 8


def rect_verts(light):
    c, ex, ey = (np.asarray(a, np.float64) for a in (light.corner, light.edge_x, light.edge_y))
    return np.array([c, c + ex, c + ex + ey, c + ey])


RECTS = [
    sphrect.RectLight(corner=(-0.2, -0.3, 1.0), edge_x=(0, 1, 0), edge_y=(1, 0, 0), radiance=(1, 1, 1), visible=False),
    sphrect.RectLight(corner=(-0.6, -0.5, 0.6), edge_x=(0, 0.3, 0), edge_y=(0.3, 0, 0), radiance=(4, 4, 4),
                      visible=False),
    # Two-sided, standing on the plane across the image.
    sphrect.RectLight(corner=(0.1, -0.5, 0.05), edge_x=(0, 1, 0), edge_y=(0, 0, 0.4), radiance=(0.5, 0.5, 0.5),
                      two_sided=True, visible=False),
]
# Above every other emitter (a mesh occludes) and behind the camera (at z = 0.5, below the lights).
TRIANGLE = np.array([[-0.6, 0.2, 2.0], [0.7, 0.4, 1.9], [0.1, 0.9, 2.2]])
TRIANGLE_RADIANCE = 3.0
POINTS = [sphrect.PointLight(position=(0.5, 0.2, 1.0), intensity=(0.7, 0.7, 0.7)),
          sphrect.PointLight(position=(-0.8, -0.7, 0.3), intensity=(0.05, 0.05, 0.05))]
SPOT = sphrect.SpotLight(position=(-0.4, 0.1, 1.5), direction=(0, 0, -1), intensity=(2, 2, 2),
                         spot_size=math.radians(60), spot_blend=0.3)
# Low, from +x: the triangle's shadow falls outside the image.
SUN_DIR = np.array([-1.0, 0.0, -0.5]) / np.linalg.norm([-1.0, 0.0, -0.5])
SUN = sphrect.SunLight(direction=tuple(SUN_DIR), irradiance=(0.2, 0.2, 0.2))


def mixed_scene():
    ground = plane_mesh()
    ground.material_ids = np.zeros(2, np.int32)
    emitter = sphrect.Mesh(vertices=TRIANGLE.astype(np.float32), triangles=np.array([[0, 1, 2]], np.int32),
                           name="triangle", material_ids=np.ones(1, np.int32))
    return sphrect.Scene(camera=top_camera(height_above=0.5), meshes=[ground, emitter],
                         lights=RECTS + POINTS + [SPOT, SUN],
                         materials=[sphrect.Material(name="ground", base_color=(ALBEDO,) * 3),
                                    sphrect.Material(name="emitter", base_color=(0, 0, 0),
                                                     emission=(TRIANGLE_RADIANCE,) * 3)])


def point_irradiance(P, position, intensity):
    d = np.asarray(position) - P
    dist = np.linalg.norm(d, axis=-1)
    return intensity * (d[..., 2] / dist) / dist ** 2


def spot_irradiance(P):
    """Cycles 3.4's spot falloff, as tests/python/test_render_analytic.py's delta-light scene."""
    d = np.asarray(SPOT.position) - P
    dist = np.linalg.norm(d, axis=-1)
    cos_axis = d[..., 2] / dist
    cos_half = math.cos(SPOT.spot_size / 2)
    smooth = (1 - cos_half) * SPOT.spot_blend
    t = np.clip((cos_axis - cos_half) / smooth, 0, 1)
    att = np.where(cos_axis > cos_half, cos_axis * np.where(cos_axis - cos_half < smooth, t * t * (3 - 2 * t), 1), 0)
    return SPOT.intensity[0] * att * (d[..., 2] / dist) / dist ** 2


def mixed_irradiance(P):
    e = sum(l.radiance[0] * polygon_irradiance(P, (0, 0, 1), rect_verts(l), two_sided=l.two_sided) for l in RECTS)
    e = e + TRIANGLE_RADIANCE * polygon_irradiance(P, (0, 0, 1), TRIANGLE)
    e = e + sum(point_irradiance(P, p.position, p.intensity[0]) for p in POINTS) + spot_irradiance(P)
    return e + SUN.irradiance[0] * -SUN_DIR[2]


@pytest.mark.parametrize("mis", sphrect.mis_modes)
def test_tree_is_unbiased_on_mixed_emitters(mis):
    scene = mixed_scene()
    expected = expected_plane_image(scene.camera, ALBEDO, mixed_irradiance)
    reps = replicate_images(scene, ALL_TECHNIQUES, REPLICATES, SAMPLES, mis=mis, light_samples=2,
                            light_selection="tree")
    for t in ALL_TECHNIQUES:
        ok, p_min, alpha = pixel_t_test(reps[t], expected, FAMILY_ALPHA, rel_tol=1e-4)
        assert ok, f"tree/{mis}/{t}: worst p = {p_min:.3g} < {alpha:.3g}"


def welch_test(a, b, family_alpha):
    """Per-pixel Welch t-test of two replicate sets' means, Sidak over the pixels."""
    t, p = stats.ttest_ind(a, b, axis=0, equal_var=False)
    p = np.where(np.isfinite(p), p, 1.0)
    alpha = sidak_alpha(family_alpha, p.size)
    return bool(p.min() >= alpha), float(p.min()), alpha


@pytest.mark.parametrize("mis", ["balance", "power"])
def test_tree_mis_agrees_with_light_sampling_alone(mis):
    """A glossy plane (no closed form): the tree's pmf in the MIS weights must leave the expectation of
    light sampling alone (mis="none") unchanged, with the rectangles, the triangle and the delta lights."""
    scene = mixed_scene()
    scene.materials[0] = sphrect.Material(name="ground", kind="glossy", base_color=(ALBEDO,) * 3, roughness=0.3,
                                          specular=0.5)
    none = replicate_images(scene, ["rectangle"], REPLICATES, SAMPLES, mis="none", light_samples=2,
                            light_selection="tree")["rectangle"]
    mixed = []
    for k in range(REPLICATES):  # other seeds than replicate_images' 1000 + k: the two sets are independent
        r = sphrect.Renderer(scene, techniques=["rectangle"], seed=5000 + k, mis=mis, light_samples=2,
                             light_selection="tree")
        r.render(SAMPLES)
        mixed.append(r.image("rectangle")[:, :, 0].astype(np.float64))
    ok, p_min, alpha = welch_test(none, mixed, FAMILY_ALPHA)
    assert ok, f"tree/{mis} vs none: worst p = {p_min:.3g} < {alpha:.3g}"


@pytest.mark.slow
@pytest.mark.parametrize("mis", ["none", "power"])
def test_tree_in_a_medium_matches_quadrature(mis):
    """test_render_medium's rectangle + point light in fog, both chosen by the tree at the scattering point
    (no normal), against its quadrature."""
    from test_render_medium import expected_image, medium_scene
    reps = replicate_images(medium_scene(), ["rectangle"], 16, 1024, mis=mis, light_selection="tree")
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected_image(), FAMILY_ALPHA, rel_tol=1e-3)
    assert ok, f"medium/tree/{mis}: worst p = {p_min:.3g} < {alpha:.3g}"


def many_small_lights_scene(n_side=10):
    """n_side^2 small square lights (0.04 wide, equal radiance) over the camera's view at heights
    0.2 ... 3 (unequal distances), hidden from the camera."""
    rng = np.random.default_rng(11)
    lights = []
    for i in range(n_side):
        for j in range(n_side):
            x, y = -1.2 + 2.4 * (i + 0.5) / n_side, -1.2 + 2.4 * (j + 0.5) / n_side
            lights.append(sphrect.RectLight(corner=(x - 0.02, y - 0.02, float(rng.uniform(0.2, 3.0))),
                                            edge_x=(0, 0.04, 0), edge_y=(0.04, 0, 0), radiance=(50, 50, 50),
                                            visible=False))
    return sphrect.Scene(camera=top_camera(width=16, height=16), meshes=[plane_mesh()], lights=lights,
                         materials=[sphrect.Material(base_color=(ALBEDO,) * 3)])


def pooled_variance(scene, light_selection, replicates=16, samples=16, mis="power"):
    reps = replicate_images(scene, ["rectangle"], replicates, samples, mis=mis, light_samples=1,
                            light_selection=light_selection)["rectangle"]
    return float(reps.var(axis=0, ddof=1).sum()), float(reps.mean())


def test_tree_beats_power_on_many_small_lights():
    scene = many_small_lights_scene()
    v_power, m_power = pooled_variance(scene, "power")
    v_tree, m_tree = pooled_variance(scene, "tree")
    assert abs(m_tree / m_power - 1) < 0.05, (m_tree, m_power)
    assert v_tree < 0.5 * v_power, (v_tree, v_power)


def test_light_selection_names():
    assert sphrect.light_selections == ("power", "tree", "ris")
    with pytest.raises(ValueError, match="light_selection"):
        sphrect.Renderer(mixed_scene(), light_selection="bvh")


if __name__ == "__main__":
    scene = many_small_lights_scene()
    for mis in ("none", "power"):
        v_power, _ = pooled_variance(scene, "power", mis=mis)
        v_tree, _ = pooled_variance(scene, "tree", mis=mis)
        print(f"100 small rectangles, 16 spp, 1 light sample, mis={mis}: pooled variance power {v_power:.4g}, "
              f"tree {v_tree:.4g}, tree / power {v_tree / v_power:.3f}")
