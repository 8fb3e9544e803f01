"""Emissive meshes: every emissive triangle is a two-sided area light (Cycles' mesh-light conventions),
an exact rectangle of two triangles is one rectangle light.

Statistical tests: per-pixel t-tests of independent replicate renders against Lambert's polygon
formula (render_testing.pixel_t_test), Sidak-corrected so that each test fails falsely with probability
FAMILY_ALPHA = 1e-4 over all its pixels, techniques and MIS modes (fixed seeds: the outcome is
deterministic, the rate is that of a seed set drawn at random)."""
import json

import numpy as np
import pytest

import sphrect
from sphrect.render import build_native_scene
from render_testing import (ALL_TECHNIQUES, expected_plane_image, pixel_t_test, plane_mesh, polygon_irradiance,
                            replicate_images, top_camera)

FAMILY_ALPHA = 1e-4
ALBEDO = 0.5
REPLICATES = 24
SAMPLES = 16
RADIANCE = 2.0


def emissive_mesh(vertices, triangles, name="panel"):
    v = np.asarray(vertices, np.float32)
    t = np.asarray(triangles, np.int32)
    return sphrect.Mesh(vertices=v, triangles=t, name=name, material_ids=np.ones(len(t), np.int32))


def materials(radiance=RADIANCE):
    return [sphrect.Material(name="ground", base_color=(ALBEDO,) * 3),
            sphrect.Material(name="emitter", base_color=(0, 0, 0), emission=(radiance,) * 3)]


def ground():
    g = plane_mesh()
    g.material_ids = np.zeros(2, np.int32)
    return g


# The light at z = 1 above a camera at z = 0.5 looking down: the camera sees only the lit plane.
SQUARE = [[-0.5, -0.4, 1], [0.6, -0.4, 1], [0.6, 0.5, 1], [-0.5, 0.5, 1]]
TRIANGLE = [[-0.6, -0.5, 1.0], [0.7, -0.2, 0.8], [0.1, 0.6, 1.2]]


def test_square_mesh_is_one_rectangle_light():
    native, warnings = build_native_scene(sphrect.Scene(camera=top_camera(), meshes=[ground(), emissive_mesh(
        SQUARE, [[0, 1, 2], [0, 2, 3]])], materials=materials()))
    assert native.num_area_lights == 1 and "emissive_meshes" in native.features and not warnings
    # A sheared quad (a parallelogram) is two triangle lights.
    sheared = [[-0.5, -0.4, 1], [0.6, -0.4, 1], [0.8, 0.5, 1], [-0.3, 0.5, 1]]
    native, _ = build_native_scene(sphrect.Scene(camera=top_camera(), meshes=[ground(), emissive_mesh(
        sheared, [[0, 1, 2], [0, 2, 3]])], materials=materials()))
    assert native.num_area_lights == 2


@pytest.mark.parametrize("medium", [False, True])
@pytest.mark.parametrize("mis", sphrect.mis_modes)
def test_square_mesh_equals_rectangle_light(mis, medium):
    """The same samples on the recognised rectangle and on the equivalent two-sided RectLight: images
    equal up to the shadow ray's end pulled off the mesh (~1e-4 relative) and float rounding; also in a
    medium (light and phase samples, equi-angular sampling about the same centre).  Both with BSDF samples at the
    diffuse ground: a scene with an emissive mesh keeps them (MIS), one with the RectLight alone would drop them."""
    cam = top_camera(height_above=0.5)
    v = np.asarray(SQUARE, np.float32)
    world = sphrect.World(medium=sphrect.Medium(sigma_s=(0.3,) * 3, sigma_a=(0.1,) * 3, g=0.2) if medium else None)
    mesh_scene = sphrect.Scene(camera=cam, meshes=[ground(), emissive_mesh(v, [[0, 1, 2], [0, 2, 3]])],
                               materials=materials(), world=world)
    # The rectangle as RectangleOfPair reads it: corner at the first triangle's unshared vertex.
    rect = sphrect.RectLight(corner=tuple(v[1]), edge_x=tuple(v[2] - v[1]), edge_y=tuple(v[0] - v[1]),
                             radiance=(RADIANCE,) * 3, two_sided=True)
    rect_scene = sphrect.Scene(camera=cam, meshes=[ground()], lights=[rect], materials=materials(), world=world)
    a = sphrect.Renderer(mesh_scene, techniques=ALL_TECHNIQUES, mis=mis, seed=3, bsdf_samples_on_diffuse=True)
    b = sphrect.Renderer(rect_scene, techniques=ALL_TECHNIQUES, mis=mis, seed=3, bsdf_samples_on_diffuse=True)
    assert a.render(16) and b.render(16)
    for t in ALL_TECHNIQUES:
        x, y = a.image(t)[..., :3], b.image(t)[..., :3]
        assert y.max() > 0.1
        assert np.abs(x - y).max() <= 2e-4 * y.max(), f"{mis}/{t}: {np.abs(x - y).max()}"


def test_emissive_square_against_polygon_formula():
    cam = top_camera(height_above=0.5)
    scene = sphrect.Scene(camera=cam, meshes=[ground(), emissive_mesh(SQUARE, [[0, 1, 2], [0, 2, 3]])],
                          materials=materials())
    expected = expected_plane_image(cam, ALBEDO, lambda P: RADIANCE * polygon_irradiance(P, (0, 0, 1), SQUARE))
    for mis in sphrect.mis_modes:
        reps = replicate_images(scene, ALL_TECHNIQUES, REPLICATES, SAMPLES, mis=mis)
        for t in ALL_TECHNIQUES:
            ok, p_min, alpha = pixel_t_test(reps[t], expected, FAMILY_ALPHA / (3 * len(ALL_TECHNIQUES)))
            assert ok, f"square/{mis}/{t}: worst p = {p_min:.3g} < {alpha:.3g}"


@pytest.mark.parametrize("mis", sphrect.mis_modes)
def test_emissive_triangle_against_polygon_formula(mis):
    """One tilted emissive triangle: spherical-triangle sampling (solid-angle techniques) and area
    sampling (`area`), with MIS through BSDF rays that find the triangle through Embree."""
    cam = top_camera(height_above=0.5)
    scene = sphrect.Scene(camera=cam, meshes=[ground(), emissive_mesh(TRIANGLE, [[0, 1, 2]])], materials=materials())
    assert build_native_scene(scene)[0].num_area_lights == 1
    expected = expected_plane_image(cam, ALBEDO, lambda P: RADIANCE * polygon_irradiance(P, (0, 0, 1), TRIANGLE))
    assert expected.max() > 0.05
    reps = replicate_images(scene, ALL_TECHNIQUES, REPLICATES, SAMPLES, mis=mis)
    for t in ALL_TECHNIQUES:
        ok, p_min, alpha = pixel_t_test(reps[t], expected, FAMILY_ALPHA / len(ALL_TECHNIQUES))
        rel = np.abs(reps[t].mean(0) - expected).max() / expected.max()
        assert ok, f"triangle/{mis}/{t}: worst p = {p_min:.3g} < {alpha:.3g} (max rel. error {rel:.3g})"


def test_emissive_triangle_hard_cases_on_plane():
    """A tiny triangle (1e-3 across) and a distant one (10^4 away, radiance scaled by 10^8), and one
    standing on the plane (grazing for the points near its foot): unbiased for every technique."""
    tiny = np.array([[0, 0, 0.3], [1e-3, 0, 0.3], [0, 1e-3, 0.3]])
    distant = np.array([[-0.5, -0.5, 1e4], [0.5, -0.3, 1e4], [0.0, 0.5, 1e4]])
    standing = np.array([[0.1, -0.6, 1e-3], [0.1, 0.6, 1e-3], [0.1, 0.0, 0.8]])
    cam = top_camera(height_above=0.2)
    for name, verts, le in (("tiny", tiny, 1e6), ("distant", distant, 1e8), ("standing", standing, 1.0)):
        scene = sphrect.Scene(camera=cam, meshes=[ground(), emissive_mesh(verts, [[0, 1, 2]])],
                              materials=materials(le))
        expected = expected_plane_image(cam, ALBEDO, lambda P: le * polygon_irradiance(P, (0, 0, 1), verts))
        reps = replicate_images(scene, ALL_TECHNIQUES, REPLICATES, SAMPLES, mis="power")
        for t in ALL_TECHNIQUES:
            ok, p_min, alpha = pixel_t_test(reps[t], expected, FAMILY_ALPHA / (3 * len(ALL_TECHNIQUES)))
            assert ok, f"{name}/{t}: worst p = {p_min:.3g} < {alpha:.3g}"


def test_camera_sees_emission_once():
    """A camera looking at the emissive square sees its radiance (both sides), not twice."""
    for z in (1.0, -1.0):  # above and below the camera's view direction: front and back
        cam = sphrect.Camera(width=8, height=8, type="orthographic", ortho_scale=0.4,
                             to_world=[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, z, 3 * z], [0, 0, 0, 1]])
        scene = sphrect.Scene(camera=cam, meshes=[emissive_mesh(SQUARE, [[0, 1, 2], [0, 2, 3]])],
                              materials=materials())
        r = sphrect.Renderer(scene, techniques=["rectangle"])
        assert r.render(4)
        np.testing.assert_allclose(r.image("rectangle")[..., :3], RADIANCE, rtol=1e-6)


def test_bad_emissive_input():
    cam = top_camera()
    # Degenerate triangles: skipped and counted in one warning; the good one still lights the plane.
    verts = [[0, 0, 1], [1, 0, 1], [0, 1, 1], [2, 2, 1], [2, 2, 1], [3, 3, 1]]
    scene = sphrect.Scene(camera=cam, meshes=[ground(), emissive_mesh(verts, [[0, 1, 2], [3, 4, 5], [3, 3, 3]])],
                          materials=materials())
    with pytest.warns(RuntimeWarning, match="2 emissive triangles with zero area"):
        r = sphrect.Renderer(scene)
    assert r.render(4) and r.image("rectangle")[..., 0].max() > 0
    # NaN vertices: a clear error (the mesh's vertex check).
    bad = emissive_mesh([[0, 0, 1], [np.nan, 0, 1], [0, 1, 1]], [[0, 1, 2]])
    with pytest.raises(ValueError, match="not finite"):
        sphrect.Renderer(sphrect.Scene(camera=cam, meshes=[ground(), bad], materials=materials()))
    # Negative emission: rejected by the renderer (the exporter clamps negative strengths to 0 with a warning).
    with pytest.raises(ValueError, match="emission must be finite and non-negative"):
        sphrect.Renderer(sphrect.Scene(camera=cam, meshes=[ground(), emissive_mesh(TRIANGLE, [[0, 1, 2]])],
                                       materials=materials(-1.0)))


def test_coinciding_emissive_triangles():
    """Ten copies of one triangle: a warning names them; without MIS the plane receives ten times the light
    (each is an emitter); with MIS, a BSDF ray finds only the first of coincident surfaces (as in any ray
    tracer), so the image is finite and between one and ten times the single light's."""
    cam = top_camera(height_above=0.5)
    one = expected_plane_image(cam, ALBEDO, lambda P: RADIANCE * polygon_irradiance(P, (0, 0, 1), TRIANGLE))
    verts = np.tile(np.asarray(TRIANGLE, np.float32), (10, 1))
    mesh = emissive_mesh(verts, np.arange(30).reshape(10, 3))
    scene = sphrect.Scene(camera=cam, meshes=[ground(), mesh], materials=materials())
    with pytest.warns(RuntimeWarning, match="9 emissive triangles coincide with another"):
        r = sphrect.Renderer(scene, techniques=["rectangle"], mis="none", seed=1)
    assert r.render(64)
    img = r.image("rectangle")[..., 0]
    np.testing.assert_allclose(img.mean(), 10 * one.mean(), rtol=0.02)
    with pytest.warns(RuntimeWarning, match="coincide"):  # (BSDF samples on the diffuse plane: MIS at work)
        r = sphrect.Renderer(scene, techniques=["rectangle"], mis="power", bsdf_samples_on_diffuse=True, seed=1)
    assert r.render(16)
    img = r.image("rectangle")[..., 0]
    assert np.isfinite(img).all() and one.mean() < img.mean() < 10 * one.mean()


def test_emission_round_trips_through_the_file(tmp_path):
    scene = sphrect.Scene(camera=top_camera(), meshes=[ground()], materials=materials())
    path = str(tmp_path / "s.sphrect.npz")
    sphrect.save_scene(scene, path)
    assert tuple(sphrect.load_scene(path).materials[1].emission) == (RADIANCE,) * 3


def test_version_1_files_load_without_emission(tmp_path):
    """A version-1 file (materials without 'emission') loads with emission 0."""
    scene = sphrect.Scene(camera=top_camera(), meshes=[ground()], materials=materials())
    path = str(tmp_path / "v2.sphrect.npz")
    sphrect.save_scene(scene, path)
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    meta = json.loads(bytes(arrays["scene.json"]).decode())
    meta["version"] = 1
    for m in meta["materials"]:
        del m["emission"]
    arrays["scene.json"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    old = str(tmp_path / "v1.sphrect.npz")
    np.savez(old, **arrays)
    assert all(m.emission == (0.0, 0.0, 0.0) for m in sphrect.load_scene(old).materials)


@pytest.mark.parametrize("mis", sphrect.mis_modes)
def test_emissive_triangle_with_a_rectangle_light(mis):
    """Light selection by power over both kinds: an analytic rectangle light (3x the triangle's radiance)
    and an emissive triangle, against the sum of their polygon formulas.  The rectangle lies below the
    triangle (which, being geometry, would otherwise shadow it; analytic lights cast no shadow)."""
    cam = top_camera(height_above=0.5)
    rect = sphrect.RectLight(corner=(-0.9, -0.9, 0.7), edge_x=(0.5, 0, 0), edge_y=(0, 0.4, 0),
                             radiance=(3 * RADIANCE,) * 3, two_sided=True, visible=False)
    rect_verts = [[-0.9, -0.9, 0.7], [-0.4, -0.9, 0.7], [-0.4, -0.5, 0.7], [-0.9, -0.5, 0.7]]
    scene = sphrect.Scene(camera=cam, meshes=[ground(), emissive_mesh(TRIANGLE, [[0, 1, 2]])], lights=[rect],
                          materials=materials())
    expected = expected_plane_image(cam, ALBEDO, lambda P: RADIANCE * polygon_irradiance(P, (0, 0, 1), TRIANGLE)
                                    + 3 * RADIANCE * polygon_irradiance(P, (0, 0, 1), rect_verts))
    reps = replicate_images(scene, ALL_TECHNIQUES, REPLICATES, SAMPLES, mis=mis)
    for t in ALL_TECHNIQUES:
        ok, p_min, alpha = pixel_t_test(reps[t], expected, FAMILY_ALPHA / len(ALL_TECHNIQUES))
        assert ok, f"mixed/{mis}/{t}: worst p = {p_min:.3g} < {alpha:.3g}"
