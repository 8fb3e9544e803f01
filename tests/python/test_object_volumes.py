"""Object volumes (homogeneous media bounded by closed meshes) against closed forms and against the world medium.

- Transmittance along camera and shadow rays through a slab: exact (one deterministic estimate per pixel).
- Single scattering of a sun in layered, overlapping slabs (and behind a transparent sheet): the closed form, which
  is the same at every pixel, against the image means of independent replicates (t-test; it detects ~1% errors).
- A box larger than the scene renders as the world medium of the same coefficients, and a world medium plus such a
  box as one world medium of their sum: per-pixel Welch tests.
Statistical tests use fixed seeds; each test's family-wise false-failure rate is FAMILY_ALPHA = 1e-4 over all its
pixels and configurations."""
import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh, replicate_images
from test_area_spread import pooled_t_test
from test_render_convergence import medium_scene, welch_agree

FAMILY_ALPHA = 1e-4


def box_volume(lo, hi, sigma_s, sigma_a=(0.0, 0.0, 0.0), g=0.0, name="box"):
    """An axis-aligned box [lo, hi] as a volume, its triangles counter-clockwise seen from outside."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    v = np.array([[hi[0] if i & 1 else lo[0], hi[1] if i & 2 else lo[1], hi[2] if i & 4 else lo[2]]
                  for i in range(8)])
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    t = np.array([tri for a, b, c, d in quads for tri in ((a, b, c), (a, c, d))])
    return sphrect.Volume(vertices=v, triangles=t, name=name,
                          medium=sphrect.Medium(sigma_s=tuple(sigma_s), sigma_a=tuple(sigma_a), g=g))


def looking_down(z, size=8):
    """An orthographic camera at height z looking down -Z over [-0.5, 0.5]^2."""
    return sphrect.Camera(width=size, height=size, type="orthographic", ortho_scale=1.0,
                          to_world=[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, z], [0, 0, 0, 1]])


SIGMA = np.array([0.5, 1.0, 2.0])


def test_a_light_seen_through_an_absorbing_slab_is_dimmed_by_exp_of_its_optical_depth():
    light = sphrect.RectLight(corner=(-2, -2, 0), edge_x=(4, 0, 0), edge_y=(0, 4, 0), radiance=(1, 1, 1),
                              visible=True)
    scene = sphrect.Scene(camera=looking_down(5), lights=[light],
                          volumes=[box_volume((-3, -3, 1), (3, 3, 2), (0, 0, 0), SIGMA)])
    r = sphrect.Renderer(scene)
    assert "volumes" in r.features and "medium" in r.features
    r.render(2)
    np.testing.assert_allclose(r.image()[..., :3], np.broadcast_to(np.exp(-SIGMA), (8, 8, 3)), rtol=1e-5)


@pytest.mark.parametrize("camera_z, length_to_camera", [(5.0, 1.0), (1.5, 0.5)])
def test_a_surface_lit_by_the_sun_through_a_slab(camera_z, length_to_camera):
    # The sun's light crosses the whole slab (1 m), the camera ray all of it or, from inside, half.
    sun = sphrect.SunLight(direction=(0, 0, -1), irradiance=(3, 3, 3))
    ground = plane_mesh(10)
    scene = sphrect.Scene(camera=looking_down(camera_z), lights=[sun], meshes=[ground],
                          materials=[sphrect.Material(base_color=(1, 1, 1))],
                          volumes=[box_volume((-3, -3, 1), (3, 3, 2), (0, 0, 0), SIGMA)])
    r = sphrect.Renderer(scene)
    r.render(1)
    expected = 3 / np.pi * np.exp(-(1 + length_to_camera) * SIGMA)
    np.testing.assert_allclose(r.image()[..., :3], np.broadcast_to(expected, (8, 8, 3)), rtol=1e-5)


def layered_single_scattering(layers, irradiance, mu, g):
    """Radiance scattered straight up out of horizontal layers [(thickness, sigma_s, sigma_t)] listed from the top,
    lit by a sun at mu = cos(its zenith angle), seen from above, nothing below: per layer
    sigma_s p E exp(-tau0 k) (1 - exp(-sigma_t h k)) / (sigma_t k), k = 1 + 1 / mu, tau0 the optical depth above."""
    cos_theta = -mu  # between the direction to the sun and the camera ray's (straight down)
    phase = (1 - g * g) / (4 * np.pi * (1 + g * g - 2 * g * cos_theta) ** 1.5)
    k = 1 + 1 / mu
    total, tau0 = np.zeros(3), np.zeros(3)
    for h, ss, st in layers:
        ss, st = np.asarray(ss, float), np.asarray(st, float)
        total += ss * phase * irradiance * np.exp(-tau0 * k) * (1 - np.exp(-st * h * k)) / (st * k)
        tau0 = tau0 + st * h
    return total


@pytest.mark.parametrize("medium_sampling", ["distance", "mis"])
def test_single_scattering_in_overlapping_slabs_matches_the_closed_form(medium_sampling):
    # Box a: z in [0, 2], box b: z in [1, 3]; from the top: b alone, a + b, a alone.  An oblique sun.
    g = 0.4
    ss_a, sa_a = np.array([0.3, 0.6, 0.9]), np.array([0.1, 0.0, 0.2])
    ss_b, sa_b = np.array([0.5, 0.2, 0.1]), np.array([0.2, 0.3, 0.0])
    mu = np.cos(np.radians(30))
    sun = sphrect.SunLight(direction=(-np.sqrt(1 - mu * mu), 0, -mu), irradiance=(2, 2, 2))
    scene = sphrect.Scene(camera=looking_down(5, size=8), lights=[sun],
                          volumes=[box_volume((-4, -4, 0), (4, 4, 2), ss_a, sa_a, g, "a"),
                                   box_volume((-4, -4, 1), (4, 4, 3), ss_b, sa_b, g, "b")])
    expected = layered_single_scattering([(1, ss_b, ss_b + sa_b), (1, ss_a + ss_b, ss_a + sa_a + ss_b + sa_b),
                                          (1, ss_a, ss_a + sa_a)], 2.0, mu, g)
    for channel in range(3):
        # replicate_images keeps the red channel: one run per channel, the colours permuted into red.
        perm = [channel, (channel + 1) % 3, (channel + 2) % 3]
        permuted = sphrect.Scene(camera=scene.camera, lights=scene.lights, volumes=[
            box_volume(v.vertices.min(0), v.vertices.max(0), np.asarray(v.medium.sigma_s)[perm],
                       np.asarray(v.medium.sigma_a)[perm], g, v.name) for v in scene.volumes])
        reps = replicate_images(permuted, ["rectangle"], 16, 64, medium_sampling=medium_sampling)["rectangle"]
        ok, p, rel = pooled_t_test(reps, expected[channel], FAMILY_ALPHA / 6)
        assert ok, f"channel {channel}: p = {p:.3g}, {rel:+.2%} from the closed form"


def test_scattering_behind_a_transparent_surface_is_filtered_by_it_and_in_front_is_not():
    # A slab z in [0, 2], a transparent sheet of colour c at z = 1, a sun
    # straight above: the upper half's light as without the sheet, the lower half's filtered by c twice (the sun's
    # shadow ray and the camera ray cross it).  Closed form: layered_single_scattering's layers, the lower one times
    # c^2.  Family-wise false-failure rate FAMILY_ALPHA over the pixels and channels.
    ss, sa, c = np.array([0.6, 0.4, 0.2]), np.array([0.1, 0.2, 0.3]), np.array([0.7, 0.5, 0.3])
    sun = sphrect.SunLight(direction=(0, 0, -1), irradiance=(2, 2, 2))
    sheet = plane_mesh(10, z=1.0)
    top = layered_single_scattering([(1, ss, ss + sa)], 2.0, 1.0, 0.0)
    below = layered_single_scattering([(1, ss, ss + sa), (1, ss, ss + sa)], 2.0, 1.0, 0.0) - top
    expected = top + c * c * below
    for channel in range(3):
        perm = [channel, (channel + 1) % 3, (channel + 2) % 3]
        scene = sphrect.Scene(camera=looking_down(5, size=8), lights=[sun], meshes=[sheet],
                              materials=[sphrect.Material(kind="transparent", base_color=tuple(c[perm]))],
                              volumes=[box_volume((-4, -4, 0), (4, 4, 2), ss[perm], sa[perm])])
        reps = replicate_images(scene, ["rectangle"], 16, 64, medium_sampling="distance")["rectangle"]
        ok, p, rel = pooled_t_test(reps, expected[channel], FAMILY_ALPHA / 3)
        assert ok, f"channel {channel}: p = {p:.3g}, {rel:+.2%} from the closed form"


def enclosed(scene, volumes, medium=None):
    """`scene` with its world medium replaced by `medium` and the volumes added."""
    world = sphrect.World(background=scene.world.background, medium=medium)
    return sphrect.Scene(camera=scene.camera, meshes=scene.meshes, lights=scene.lights, materials=scene.materials,
                         world=world, volumes=volumes)


@pytest.mark.slow
def test_a_box_around_the_scene_renders_as_the_world_medium():
    ss, sa, g = (0.25, 0.3, 0.35), (0.05, 0.02, 0.0), 0.3
    world = medium_scene(ss, sa, g)
    boxed = enclosed(world, [box_volume((-50, -50, -50), (50, 50, 50), ss, sa, g)])
    for ms in ("distance", "equiangular", "mis"):
        a = replicate_images(world, ["rectangle"], 8, 32, medium_sampling=ms, first_seed=1000)["rectangle"]
        b = replicate_images(boxed, ["rectangle"], 8, 32, medium_sampling=ms, first_seed=2000)["rectangle"]
        ok, p = welch_agree(a, b, FAMILY_ALPHA / 5)
        assert ok, f"{ms}: the box differs from the world medium, worst p = {p:.3g}"
    # A world medium and a box around the scene add up to one world medium of their sum.
    half = tuple(x / 2 for x in ss), tuple(x / 2 for x in sa)
    split = enclosed(world, [box_volume((-50, -50, -50), (50, 50, 50), *half, g)],
                     sphrect.Medium(sigma_s=half[0], sigma_a=half[1], g=g))
    a = replicate_images(world, ["rectangle"], 8, 32, first_seed=1000)["rectangle"]
    b = replicate_images(split, ["rectangle"], 8, 32, first_seed=2000)["rectangle"]
    ok, p = welch_agree(a, b, FAMILY_ALPHA / 5)
    assert ok, f"world + box differs from the world medium of their sum, worst p = {p:.3g}"
    # Through a transparent sheet across the view (the world medium's path weights its scattering by the sheet's
    # transparency past it as the volumes' does; their closed form is checked above).
    sheet = plane_mesh(4)
    sheet.vertices = np.asarray(sheet.vertices, float) @ np.array([[1, 0, 0], [0, 0, 1], [0, 1, 0]]) + [0, -1.5, 0]
    sheet.material_ids = np.full(len(sheet.triangles), 1, np.int32)
    veiled = [sphrect.Scene(camera=s.camera, meshes=s.meshes + [sheet], lights=s.lights, world=s.world,
                            volumes=s.volumes, materials=s.materials + [
                                sphrect.Material(kind="transparent", base_color=(0.6, 0.6, 0.6))])
              for s in (world, boxed)]
    a = replicate_images(veiled[0], ["rectangle"], 8, 32, first_seed=1000)["rectangle"]
    b = replicate_images(veiled[1], ["rectangle"], 8, 32, first_seed=2000)["rectangle"]
    ok, p = welch_agree(a, b, FAMILY_ALPHA / 5)
    assert ok, f"behind a transparent sheet, the box differs from the world medium, worst p = {p:.3g}"


@pytest.mark.slow
def test_equiangular_centres_weighed_and_lumped_agree_with_the_world_medium():
    """More lights than a camera ray weighs one by one (an emissive strip of 40 triangles beside the scene's two
    lights): the weighed and the lumped centres of the box's equi-angular sampling against the world medium's power
    choice (per-pixel Welch tests)."""
    ss, sa, g = (0.25, 0.3, 0.35), (0.05, 0.02, 0.0), 0.3
    world = medium_scene(ss, sa, g)
    xs = np.linspace(-1.5, 1.5, 21)
    strip = sphrect.Mesh(vertices=np.array([[x, 1.2, z] for x in xs for z in (0.05, 0.25)], np.float32),
                         triangles=np.array([t for i in range(20) for t in ((2 * i, 2 * i + 2, 2 * i + 3),
                                                                           (2 * i, 2 * i + 3, 2 * i + 1))], np.int32),
                         material_ids=np.full(40, 1, np.int32), name="strip")
    lamp = sphrect.Material(name="lamp", emission=(2.0, 1.5, 1.0), base_color=(0, 0, 0))
    world = sphrect.Scene(camera=world.camera, meshes=world.meshes + [strip], lights=world.lights, world=world.world,
                          materials=world.materials + [lamp])
    boxed = enclosed(world, [box_volume((-50, -50, -50), (50, 50, 50), ss, sa, g)])
    for ms in ("equiangular", "mis"):
        a = replicate_images(world, ["rectangle"], 8, 32, medium_sampling=ms, first_seed=1000)["rectangle"]
        b = replicate_images(boxed, ["rectangle"], 8, 32, medium_sampling=ms, first_seed=2000)["rectangle"]
        ok, p = welch_agree(a, b, FAMILY_ALPHA / 2)
        assert ok, f"{ms}: the box differs from the world medium with many lights, worst p = {p:.3g}"


def test_a_volume_the_rays_never_reach_changes_nothing():
    # Far off to the side: every ray misses its bounds (no walk), and the image is the volume-free one exactly.
    free = medium_scene(None, None)
    far = enclosed(free, [box_volume((100, 100, 100), (101, 101, 101), (1, 1, 1))])
    a, b = sphrect.Renderer(free, seed=3, analytic_light_coverage=False), sphrect.Renderer(far, seed=3)
    a.render(8)
    b.render(8)
    np.testing.assert_array_equal(a.image(), b.image())
