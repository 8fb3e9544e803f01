"""Stratified light selection: the light a light sample goes to is picked by power with the v of the
light sample's pattern point, which is then rescaled for the point on that light
(LightSelector::SelectRemapped, ChooseAreaLight).

1. Unbiased: four rectangles of different power over a Lambertian plane, every pattern x MIS none/power x
   technique, per-pixel t-test (Sidak) against Lambert's polygon formula.
2. The variance of the light choice, exactly: four tiny lights (each light's own sampling noise ~1e-4 of
   the choice's) seen through a tiny pixel footprint (the irradiance is constant over a pixel within
   ~1e-3), powers 1:1:2:4, i.e. pmfs 1/8, 1/8, 1/4, 1/2, 16 camera samples of one light sample each:
   - independent pattern: the choice is independent per sample, as before stratification: the pixel
     variance is the multinomial one, (sum_i I_i^2 / p_i - I^2) / N;
   - stratified (a 4 x 4 jittered grid; v picks the light): lights 2 and 3 get exactly one and two rows
     (4 and 8 samples); the 4 samples of the first row split between lights 0 and 1 as Binomial(4, 1/2),
     so the variance is (8 / N)^2 (I_0 - I_1)^2 (variance_stratified below);
   - latin, hammersley, sobol: v has exactly one point in each 1/16 of [0,1), so every light gets
     exactly N p_i samples and the choice adds no variance at all.

False-failure rate: test 1 checks 5 x 2 x 4 + 1 = 41 images, each a family of pixel tests with family-wise
rate 1e-4 (Sidak): < 0.5 %.  Test 2's ratio bounds are > 6 standard deviations of the pooled variance
estimate (1,008 degrees of freedom) away from the expected ratio: < 1e-6 each.  Seeds are fixed, so
the outcome is deterministic."""
import numpy as np
import pytest

import sphrect
from render_testing import (ALL_TECHNIQUES, expected_plane_image, pixel_t_test, plane_mesh, polygon_irradiance,
                            replicate_images, top_camera)

FAMILY_ALPHA = 1e-4
ALBEDO = 0.5
PATTERNS = list(sphrect.patterns)


def rect_verts(light):
    c, ex, ey = (np.asarray(a, np.float64) for a in (light.corner, light.edge_x, light.edge_y))
    return np.array([c, c + ex, c + ex + ey, c + ey])


def facing_down(center, size, radiance):
    """A one-sided square light of side `size` centred at `center`, emitting downwards (cross(ex, ey) = -z)."""
    c = np.asarray(center, np.float64) - np.array([size / 2, size / 2, 0])
    return sphrect.RectLight(corner=tuple(c), edge_x=(0, size, 0), edge_y=(size, 0, 0), radiance=(radiance,) * 3,
                             visible=False)


def plane_scene(lights, camera):
    return sphrect.Scene(camera=camera, meshes=[plane_mesh()], lights=list(lights),
                         materials=[sphrect.Material(base_color=(ALBEDO,) * 3)])


def light_images(lights, camera, order=16):
    """[light, H, W]: each light's pixel-averaged radiance albedo / pi * L * E on the plane."""
    return np.array([expected_plane_image(camera, ALBEDO, lambda P, l=l: l.radiance[0] * polygon_irradiance(
        P, (0, 0, 1), rect_verts(l), two_sided=False), order) for l in lights])


# Four rectangles of powers 1 : 2 : 3 : 6 (radiance x area) at different heights over the image.
FOUR_LIGHTS = [facing_down((-0.6, -0.5, 0.6), 0.3, 10.0), facing_down((0.5, 0.4, 1.0), 0.6, 5.0),
               facing_down((0.3, -0.6, 0.5), 0.2, 67.5), facing_down((-0.4, 0.7, 1.5), 1.0, 5.4)]


@pytest.mark.slow
@pytest.mark.parametrize("pattern", PATTERNS)
@pytest.mark.parametrize("mis", ["none", "power"])
def test_stratified_choice_is_unbiased(pattern, mis):
    scene = plane_scene(FOUR_LIGHTS, top_camera())
    expected = light_images(FOUR_LIGHTS, scene.camera).sum(axis=0)
    reps = replicate_images(scene, ALL_TECHNIQUES, 24, 16, mis=mis, pattern=pattern, light_samples=1)
    for t in ALL_TECHNIQUES:
        ok, p_min, alpha = pixel_t_test(reps[t], expected, FAMILY_ALPHA)
        assert ok, f"{pattern}/{mis}/{t}: worst p = {p_min:.3g} < {alpha:.3g}"


def test_stratified_choice_with_several_light_samples_is_unbiased():
    """light_samples = 3 over 16 camera samples: 48 light points per pixel, the choice stratified over all."""
    scene = plane_scene(FOUR_LIGHTS, top_camera())
    expected = light_images(FOUR_LIGHTS, scene.camera).sum(axis=0)
    reps = replicate_images(scene, ["rectangle"], 24, 16, mis="balance", pattern="stratified", light_samples=3)
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, FAMILY_ALPHA)
    assert ok, f"worst p = {p_min:.3g} < {alpha:.3g}"


# Tiny (1 cm) lights at different distances and directions, powers 1 : 1 : 2 : 4 (equal areas), so the
# pmfs are 1/8, 1/8, 1/4, 1/2 and the CDF's intervals [0, 1/8), [1/8, 1/4), [1/4, 1/2), [1/2, 1).
TINY = 0.01
TINY_LIGHTS = [facing_down((0.3, 0.0, 1.0), TINY, 1e4), facing_down((-1.0, 0.5, 0.8), TINY, 1e4),
               facing_down((0.0, -2.0, 1.5), TINY, 2e4), facing_down((1.5, 1.5, 0.5), TINY, 4e4)]
PMF = np.array([1, 1, 2, 4]) / 8
N = 16          # camera samples per pixel, one light sample each
REPLICATES = 64


def variance_independent(I):
    """Per-pixel variance of the mean of N samples, each L_i E_i / p_i for light i drawn with probability p_i."""
    total = I.sum(axis=0)
    return (np.einsum("i,ihw->hw", 1 / PMF, I ** 2) - total ** 2) / N


def variance_stratified(I):
    """A 4 x 4 jittered grid: v in row r lies in [r/4, (r+1)/4), uniform and independent per sample.  Rows 1
    and 2-3 are exactly lights 2 and 3; row 0's 4 samples go to light 0 (v < 1/8) or 1, n_0 ~ Binomial(4, 1/2).
    The pixel value is sum_i n_i I_i / (N p_i) = (8 / N) (n_0 I_0 + (4 - n_0) I_1) + constant, so its variance
    is (8 / N)^2 (I_0 - I_1)^2 Var(n_0), Var(n_0) = 4 * 1/2 * 1/2 = 1."""
    return (8 / N) ** 2 * (I[0] - I[1]) ** 2


def pooled_ratio(reps, expected_var):
    """sum over pixels of the replicates' sample variance / sum of the expected one."""
    return float(reps.var(axis=0, ddof=1).sum() / expected_var.sum())


def test_variance_of_the_light_choice():
    camera = top_camera(width=4, height=4, half=0.005)  # 2.5 mm pixels
    scene = plane_scene(TINY_LIGHTS, camera)
    I = light_images(TINY_LIGHTS, camera, order=4)
    v_ind = variance_independent(I)
    # light_selection="power": the predicted variances are those of the power pmfs PMF.
    reps = {p: replicate_images(scene, ["rectangle"], REPLICATES, N, mis="none", pattern=p,
                                 light_samples=1, light_selection="power")["rectangle"]
            for p in PATTERNS}
    results = {p: pooled_ratio(r, v_ind) for p, r in reps.items()}
    # Independent: nothing changes, the multinomial variance (ratio 1; 16 x 63 degrees of freedom: the
    # ratio's standard deviation is ~0.045 for normal pixel means, ~0.06 allowing for their kurtosis).
    assert 0.6 < results["independent"] < 1.4, results
    # Stratified: only the first row's binomial split, a known fraction of the independent variance.
    strat = pooled_ratio(reps["stratified"], variance_stratified(I))
    expected_fraction = variance_stratified(I).sum() / v_ind.sum()
    assert 0.6 < strat < 1.4, (strat, expected_fraction, results)
    # Exact counts: what remains is the lights' own sampling and the pixel jitter, < 1e-3 of the choice's.
    for pattern in ("latin", "hammersley", "sobol"):
        assert results[pattern] < 1e-3, results
