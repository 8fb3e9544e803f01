"""The renderer's Python API: determinism, progressive rendering, progress and cancellation,
time budgets, features, and clear errors for bad input."""
import threading
import time
import warnings

import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh


def box_mesh(center, size, name="box"):
    c, s = np.asarray(center, np.float32), np.asarray(size, np.float32) / 2
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], np.float32) * s + c
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = [t for a, b, c2, d in quads for t in ((a, b, c2), (a, c2, d))]
    return sphrect.Mesh(vertices=corners, triangles=np.array(tris, np.int32), name=name)


def simple_scene(width=24, height=16, **camera_kw):
    cam = sphrect.Camera(width=width, height=height, lens=35,
                         to_world=[[1, 0, 0, 0], [0, 0.8, -0.6, -4], [0, 0.6, 0.8, 3], [0, 0, 0, 1]], **camera_kw)
    light = sphrect.RectLight(corner=(-0.5, -0.5, 1.5), edge_x=(0, 1, 0), edge_y=(1, 0, 0), radiance=(4, 4, 4))
    return sphrect.Scene(camera=cam, meshes=[plane_mesh(), box_mesh((0.3, 0.2, 0.4), (0.6, 0.6, 0.8))],
                         lights=[light], materials=[sphrect.Material(base_color=(0.6, 0.5, 0.4))])


def test_image_shape_dtype_and_alpha():
    r = sphrect.Renderer(simple_scene(), techniques="rectangle")
    assert r.techniques == ["rectangle"]
    assert r.render(2)
    img = r.image("rectangle")
    assert img.dtype == np.float32 and img.shape == (16, 24, 4)
    assert np.all(img[:, :, 3] == 1) and np.all(np.isfinite(img)) and img[:, :, :3].max() > 0
    s = r.stats("rectangle")
    assert s["samples"] == 2 and s["rays"] > 0 and s["wall_time"] > 0
    assert s["light_time"] >= 0 and s["shading_time"] > 0
    assert s["camera_rays"] == 16 * 24 * 2 and s["dropped_samples"] == 0
    out = sphrect.render(simple_scene(), samples=2, techniques=("area", "rectangle"))
    assert set(out) == {"area", "rectangle"}


def test_identical_for_any_thread_count_and_tile_size():
    images = []
    for threads, tile in ((1, 16), (2, 16), (2, 5), (3, 7)):
        r = sphrect.Renderer(simple_scene(), techniques=["area", "rectangle"], threads=threads, tile_size=tile, seed=3)
        r.render(4)
        images.append([r.image(t) for t in r.techniques])
    for other in images[1:]:
        for a, b in zip(images[0], other):
            assert np.array_equal(a, b)


def test_seed_changes_the_noise():
    a = sphrect.Renderer(simple_scene(), seed=1)
    b = sphrect.Renderer(simple_scene(), seed=2)
    a.render(2)
    b.render(2)
    assert not np.array_equal(a.image(), b.image())


def test_progressive_passes_continue_the_sobol_sequence():
    """Two passes of 8 samples are the same samples as one pass of 16 (Sobol' is index-wise)."""
    a = sphrect.Renderer(simple_scene(), pattern="sobol")
    a.render(8)
    a.render(8)
    b = sphrect.Renderer(simple_scene(), pattern="sobol")
    b.render(16)
    assert a.stats()["samples"] == 16
    np.testing.assert_allclose(a.image(), b.image(), rtol=1e-5, atol=1e-6)


@pytest.mark.parametrize("pattern", sphrect.patterns)
def test_every_pattern_renders(pattern):
    r = sphrect.Renderer(simple_scene(8, 8), pattern=pattern, light_samples=3)
    assert r.render(5)
    assert np.all(np.isfinite(r.image()))


def test_progress_callback_runs_on_calling_thread():
    calls = []
    caller = threading.get_ident()
    r = sphrect.Renderer(simple_scene(40, 40), tile_size=8)
    assert r.render(1, progress=lambda d, t: calls.append((d, t, threading.get_ident())))
    assert calls and calls[-1][0] == calls[-1][1] == 25
    assert all(c[2] == caller for c in calls)
    assert [c[0] for c in calls] == sorted(c[0] for c in calls)


def test_cancel_from_another_thread_keeps_a_partial_image():
    r = sphrect.Renderer(simple_scene(96, 96), tile_size=8, light_samples=4, threads=2)
    started = threading.Event()
    canceller = threading.Thread(target=lambda: (started.wait(10), r.cancel()))
    canceller.start()
    ok = r.render(256, progress=lambda d, t: d > 0 and started.set())  # (0, total) comes first
    canceller.join()
    assert ok is False
    img = r.image()
    assert np.all(np.isfinite(img))
    lit = np.any(img[:, :, :3] > 0, axis=2)
    assert lit.any() and not lit.all()  # some tiles finished, not all
    assert r.stats()["samples"] == 0    # no complete pass
    # The renderer stays usable after a cancellation.
    assert r.render(1)


def test_cancel_from_the_progress_callback():
    r = sphrect.Renderer(simple_scene(64, 64), tile_size=8, threads=1)
    assert r.render(64, progress=lambda d, t: r.cancel()) is False


def test_render_is_not_reentrant():
    r = sphrect.Renderer(simple_scene(16, 16), tile_size=8)
    errors = []

    def progress(done, total):
        if not errors:
            try:
                r.render(1)
            except RuntimeError as e:
                errors.append(str(e))

    assert r.render(1, progress=progress)
    assert errors and "already rendering" in errors[0]


def test_exception_in_progress_callback_propagates():
    r = sphrect.Renderer(simple_scene(32, 32), tile_size=8)

    def boom(done, total):
        raise KeyError("stop")

    with pytest.raises(KeyError):
        r.render(4, progress=boom)


def test_gil_is_released_while_rendering():
    r = sphrect.Renderer(simple_scene(64, 64), threads=1)
    count = 0
    done = threading.Event()
    worker = threading.Thread(target=lambda: (r.render(64), done.set()))
    worker.start()
    while not done.is_set():
        count += 1
        time.sleep(0.001)
    worker.join()
    assert count > 5


def test_time_budget_adds_passes():
    r = sphrect.Renderer(simple_scene(16, 16))
    t0 = time.perf_counter()
    assert r.render(1, time_budget=0.3)
    elapsed = time.perf_counter() - t0
    s = r.stats()
    assert s["samples"] > 1
    assert elapsed < 3.0


def test_features():
    s = simple_scene()
    assert sphrect.Renderer(s).features == []
    s.materials = [sphrect.Material(kind="glossy", roughness=0.3)]
    s.world = sphrect.World(background=(0.1, 0.1, 0.1), medium=sphrect.Medium(sigma_s=(0.05,) * 3))
    s.camera.aperture_radius = 0.05
    s.lights.append(sphrect.EllipseLight(center=(0, 0, 2), axis_x=(0.2, 0, 0), axis_y=(0, 0.2, 0), radiance=(1, 1, 1)))
    s.lights.append(sphrect.PointLight(position=(1, 1, 1), intensity=(1, 1, 1)))
    r = sphrect.Renderer(s)
    assert set(r.features) == {"glossy", "medium", "dof", "ellipse_lights", "delta_lights", "background"}
    assert r.render(1) and np.all(np.isfinite(r.image()))
    o = simple_scene()
    o.camera.type = "orthographic"
    assert sphrect.Renderer(o).features == ["orthographic"]


@pytest.mark.parametrize("medium", [False, True])
def test_ellipse_technique_changes_only_ellipse_lights(medium):
    """A scene with a rectangle light only renders bit-identically with either ellipse technique; with a disc
    (in surface shading, and in the medium; 0.25 above the floor, close enough for spherical_ellipse to take its
    map there rather than area sampling, core/ellipse_map_choice.h) each technique renders its own finite image."""
    s = simple_scene(16, 12)
    if medium:
        s.world = sphrect.World(medium=sphrect.Medium(sigma_s=(0.1,) * 3))

    def images(scene):
        out = {}
        for ellipse_technique in sphrect.ellipse_techniques:
            r = sphrect.Renderer(scene, ellipse_technique=ellipse_technique, mis="balance")
            assert r.render(4) and r.stats()["dropped_samples"] == 0
            out[ellipse_technique] = r.image()
        return out

    rect = images(s)
    assert np.array_equal(rect["area"], rect["spherical_ellipse"])
    s.lights = [sphrect.EllipseLight(center=(-0.8, 0, 0.25), axis_x=(0, 0.3, 0), axis_y=(0.5, 0, 0),
                                     radiance=(4, 4, 4))]
    disc = images(s)
    assert all(np.all(np.isfinite(i)) and i[..., :3].mean() > 0.01 for i in disc.values())
    assert not np.array_equal(disc["area"], disc["spherical_ellipse"])


# --- bad input ----------------------------------------------------------------------------------

def with_mesh(vertices, triangles, **kw):
    s = simple_scene(8, 8)
    s.meshes = [sphrect.Mesh(vertices=np.asarray(vertices, np.float32), triangles=np.asarray(triangles), **kw)]
    return s


TRI = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]


@pytest.mark.parametrize("scene, match", [
    (lambda: with_mesh([[0, 0, 0], [1, np.nan, 0], [0, 1, 0]], [[0, 1, 2]]), "not finite"),
    (lambda: with_mesh(TRI, [[0, 1, 3]]), "out of range"),
    (lambda: with_mesh(TRI, [[0, -1, 2]]), "out of range"),
    (lambda: with_mesh(TRI, [[0, 1, 2**40]]), "out of range"),
    (lambda: with_mesh(TRI, [[0, 1]]), "shape"),
    (lambda: with_mesh(TRI, [[0.0, 1.5, 2.0]]), "integers"),
    (lambda: with_mesh(TRI, [[0, 1, 2]], material_ids=np.array([5])), "material_ids"),
    (lambda: with_mesh(TRI, [[0, 1, 2]], normals=np.zeros((2, 3), np.float32)), "normals"),
    # Embree would silently drop the triangle (its documented range is +-1.844e18).
    (lambda: with_mesh([[0, 0, 0], [1e19, 0, 0], [0, 1, 0]], [[0, 1, 2]]), "Embree's range"),
    (lambda: sphrect.Scene(camera=sphrect.Camera(width=8, height=8)), "empty scene"),
])
def test_bad_scene_raises_value_error(scene, match):
    with pytest.raises(ValueError, match=match):
        sphrect.Renderer(scene())


@pytest.mark.parametrize("width, height", [(0, 10), (10, -1), (100000, 10), (30000, 30000)])
def test_absurd_resolution(width, height):
    s = simple_scene()
    s.camera.width, s.camera.height = width, height
    with pytest.raises(ValueError, match="resolution|width|height"):
        sphrect.Renderer(s)


@pytest.mark.parametrize("kw, match", [
    (dict(techniques=["area", "nope"]), "unknown technique"),
    (dict(techniques=[]), "technique"),
    (dict(techniques=["area", "area"]), "twice"),
    (dict(pattern="halton"), "unknown pattern"),
    (dict(mis="heuristic"), "unknown mis"),
    (dict(medium_sampling="x"), "unknown medium_sampling"),
    (dict(ellipse_technique="disk"), "unknown ellipse_technique 'disk'; valid ellipse techniques: 'area', "
                                     "'spherical_ellipse'"),
    (dict(ellipse_technique="rectangle"), "unknown ellipse_technique"),  # a rectangle technique is not one
    (dict(light_samples=0), "light_samples"),
    (dict(light_samples=sphrect.MAX_LIGHT_SAMPLES + 1), "light_samples"),
    (dict(light_samples=2 ** 31), "light_samples"),  # beyond a C int: a ValueError, not pybind's TypeError
    (dict(threads=-1), "threads"),
    (dict(tile_size=2 ** 31), "tile_size"),
    (dict(seed=2 ** 64), "seed"),
])
def test_bad_options(kw, match):
    with pytest.raises(ValueError, match=match):
        sphrect.Renderer(simple_scene(), **kw)


def test_bad_render_arguments():
    r = sphrect.Renderer(simple_scene(8, 8))
    for bad in (0, -3, 1.5, True, sphrect.MAX_SAMPLES_PER_CALL + 1, 2 ** 40):
        with pytest.raises(ValueError, match="samples"):
            r.render(bad)
    with pytest.raises(ValueError):
        r.render(1, time_budget=-1)
    with pytest.raises(ValueError, match="not rendered"):
        r.image("area")


def test_bad_lights_and_materials():
    s = simple_scene()
    s.lights.append(sphrect.RectLight(corner=(0, 0, 1), edge_x=(1, 0, 0), edge_y=(1, 1, 0), radiance=(1, 1, 1)))
    with pytest.raises(ValueError, match="orthogonal"):
        sphrect.Renderer(s)
    s = simple_scene()
    s.lights[0].radiance = (np.nan, 1, 1)
    with pytest.raises(ValueError, match="radiance"):
        sphrect.Renderer(s)
    s = simple_scene()
    s.materials = [sphrect.Material(kind="velvet")]
    with pytest.raises(ValueError, match="unknown kind"):
        sphrect.Renderer(s)
    s = simple_scene()
    s.world = sphrect.World(medium=sphrect.Medium(g=1.5))
    with pytest.raises(ValueError, match="anisotropy"):
        sphrect.Renderer(s)


def test_zero_area_light_is_skipped_with_a_warning():
    s = simple_scene()
    s.lights.append(sphrect.RectLight(corner=(0, 0, 1), edge_x=(0, 0, 0), edge_y=(1, 0, 0), radiance=(1, 1, 1),
                                      name="flat"))
    with pytest.warns(RuntimeWarning, match="flat.*zero area"):
        r = sphrect.Renderer(s)
    assert r.render(1)
    s.lights = [s.lights[1]]  # only the degenerate light left, but the mesh remains: renders black
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = sphrect.Renderer(s)
    r.render(1)
    assert r.image()[:, :, :3].max() == 0


def test_light_whose_area_overflows_is_skipped_with_a_warning():
    s = simple_scene()
    s.lights.append(sphrect.RectLight(corner=(0, 0, 1), edge_x=(1e20, 0, 0), edge_y=(0, 1e20, 0), radiance=(1, 1, 1),
                                      name="vast"))
    with pytest.warns(RuntimeWarning, match="vast.*overflows"):
        sphrect.Renderer(s)


def test_large_mesh_from_numpy():
    """A 1M-triangle grid passes through without per-triangle Python work."""
    n = 709  # 2 * 708^2 ~ 1.0M triangles
    x, y = np.meshgrid(np.linspace(-2, 2, n, dtype=np.float32), np.linspace(-2, 2, n, dtype=np.float32))
    v = np.stack([x.ravel(), y.ravel(), np.zeros(n * n, np.float32)], axis=1)
    i = np.arange(n * n, dtype=np.int32).reshape(n, n)[:-1, :-1].ravel()
    tris = np.concatenate([np.stack([i, i + 1, i + n + 1], 1), np.stack([i, i + n + 1, i + n], 1)])
    s = simple_scene(8, 8)
    s.meshes = [sphrect.Mesh(vertices=v, triangles=tris)]
    r = sphrect.Renderer(s)
    assert len(tris) > 1_000_000
    assert r.render(1)
    assert r.image()[:, :, 0].max() > 0


def test_mesh_without_triangles_is_ignored():
    s = simple_scene(8, 8)
    s.meshes.append(sphrect.Mesh(vertices=np.zeros((0, 3), np.float32), triangles=np.zeros((0, 3), np.int32)))
    r = sphrect.Renderer(s)
    assert r.render(1) and np.all(np.isfinite(r.image()))


def test_every_render_default_is_render_options():
    # One place for the defaults (render/options.h's RenderOptions): the Renderer's keywords are its values.
    import inspect
    parameters = inspect.signature(sphrect.Renderer).parameters
    assert set(sphrect.RENDER_DEFAULTS) <= set(parameters)
    for name, value in sphrect.RENDER_DEFAULTS.items():
        assert parameters[name].default == value, name
    assert sphrect.RENDER_DEFAULTS["mis"] == "power" and sphrect.RENDER_DEFAULTS["light_selection"] == "tree"
