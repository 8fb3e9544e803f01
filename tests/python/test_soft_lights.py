"""Soft point, spot and sun lights (a radius, an angle) as Cycles 3.4 evaluates them, sampled by the solid
angle of the cone each subtends (render/delta_light.h), on a Lambertian plane:

- a soft point light (a disc of radius r facing the shading point, radiance I / (pi r^2)): wherever its cone is
  above the horizon, E = I cos(theta_axis) / (d^2 + r^2);
- a sun of angle 2 alpha (radiance E_sun / (pi tan^2 alpha cos^3 theta) in the cone): for a plane whose horizon
  leaves the cone whole, E = E_sun cos(theta_n) (2 / tan^2 alpha) (1 / cos alpha - 1);
- a soft spot light (its falloff taken towards the point, no closed form): the renders with and without MIS,
  with each light selection, agree;
- camera rays see a visible soft point light's disc at its radiance; a file keeps radius and angle, and an older
  one loads them as 0.

False-failure rate: each image is one family of pixel tests with family-wise rate 1e-4 (Sidak); there are
4 + 2 + 2 + 1 = 9 image tests (point: two MIS modes x two selections; sun: two MIS modes; spot: two
selections against the image without MIS; fog), so a correct renderer fails this file with probability
< 0.1 % (fixed seeds: the outcome is deterministic).  The other tests are exact."""
import math

import numpy as np
import pytest
from scipy import stats

import sphrect
from chi2 import sidak_alpha
from render_testing import (expected_plane_image, pixel_t_test, plane_mesh, replicate_images, save_as_older_version,
                            top_camera)

FAMILY_ALPHA = 1e-4
ALBEDO = 0.5
REPLICATES = 24


def plane_scene(*lights):
    return sphrect.Scene(camera=top_camera(), meshes=[plane_mesh()], lights=list(lights),
                         materials=[sphrect.Material(base_color=(ALBEDO,) * 3)])


@pytest.mark.parametrize("light_selection", ["power", "tree"])
@pytest.mark.parametrize("mis", ["none", "balance"])
def test_soft_point_light_on_plane(mis, light_selection):
    point = sphrect.PointLight(position=(0.3, -0.2, 1.0), intensity=(0.7, 0.7, 0.7), radius=0.25, visible=False)
    scene = plane_scene(point)

    def irradiance(P):
        d = np.asarray(point.position) - P
        d2 = (d ** 2).sum(axis=-1)
        return 0.7 * (d[..., 2] / np.sqrt(d2)) / (d2 + point.radius ** 2)

    expected = expected_plane_image(scene.camera, ALBEDO, irradiance)
    reps = replicate_images(scene, ["rectangle"], REPLICATES, 8, mis=mis, light_selection=light_selection,
                            bsdf_samples_on_diffuse=True)
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, FAMILY_ALPHA, rel_tol=1e-4)
    assert ok, f"soft point {mis}/{light_selection}: worst p = {p_min:.3g} < {alpha:.3g}"


@pytest.mark.parametrize("mis", ["none", "balance"])
def test_sun_cone_on_plane(mis):
    """A 57 degree sun 34 degrees from the zenith: the plane's horizon leaves its cone whole.  (Wide, so that
    BSDF rays find it often: with a narrow sun a pixel whose replicates all miss it looks ~1 % dark to the
    t-test, its MIS share of the light; the narrow suns are test_cone.cpp's.)"""
    sun_dir = np.array([math.sin(0.6), 0.0, -math.cos(0.6)])
    angle = 1.0
    sun = sphrect.SunLight(direction=tuple(sun_dir), irradiance=(0.9, 0.9, 0.9), angle=angle, visible=False)
    scene = plane_scene(sun)
    alpha = angle / 2
    e = 0.9 * math.cos(0.6) * 2 / math.tan(alpha) ** 2 * (1 / math.cos(alpha) - 1)
    expected = expected_plane_image(scene.camera, ALBEDO, lambda P: np.full(P.shape[:-1], e))
    reps = replicate_images(scene, ["rectangle"], REPLICATES, 8, mis=mis, bsdf_samples_on_diffuse=True)
    ok, p_min, alpha_pixel = pixel_t_test(reps["rectangle"], expected, FAMILY_ALPHA, rel_tol=1e-4)
    assert ok, f"sun cone {mis}: worst p = {p_min:.3g} < {alpha_pixel:.3g}"


@pytest.mark.parametrize("light_selection", ["power", "tree"])
def test_soft_spot_light_with_mis_matches_without(light_selection):
    """Light sampling alone and MIS with BSDF rays that find the disc estimate the same image (Welch t-test per
    pixel): the pdf the BSDF rays' weights take is the light sample's."""
    spot = sphrect.SpotLight(position=(-0.2, 0.1, 0.6), direction=(0.2, 0, -1), intensity=(2, 2, 2),
                             spot_size=math.radians(70), spot_blend=0.4, radius=0.4, visible=False)
    scene = plane_scene(spot, sphrect.PointLight(position=(0.5, 0.5, 0.3), intensity=(0.2,) * 3, radius=0.1))
    a = replicate_images(scene, ["rectangle"], REPLICATES, 8, mis="none", light_selection=light_selection)
    b = replicate_images(scene, ["rectangle"], REPLICATES, 8, mis="power", light_selection=light_selection,
                         bsdf_samples_on_diffuse=True)
    a, b = a["rectangle"], b["rectangle"]
    assert a.mean() > 1e-3
    p = stats.ttest_ind(a, b, axis=0, equal_var=False).pvalue
    p = np.where(np.isnan(p), 1.0, p)  # pixels that no light reaches: both black
    assert p.min() >= sidak_alpha(FAMILY_ALPHA, p.size), p.min()


def test_soft_lights_in_a_medium_with_mis_match_without():
    """In fog, light samples of a soft point light and a sun weighted against phase rays that find them (MIS)
    estimate what light samples alone do (Welch t-test per pixel)."""
    scene = plane_scene(sphrect.PointLight(position=(0.2, 0.1, 0.8), intensity=(0.7,) * 3, radius=0.3),
                        sphrect.SunLight(direction=(0.3, 0, -1), irradiance=(0.5,) * 3, angle=0.8))
    scene.world = sphrect.World(medium=sphrect.Medium(sigma_s=(0.3,) * 3, g=0.3))
    a = replicate_images(scene, ["rectangle"], REPLICATES, 8, mis="none")["rectangle"]
    b = replicate_images(scene, ["rectangle"], REPLICATES, 8, mis="balance")["rectangle"]
    p = stats.ttest_ind(a, b, axis=0, equal_var=False).pvalue
    assert p.min() >= sidak_alpha(FAMILY_ALPHA, p.size), p.min()


def test_camera_sees_a_visible_soft_point_light():
    """The pixel under the disc's centre sees its radiance I / (pi r^2) on top of the lit plane (light objects
    do not occlude); hidden, only the plane."""
    centre = (1 / 12, 1 / 12, 1.0)  # a pixel centre of the 12 x 12 top camera

    def render(visible):
        light = sphrect.PointLight(position=centre, intensity=(0.7, 0.7, 0.7), radius=0.25, visible=visible)
        r = sphrect.Renderer(plane_scene(light), techniques=["rectangle"], seed=3)
        assert r.render(4)
        return r.image("rectangle")[:, :, 0].astype(np.float64)

    diff = render(True) - render(False)
    radiance = 0.7 / (math.pi * 0.25 ** 2)
    assert diff[5, 6] == pytest.approx(radiance, rel=1e-5)
    assert diff[0, 0] == 0 and diff.min() >= -1e-6


def test_files_keep_radius_and_angle_and_older_ones_load_delta_lights(tmp_path):
    scene = plane_scene(sphrect.PointLight(position=(0, 0, 1), intensity=(1, 1, 1), radius=0.25),
                        sphrect.SpotLight(position=(0, 0, 1), direction=(0, 0, -1), intensity=(1, 1, 1), radius=0.1,
                                          visible=False),
                        sphrect.SunLight(direction=(0, 0, -1), irradiance=(1, 1, 1), angle=0.2))
    path = str(tmp_path / "soft.sphrect.npz")
    sphrect.save_scene(scene, path)
    loaded = sphrect.load_scene(path)
    assert [getattr(light, "radius", getattr(light, "angle", None)) for light in loaded.lights] == [0.25, 0.1, 0.2]
    assert [light.visible for light in loaded.lights] == [True, False, True]
    # A version-9 file (before soft lights) has no radius, angle or visible: delta lights.

    def drop_soft_fields(meta):
        for light in meta["lights"]:
            for key in ("radius", "angle", "visible"):
                light.pop(key, None)

    old = str(tmp_path / "v9.sphrect.npz")
    save_as_older_version(path, old, 9, drop_soft_fields)
    loaded = sphrect.load_scene(old)
    assert [getattr(light, "radius", getattr(light, "angle", None)) for light in loaded.lights] == [0, 0, 0]


@pytest.mark.parametrize("light, message", [
    (sphrect.PointLight(position=(0, 0, 1), intensity=(1, 1, 1), radius=-0.1), "radius"),
    (sphrect.PointLight(position=(0, 0, 1), intensity=(1, 1, 1), radius=float("nan")), "radius"),
    (sphrect.SpotLight(position=(0, 0, 1), direction=(0, 0, -1), intensity=(1, 1, 1), radius=float("inf")), "radius"),
    (sphrect.PointLight(position=(0, 0, 1), intensity=(1, 1, 1), radius=1e-30), "radius"),
    (sphrect.SunLight(direction=(0, 0, -1), irradiance=(1, 1, 1), angle=3.2), "angle"),
    (sphrect.SunLight(direction=(0, 0, -1), irradiance=(1, 1, 1), angle=-0.1), "angle"),
])
def test_bad_radius_or_angle_is_refused(light, message):
    with pytest.raises(ValueError, match=message):
        sphrect.render(plane_scene(light), samples=1)


def test_a_180_degree_sun_and_a_tiny_radius_render_finite():
    """A 180 degree sun sends nothing (Cycles: radius tan(pi / 2)); a radius of 1e-6 is the point light."""
    sun = sphrect.SunLight(direction=(0, 0, -1), irradiance=(1, 1, 1), angle=math.pi)
    image = sphrect.render(plane_scene(sun), samples=2)["rectangle"][..., :3]
    assert np.isfinite(image).all() and image.max() < 1e-6
    point = dict(position=(0.1, 0.2, 1.0), intensity=(0.7, 0.7, 0.7))
    soft = sphrect.render(plane_scene(sphrect.PointLight(radius=1e-6, **point)), samples=2)["rectangle"]
    sharp = sphrect.render(plane_scene(sphrect.PointLight(**point)), samples=2)["rectangle"]
    np.testing.assert_allclose(soft, sharp, rtol=1e-4, atol=1e-7)
