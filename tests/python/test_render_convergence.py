"""Techniques agree with each other on scenes without a closed form (occlusion, glossy
materials, ellipse lights), the medium's two distance-sampling strategies agree, a thin medium
converges to the medium-free image, and the camera models put things where Blender does.

Comparisons are per-pixel Welch t-tests between independent replicate renders, Sidak-corrected
per image pair with family-wise false-failure rate 1e-4; with the 19 image pairs below a correct
renderer fails this file with probability < 0.2 % (fixed seeds: the outcome is deterministic)."""

import numpy as np
import pytest
from scipy import stats

import sphrect
from chi2 import sidak_alpha
from render_testing import ALL_TECHNIQUES, plane_mesh, replicate_images
from test_render_api import box_mesh

FAMILY_ALPHA = 1e-4


def welch_agree(a, b, family_alpha=FAMILY_ALPHA, rel_tol=1e-4):
    """Per-pixel Welch t-test of two replicate stacks [k, H, W]; True if no pixel rejects."""
    ma, mb = a.mean(0), b.mean(0)
    va, vb = a.var(0, ddof=1) / len(a), b.var(0, ddof=1) / len(b)
    floor = (rel_tol * np.maximum(np.abs(ma), np.abs(mb)) + 1e-7) ** 2
    se2 = va + vb + floor
    t = (ma - mb) / np.sqrt(se2)
    # Welch-Satterthwaite degrees of freedom.
    df = se2 ** 2 / (va ** 2 / (len(a) - 1) + vb ** 2 / (len(b) - 1) + floor ** 2 / 1e9)
    p = 2 * stats.t.sf(np.abs(t), df=np.maximum(df, 1))
    alpha_pixel = sidak_alpha(family_alpha, ma.size)
    return bool(p.min() >= alpha_pixel), float(p.min())


def glossy_scene():
    cam = sphrect.Camera(width=16, height=12, lens=30,
                         to_world=[[1, 0, 0, 0], [0, 0.8, -0.6, -3.5], [0, 0.6, 0.8, 2.8], [0, 0, 0, 1]])
    mats = [sphrect.Material(name="floor", kind="glossy", base_color=(0.5, 0.5, 0.5), roughness=0.45, specular=0.5),
            sphrect.Material(name="gold", kind="glossy", base_color=(0.9, 0.7, 0.3), roughness=0.35, metallic=1.0),
            sphrect.Material(name="matte", base_color=(0.3, 0.6, 0.3))]
    ground = plane_mesh(10)
    ground.material_ids = np.array([0, 0], np.int32)
    box = box_mesh((0.0, 0.0, 0.35), (0.7, 0.7, 0.7))
    box.material_ids = np.array([1] * 6 + [2] * 6, np.int32)
    lights = [sphrect.RectLight(corner=(-1.2, 0.9, 0.05), edge_x=(1.5, 0, 0), edge_y=(0, 0, 1.0), radiance=(3, 3, 3),
                                two_sided=True, visible=False),
              sphrect.EllipseLight(center=(1.0, -0.5, 1.2), axis_x=(0.3, 0, 0), axis_y=(0, 0.2, 0),
                                   radiance=(2, 1.5, 1), two_sided=True)]
    return sphrect.Scene(camera=cam, meshes=[ground, box], lights=lights, materials=mats,
                         world=sphrect.World(background=(0.05, 0.05, 0.08)))


def assert_techniques_and_mis_modes_agree(scene):
    """Every technique under every MIS mode (8 x 32 spp) against rectangle / balance (8 x 64 spp): 18 image pairs."""
    reference = replicate_images(scene, ["rectangle"], 8, 64, mis="balance")["rectangle"]
    assert reference.mean() > 0.01
    for mis in sphrect.mis_modes:
        reps = replicate_images(scene, ALL_TECHNIQUES, 8, 32, mis=mis)
        for t in ALL_TECHNIQUES:
            ok, p = welch_agree(reps[t], reference)
            assert ok, f"{t}/{mis} differs from rectangle/balance: worst p = {p:.3g}"


def test_all_techniques_and_mis_modes_agree_with_occlusion_and_glossy():
    assert_techniques_and_mis_modes_agree(glossy_scene())


def medium_scene(sigma_s, sigma_a, g=0.3, visible=True):
    cam = sphrect.Camera(width=12, height=10, lens=28,
                         to_world=[[1, 0, 0, 0], [0, 0.8, -0.6, -3.5], [0, 0.6, 0.8, 2.5], [0, 0, 0, 1]])
    light = sphrect.RectLight(corner=(-0.4, 0.3, 0.1), edge_x=(0.8, 0, 0), edge_y=(0, 0, 0.8), radiance=(5, 5, 5),
                              two_sided=True, visible=visible)
    spot = sphrect.PointLight(position=(1.0, -1.0, 1.0), intensity=(0.5, 0.5, 0.5))
    world = sphrect.World(background=(0.0, 0.0, 0.0),
                          medium=sphrect.Medium(sigma_s=sigma_s, sigma_a=sigma_a, g=g) if sigma_s else None)
    return sphrect.Scene(camera=cam, meshes=[plane_mesh(6), box_mesh((0.6, -0.3, 0.3), (0.4, 0.4, 0.6))],
                         lights=[light, spot], world=world,
                         materials=[sphrect.Material(base_color=(0.5, 0.5, 0.5))])


def test_medium_distance_and_equiangular_sampling_agree():
    scene = medium_scene((0.25, 0.3, 0.35), (0.05, 0.02, 0.0))
    techniques = ["area", "rectangle"]
    runs = {ms: replicate_images(scene, techniques, 8, 48, medium_sampling=ms, mis="balance")
            for ms in ("distance", "equiangular", "mis")}
    for t in techniques:
        for ms in ("equiangular", "mis"):
            ok, p = welch_agree(runs[ms][t], runs["distance"][t])
            assert ok, f"{t}: {ms} vs distance sampling, worst p = {p:.3g}"
    # Light sampling without MIS must agree too (phase sampling only finds the background).
    plain = replicate_images(scene, ["rectangle"], 8, 48, mis="none")
    ok, p = welch_agree(plain["rectangle"], runs["mis"]["rectangle"])
    assert ok, f"mis=none vs balance in the medium, worst p = {p:.3g}"


def test_thin_medium_converges_to_the_medium_free_image():
    # (The exact coverage of lights seen by the camera is off in a medium: off here too, for the same samples.)
    free = sphrect.Renderer(medium_scene(None, None), seed=5, analytic_light_coverage=False)
    thin = sphrect.Renderer(medium_scene((1e-6,) * 3, (1e-6,) * 3), seed=5)
    assert "medium" in thin.features and "medium" not in free.features
    free.render(16)
    thin.render(16)
    a, b = free.image()[:, :, :3], thin.image()[:, :, :3]
    # Same camera and surface samples: only transmittance (~1 - 2e-6 d) and a ~1e-6 scattering term differ.
    np.testing.assert_allclose(b, a, rtol=1e-4, atol=1e-4 * a.max())


def marker_scene(cam, point, size=0.02):
    """A small visible emitter facing the camera at `point` (camera at the origin looking down -Z)."""
    x, y, z = point
    light = sphrect.RectLight(corner=(x - size / 2, y - size / 2, z), edge_x=(size, 0, 0), edge_y=(0, size, 0),
                              radiance=(1, 1, 1))
    return sphrect.Scene(camera=cam, lights=[light])


def brightest_pixel(scene):
    r = sphrect.Renderer(scene)
    r.render(16)
    img = r.image()[:, :, 0]
    return np.unravel_index(np.argmax(img), img.shape)


def test_perspective_projection_matches_blender():
    """A point placed (by Blender's projection) at the centre of pixel (row 24, col 42) lights that pixel:
    36 mm sensor, 50 mm lens, horizontal fit, shift_x 0.1, +Y up, row 0 at the top."""
    cam = sphrect.Camera(width=80, height=60, lens=50, sensor_width=36, shift_x=0.1)
    row, col, z = 24, 42, 10.0
    u, v = (col + 0.5) / 80, (row + 0.5) / 60        # fractions of the width (from the left) and height (from the top)
    x = (u - 0.5 + 0.1) * z * 36 / 50                # u = 0.5 + x f / (z * sensor) - shift
    y = (0.5 - v) * z * 36 / 50 * 60 / 80             # the height spans sensor * 60 / 80
    pixel = 36 / 50 * z / 80                         # pixel size at depth z
    assert brightest_pixel(marker_scene(cam, (x, y, -z), size=0.3 * pixel)) == (row, col)


def test_orthographic_projection():
    cam = sphrect.Camera(width=40, height=40, type="orthographic", ortho_scale=4.0)
    # Pixel (row 27, col 30) is centred on x = (30.5 / 40 - 0.5) * 4, y = (0.5 - 27.5 / 40) * 4.
    x, y = (30.5 / 40 - 0.5) * 4, (0.5 - 27.5 / 40) * 4
    assert brightest_pixel(marker_scene(cam, (x, y, -3.0), size=0.03)) == (27, 30)


def test_depth_of_field_blurs_out_of_focus_points_only():
    """A 5 cm marker in focus stays within a few pixels; at half the focus distance it spreads over
    many, and the lens still gathers its whole image: the sum over pixels is the marker's image area
    in pixels (times its radiance 1), (0.05 m / pixel size at depth z)^2, within 6 % (observed: 3 %)."""
    def render(z):
        cam = sphrect.Camera(width=40, height=40, lens=50, aperture_radius=0.3, focus_distance=5.0)
        r = sphrect.Renderer(marker_scene(cam, (0, 0, -z), size=0.05))
        assert "dof" in r.features
        r.render(1024)
        img = r.image()[:, :, 0]
        return np.count_nonzero(img > 1e-3 * img.max()), float(img.sum())

    def image_area(z):
        return (0.05 / (36 / 50 * z / 40)) ** 2

    sharp, total_sharp = render(5.0)
    blurred, total_blurred = render(2.5)
    assert sharp <= 4 and blurred > 40
    assert total_sharp == pytest.approx(image_area(5.0), rel=0.06)
    assert total_blurred == pytest.approx(image_area(2.5), rel=0.06)
