"""Image worlds (render/environment_light.h): an equirectangular image as Cycles 3.4 maps it, importance-sampled by
a 2-D piecewise-constant distribution over its pixels (luminance x solid angle), a light of its own with MIS against
BSDF rays.

- SampleEnvironment against EnvironmentPDF (chi-square, chi2.py's environment_chi2_test: the project's one harness),
  including a rotated world, black regions, pole rows and a 1x1 image; the test fails for a wrong pdf;
  InvertEnvironmentSample undoes SampleEnvironment;
- closed forms on a Lambertian plane facing up (outgoing albedo / pi * E): a constant image of radiance L gives
  L albedo; a two-tone image (upper half L1, lower L2) gives L1 albedo, rotated 90 degrees about X (the plane now
  sees half of each) (L1 + L2) / 2 albedo, rotated 180 degrees L2 albedo; a single bright pixel (a small sun) gives
  the exact irradiance of its cell; each with and without MIS, with each light selection where it matters;
- a glossy plane: MIS and light samples alone estimate the same image;
- camera rays see the texel of a known direction (the mapping pinned), through a rotation too;
- bad inputs are ValueErrors.

False-failure rate: the chi-square tests share a suite-wide significance of 1e-3 (Sidak over CHI2_TESTS); each
image test is one family of pixel tests at 1e-4 (Sidak over its pixels), 13 of them: a correct renderer fails this
file with probability < 0.25 % (fixed seeds: the outcome is deterministic).  The other tests are exact."""
import math

import numpy as np
import pytest
from scipy import stats

import sphrect
from chi2 import environment_chi2_test, equirectangular_direction, sidak_alpha
from sphrect.render import build_native_scene
from render_testing import (expected_plane_image, pixel_t_test, plane_mesh, replicate_images, save_as_older_version,
                            top_camera)

FAMILY_ALPHA = 1e-4
ALBEDO = 0.5
REPLICATES = 16
CHI2_TESTS = 6


def rot_x(angle):
    c, s = math.cos(angle), math.sin(angle)
    return [[1, 0, 0], [0, c, -s], [0, s, c]]


def rot_z(angle):
    c, s = math.cos(angle), math.sin(angle)
    return [[c, -s, 0], [s, c, 0], [0, 0, 1]]


def random_image(h, w, seed=0):
    return np.random.default_rng(seed).random((h, w, 3)).astype(np.float32)


def spot_image(h=32, w=64, x0=20, y0=27, value=500.0, floor=0.0):
    img = np.full((h, w, 3), floor, np.float32)
    img[y0, x0] = value
    return img


def two_tone_image(l1, l2):
    """Two rows: the upper half of the sphere (row 1, the top) l1, the lower l2."""
    return np.array([[[l2] * 3], [[l1] * 3]], np.float32)


CHI2_CASES = [
    ("random 6x8", random_image(6, 8), None, "linear"),
    ("random 6x8 rotated", random_image(6, 8, 1), np.array(rot_x(0.7)) @ np.array(rot_z(1.2)), "linear"),
    ("spot in black, closest", spot_image(12, 16, 3, 10, 50.0), None, "closest"),
    ("two rows (pole rows only)", two_tone_image(3.0, 0.5), rot_x(0.4), "closest"),
    ("1x1", np.ones((1, 1, 3), np.float32), None, "linear"),
]


@pytest.mark.parametrize("name,image,to_world,interpolation", CHI2_CASES, ids=[c[0] for c in CHI2_CASES])
def test_environment_sampling_matches_its_pdf(name, image, to_world, interpolation):
    sampler = sphrect.EnvironmentSampler(image, to_world=to_world, interpolation=interpolation)
    # A grid on the sampling cells' edges (the 6 x 8 images: 36 x 64) where no pixel is black (exact cell integrals:
    # fast), else one across them.
    resolution = (64, 36) if np.all(image > 0) and image.shape[:2] == (6, 8) else (25, 13)
    r = environment_chi2_test(sampler, name, to_world=to_world, test_count=CHI2_TESTS, resolution=resolution)
    assert abs(r.total_probability - 1) < 1e-3, str(r)
    assert r.passed, str(r)


def test_environment_chi2_fails_for_a_wrong_pdf():
    """The same harness rejects a pdf tilted by 10 % towards +Z: it can fail."""
    sampler = sphrect.EnvironmentSampler(random_image(6, 8))
    r = environment_chi2_test(sampler, "tilted", test_count=CHI2_TESTS, resolution=(64, 36),
                              pdf_factor=lambda w: 1 + 0.1 * w[:, 2])
    assert not r.passed, str(r)


@pytest.mark.parametrize("to_world", [None, rot_x(0.7)])
def test_invert_environment_sample_round_trip(to_world):
    sampler = sphrect.EnvironmentSampler(random_image(16, 32, 2), to_world=to_world)
    u = np.random.default_rng(3).random((20000, 2))
    dirs, pdf = sampler.sample(u)
    assert np.all(pdf > 0)
    back = sampler.invert(dirs)
    # Float32 directions: (u, v) back within ~1e-6 relative, the inverse's cdf steps within the pixel's weight.
    assert np.max(np.abs(back - u)) < 2e-4, np.max(np.abs(back - u))


def test_an_all_black_image_is_no_light():
    sampler = sphrect.EnvironmentSampler(np.zeros((4, 8, 3), np.float32))
    dirs, pdf = sampler.sample(np.random.default_rng(0).random((100, 2)))
    assert np.all(pdf == 0)
    assert np.all(sampler.pdf(np.array([[0, 0, 1.0], [1.0, 0, 0]])) == 0)


def test_pdf_is_finite_and_positive_at_the_poles_and_the_seam():
    sampler = sphrect.EnvironmentSampler(random_image(5, 7))
    pdf = sampler.pdf(np.array([[0, 0, 1.0], [0, 0, -1.0], [-1.0, 0, 0], [-1.0, 1e-7, 0], [0.1, 0, 0.995]]))[:, 0]
    assert pdf[0] == 0 and pdf[1] == 0  # exactly at a pole: a set of measure zero
    assert np.all(np.isfinite(pdf)) and np.all(pdf[2:] > 0)


def environment_scene(image, to_world=None, strength=(1.0, 1.0, 1.0), interpolation="closest", material=None,
                      meshes=None, camera=None):
    env = sphrect.Environment(texture=0, strength=strength, interpolation=interpolation,
                              to_world=np.eye(3).tolist() if to_world is None else np.asarray(to_world).tolist())
    return sphrect.Scene(camera=camera or top_camera(), meshes=[plane_mesh()] if meshes is None else meshes,
                         materials=[material or sphrect.Material(base_color=(ALBEDO,) * 3)],
                         textures=[sphrect.Texture(name="world", pixels=image, colorspace="linear")],
                         world=sphrect.World(background=(7.0, 7.0, 7.0), environment=env))


def constant_expected(cam, radiance):
    return expected_plane_image(cam, ALBEDO, lambda P: np.full(P.shape[:-1], math.pi * radiance))


@pytest.mark.parametrize("light_selection", ["power", "tree"])
@pytest.mark.parametrize("mis", ["none", "balance"])
def test_constant_environment_on_plane(mis, light_selection):
    """A constant image of radiance 0.8 (its background of 7 ignored: the image replaces it), with a rect light
    far off to the side that no pixel sees (so that light selection has something to choose): L albedo."""
    scene = environment_scene(np.full((8, 16, 3), 0.8, np.float32), interpolation="linear")
    scene.lights.append(sphrect.RectLight(corner=(90, 90, -5), edge_x=(1, 0, 0), edge_y=(0, 1, 0),
                                          radiance=(1, 1, 1)))
    expected = constant_expected(scene.camera, 0.8)
    reps = replicate_images(scene, ["rectangle"], REPLICATES, 8, mis=mis, light_selection=light_selection,
                            bsdf_samples_on_diffuse=True)
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, FAMILY_ALPHA)
    assert ok, f"constant environment {mis}/{light_selection}: worst p = {p_min:.3g} < {alpha:.3g}"


@pytest.mark.parametrize("angle,seen", [(0.0, 1.5), (math.pi / 2, (1.5 + 0.25) / 2), (math.pi, 0.25)])
@pytest.mark.parametrize("mis", ["none", "power"])
def test_two_tone_environment_on_plane(mis, angle, seen):
    """Upper half 1.5, lower 0.25, turned by `angle` about X (to_world): the plane facing up sees the upper half
    (L1 albedo), half of each (a vertical plane's view: (L1 + L2) / 2 albedo), the lower half (L2 albedo)."""
    scene = environment_scene(two_tone_image(1.5, 0.25), to_world=rot_x(angle))
    expected = constant_expected(scene.camera, seen)
    reps = replicate_images(scene, ["rectangle"], REPLICATES, 8, mis=mis, bsdf_samples_on_diffuse=True)
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, FAMILY_ALPHA, rel_tol=1e-4)
    assert ok, f"two-tone {angle:.2f} {mis}: worst p = {p_min:.3g} < {alpha:.3g}"


def spot_irradiance(h, w, x0, y0, value):
    """Irradiance at a plane facing +Z from pixel (x0, y0) of radiance `value` (closest interpolation) above its
    horizon: value * (2 pi / w) * (sin^2 theta_b - sin^2 theta_a) / 2, theta = pi (1 - v)."""
    theta_a, theta_b = math.pi * (1 - (y0 + 1) / h), math.pi * (1 - y0 / h)
    assert theta_b <= math.pi / 2
    return value * (2 * math.pi / w) * (math.sin(theta_b) ** 2 - math.sin(theta_a) ** 2) / 2


@pytest.mark.parametrize("mis", ["none", "power"])
def test_small_sun_in_a_dark_environment(mis):
    """One bright pixel of 32 x 64 (a ~5.6 x 5.6 degree sun) in black: the exact irradiance of its cell.  Found by
    BSDF rays alone it would take ~1/0.003 samples per hit; importance sampling finds it every sample."""
    h, w, x0, y0, value = 32, 64, 20, 27, 500.0
    scene = environment_scene(spot_image(h, w, x0, y0, value))
    e = spot_irradiance(h, w, x0, y0, value)
    expected = expected_plane_image(scene.camera, ALBEDO, lambda P: np.full(P.shape[:-1], e))
    reps = replicate_images(scene, ["rectangle"], REPLICATES, 4, mis=mis, bsdf_samples_on_diffuse=True)
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, FAMILY_ALPHA, rel_tol=1e-4)
    assert ok, f"small sun {mis}: worst p = {p_min:.3g} < {alpha:.3g}"
    # Light samples alone of a one-pixel cell under a cosine: the estimate's spread is a few % at most.
    assert reps["rectangle"].std(axis=0).max() < 0.05 * expected.max()


def test_glossy_plane_with_mis_matches_light_samples_alone():
    """A rough glossy plane under a random image: light samples alone and MIS with BSDF rays that escape (weighted
    by EnvironmentPDF) estimate the same image (Welch t-test per pixel)."""
    material = sphrect.Material(base_color=(0.4,) * 3, metallic=1.0, roughness=0.4)
    scene = environment_scene(random_image(8, 16, 5) * 2, material=material, interpolation="linear")
    scene.camera = sphrect.Camera(width=10, height=10, lens=35,
                                  to_world=[[1, 0, 0, 0], [0, 0.6, -0.8, -4], [0, 0.8, 0.6, 3], [0, 0, 0, 1]])
    a = replicate_images(scene, ["rectangle"], REPLICATES, 16, mis="none")["rectangle"]
    b = replicate_images(scene, ["rectangle"], REPLICATES, 16, mis="power")["rectangle"]
    assert a.mean() > 0.05
    p = stats.ttest_ind(a, b, axis=0, equal_var=False).pvalue
    assert np.nanmin(p) >= sidak_alpha(FAMILY_ALPHA, p.size), np.nanmin(p)


def look_at_camera(direction, lens=5000.0):
    """A perspective camera at the origin looking along `direction` (a narrow view: every pixel sees one texel)."""
    z = -np.asarray(direction, np.float64) / np.linalg.norm(direction)
    up = np.array([0, 0, 1.0]) if abs(z[2]) < 0.9 else np.array([1.0, 0, 0])
    x = np.cross(up, z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2] = x, y, z
    return sphrect.Camera(width=4, height=4, lens=lens, to_world=m.tolist())


@pytest.mark.parametrize("to_world", [None, rot_z(math.pi / 2) @ np.array(rot_x(0.3))])
def test_camera_sees_the_texel_of_its_direction(to_world):
    """Each texel of an 8 x 4 image a colour of its own; a camera looking at the centre of texel (x, y) in the
    image's frame -- (u, v) = ((x + 1/2) / 8, (y + 1/2) / 4), direction (sin t cos p, sin t sin p, cos t) with
    t = pi (1 - v), p = pi (1 - 2 u) (Cycles' equirectangular mapping) -- sees that colour, through to_world."""
    h, w = 4, 8
    ids = np.arange(h * w, dtype=np.float32).reshape(h, w)
    image = np.stack([ids / 10, (ids % w) / 10, (ids // w) / 10 + 0.05], axis=-1).astype(np.float32)
    R = np.eye(3) if to_world is None else np.asarray(to_world)
    for x, y in [(4, 2), (0, 0), (6, 3), (1, 1)]:
        d, _ = equirectangular_direction(np.array([(x + 0.5) / w]), np.array([(y + 0.5) / h]))
        scene = environment_scene(image, to_world=R, meshes=[], camera=look_at_camera(R @ d[0]))
        r = sphrect.Renderer(scene, techniques=["rectangle"])
        assert r.render(2)
        got = r.image("rectangle")[:, :, :3]
        np.testing.assert_allclose(got, np.broadcast_to(image[y, x], got.shape), rtol=1e-6, atol=1e-7,
                                   err_msg=f"texel ({x}, {y})")


def test_middle_column_is_plus_x_and_top_row_is_plus_z():
    """The convention in words (scene.py's docstring): +X is the image's middle column, +Z its top row.  (Exactly
    at the pole v = 1, where Cycles' closest lookup wraps to the bottom row as well: a direction of measure zero.)"""
    image = np.zeros((3, 4, 3), np.float32)
    image[1, 2] = (1, 0, 0)   # middle row, column u in [0.5, 0.75): just clockwise of +X seen from +Z
    image[2, :] = (0, 0, 1)   # top row
    sampler = sphrect.EnvironmentSampler(image, interpolation="closest")
    rad = sampler.radiance(np.array([[1.0, -0.01, 0], [0.01, 0, 1.0], [1.0, 0.01, 0]]))
    np.testing.assert_array_equal(rad, [[1, 0, 0], [0, 0, 1], [0, 0, 0]])


def test_film_transparent_hides_the_environment_but_it_still_lights():
    scene = environment_scene(np.full((2, 4, 3), 0.8, np.float32), meshes=[])
    scene.camera = look_at_camera((1, 0, 0), lens=50)
    scene.camera.film_transparent = True
    r = sphrect.Renderer(scene, techniques=["rectangle"])
    assert r.render(1)
    assert np.all(r.image("rectangle") == 0)


@pytest.mark.parametrize("change,message", [
    (dict(texture=1), "texture must be an index"),
    (dict(texture=-1), "texture must be an index"),
    (dict(texture=True), "texture must be an index"),
    (dict(interpolation="cubic"), "interpolation must be"),
    (dict(to_world=(np.eye(3) * 2).tolist()), "must be a 3x3 rotation"),
    (dict(to_world=np.diag([1.0, 1.0, -1.0]).tolist()), "must be a 3x3 rotation"),
    (dict(to_world=[[1, 0], [0, 1]]), "must be a 3x3 rotation"),
    (dict(strength=(-1, 0, 0)), "strength"),
])
def test_bad_environment_is_refused(change, message):
    scene = environment_scene(np.ones((2, 4, 3), np.float32))
    for k, v in change.items():
        setattr(scene.world.environment, k, v)
    with pytest.raises(ValueError, match=message):
        sphrect.Renderer(scene, techniques=["rectangle"])


def test_environment_is_a_scene_feature_and_its_only_light():
    """An image world alone (no triangles, no lights) is a scene; its feature is named."""
    scene = environment_scene(np.ones((2, 4, 3), np.float32), meshes=[], camera=look_at_camera((0, 1, 0), 50))
    native, _ = build_native_scene(scene)
    assert "environment" in native.features and "background" not in native.features


def test_files_keep_the_environment_and_older_ones_load_without(tmp_path):
    """A saved image world loads back the same (and renders the same image); a format-11 file, which has none,
    loads with the constant background."""
    scene = environment_scene(random_image(4, 8, 9), to_world=rot_x(0.4), strength=(2.0, 1.0, 0.5))
    path = str(tmp_path / "env.sphrect.npz")
    sphrect.save_scene(scene, path)
    loaded = sphrect.load_scene(path)
    e, f = loaded.world.environment, scene.world.environment
    assert (e.texture, tuple(e.strength), e.to_world, e.interpolation) == \
        (f.texture, tuple(f.strength), f.to_world, f.interpolation)
    a = sphrect.Renderer(scene, techniques=["rectangle"], seed=3)
    b = sphrect.Renderer(loaded, techniques=["rectangle"], seed=3)
    assert a.render(2) and b.render(2)
    np.testing.assert_array_equal(a.image("rectangle"), b.image("rectangle"))
    old = str(tmp_path / "old.sphrect.npz")
    save_as_older_version(path, old, 11, lambda meta: meta["world"].pop("environment"))
    older = sphrect.load_scene(old)
    assert older.world.environment is None and tuple(older.world.background) == (7.0, 7.0, 7.0)


def test_an_environment_in_an_infinite_medium_lights_nothing():
    """The medium's transmittance to infinity is 0, as for the constant background: the image world adds nothing
    (the image is the one with the constant background of black, bit for bit)."""
    scene = environment_scene(np.full((4, 8, 3), 3.0, np.float32))
    scene.world.medium = sphrect.Medium(sigma_s=(0.2,) * 3, sigma_a=(0.05,) * 3)
    scene.lights.append(sphrect.PointLight(position=(0, 0, 1), intensity=(1, 1, 1)))
    plain = environment_scene(np.full((4, 8, 3), 3.0, np.float32))
    plain.world = sphrect.World(medium=scene.world.medium)
    plain.lights = list(scene.lights)
    a = sphrect.Renderer(scene, techniques=["rectangle"], seed=5)
    b = sphrect.Renderer(plain, techniques=["rectangle"], seed=5)
    assert a.render(2) and b.render(2)
    assert b.image("rectangle")[..., 0].mean() > 0
    np.testing.assert_array_equal(a.image("rectangle"), b.image("rectangle"))


def test_the_sampling_distribution_counts_against_the_image_memory():
    """A 512 x 256 float image (1.5 MiB) fits a 3 MiB limit, its sampling distribution (1 MiB) beside it too, not a
    2 MiB one."""
    pixels = np.ones((256, 512, 3), np.float32)
    for limit, fits in ((3 << 20, True), (2 << 20, False)):
        native = sphrect._native._Scene()
        native.set_image_memory_limit(limit)
        native.add_image("sky", pixels, False)
        if fits:
            native.set_environment(0, (1.0, 1.0, 1.0), np.eye(3), "linear")
            assert native.image_memory_bytes == pixels.nbytes + (512 * 256 + 256) * 8
        else:
            with pytest.raises(ValueError, match="sampling distribution"):
                native.set_environment(0, (1.0, 1.0, 1.0), np.eye(3), "linear")


def test_camera_environment_is_what_camera_rays_see_and_lights_nothing(tmp_path):
    """World.camera_environment (a world whose Light Path node shows the camera something else): escaping camera rays
    see its texel, not the image world's; the plane is lit by the image world alone (its closed form), exactly as
    without a camera environment; a file keeps it, a format-18 one loads without; bad ones are refused."""
    h, w = 4, 8
    ids = np.arange(h * w, dtype=np.float32).reshape(h, w)
    seen = np.stack([ids / 10, (ids % w) / 10, (ids // w) / 10 + 0.05], axis=-1).astype(np.float32)
    x, y = 4, 2
    d, _ = equirectangular_direction(np.array([(x + 0.5) / w]), np.array([(y + 0.5) / h]))
    scene = environment_scene(np.full((2, 4, 3), 0.8, np.float32), meshes=[], camera=look_at_camera(d[0]))
    scene.textures.append(sphrect.Texture(name="camera world", pixels=seen, colorspace="linear"))
    scene.world.camera_environment = sphrect.Environment(texture=1, interpolation="closest")
    r = sphrect.Renderer(scene, techniques=["rectangle"])
    assert r.render(2)
    got = r.image("rectangle")[:, :, :3]
    np.testing.assert_allclose(got, np.broadcast_to(seen[y, x], got.shape), rtol=1e-6, atol=1e-7)
    # What the plane receives: the image world's light, the same image as without the camera's.
    lit = environment_scene(np.full((8, 16, 3), 0.8, np.float32), interpolation="linear")
    lit.textures.append(sphrect.Texture(name="camera world", pixels=seen, colorspace="linear"))
    plain = sphrect.Renderer(lit, techniques=["rectangle"], seed=4)
    lit.world.camera_environment = sphrect.Environment(texture=1)
    split = sphrect.Renderer(lit, techniques=["rectangle"], seed=4)
    assert plain.render(2) and split.render(2)
    np.testing.assert_array_equal(plain.image("rectangle"), split.image("rectangle"))
    # Saved and loaded; older files load without.
    path, old = str(tmp_path / "split.sphrect.npz"), str(tmp_path / "old.sphrect.npz")
    sphrect.save_scene(scene, path)
    assert sphrect.load_scene(path).world.camera_environment.texture == 1
    save_as_older_version(path, old, 18, lambda meta: meta["world"].pop("camera_environment"))
    assert sphrect.load_scene(old).world.camera_environment is None
    scene.world.camera_environment = sphrect.Environment(texture=2)
    with pytest.raises(ValueError, match="world camera environment texture must be an index"):
        sphrect.Renderer(scene, techniques=["rectangle"])
