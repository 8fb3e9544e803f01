"""Pixel filters against Cycles 3.4, pixel by pixel (no block averaging): an emissive corner seen by an orthographic
camera from above, no lights, rendered by SPHRECT and by Cycles (through the study's peer, cycles_peer.py, which
takes the scene's SPHRECT filter) with Blackman-Harris 1.5, Gaussian 1.5 and the box; both also against the corner's
convolution with the filter.  The Film panel's settings, their defaults (Cycles') and the exporter."""
import bpy
import numpy as np
import pytest

from conftest import addon_module, builders, export, render, set_resolution
from test_cycles_parity import cycles_peer

WIDTH, HEIGHT, SAMPLES = 24, 16, 1024
# Film pixels: the emitter covers film x > EDGE_X and y < EDGE_Y, 0.45 and 0.2 px from the nearest pixel centres,
# where the filters differ most (the convolutions differ by up to 0.10 between box 1 and Blackman-Harris 1.5,
# 0.04 between Gaussian 1.5 and Blackman-Harris 1.5).
EDGE_X, EDGE_Y = 9.05, 7.7
# Both images hold the noise of 1024 stratified samples of a 0-or-1 radiance and their filter tables'
# discretisation (1e-3): measured up to 0.002 per pixel between the renderers, 0.002 to the convolution.
PIXEL_TOLERANCE = 0.006
FILTERS = {"blackman_harris": 1.5, "gaussian": 1.5, "box": 1.0}


def filter_cdf(name, width):
    """CDF of the offset from the pixel centre (pixels) under Cycles' filter function (scene/film.cpp)."""
    if name == "box":
        return lambda v: np.clip(v / width + 0.5, 0.0, 1.0)
    radius = 1.5 * width if name == "gaussian" else width
    v = np.linspace(-radius, radius, 20001)
    if name == "gaussian":
        f = np.exp(-2.0 * (2.0 * v / width) ** 2)
    else:
        x = 2 * np.pi * (v / (2 * width) + 0.5)
        f = 0.35875 - 0.48829 * np.cos(x) + 0.14128 * np.cos(2 * x) - 0.01168 * np.cos(3 * x)
    cdf = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(v))])
    return lambda t: np.interp(t, v, cdf / cdf[-1])


def expected_corner(name, width):
    cdf = filter_cdf(name, width)
    right = 1.0 - cdf(EDGE_X - (np.arange(WIDTH) + 0.5))
    above = cdf(EDGE_Y - (np.arange(HEIGHT) + 0.5))
    return above[:, None] * right[None, :]


@pytest.fixture
def corner_scene(empty_scene):
    """An emission-1 plane's corner at film (EDGE_X, EDGE_Y) under an orthographic top camera, 0.1 units a pixel."""
    scene = empty_scene
    set_resolution(scene, WIDTH, HEIGHT)
    cam = scene.camera
    cam.location, cam.rotation_euler = (0.0, 0.0, 5.0), (0.0, 0.0, 0.0)
    cam.data.type, cam.data.ortho_scale = "ORTHO", 0.1 * WIDTH
    x0, y0 = 0.1 * EDGE_X - 0.05 * WIDTH, 0.05 * HEIGHT - 0.1 * EDGE_Y
    builders.mesh_object("Emitter", "plane", builders.emission_material("Emitter", (1.0, 1.0, 1.0), 1.0),
                         location=((x0 + 3) / 2, (y0 + 3) / 2, 0.0), scale=((3 - x0) / 2, (3 - y0) / 2, 1.0))
    bpy.context.view_layer.update()
    return scene


def render_sphrect(scene):
    scene.render.engine = "SPHRECT"
    scene.sphrect.samples, scene.sphrect.passes, scene.sphrect.technique = SAMPLES, 1, "RECTANGLE"
    return render()["images"]["rectangle"][..., 0].astype(np.float64)


def render_cycles_peer(scene, tmp_path):
    """Cycles as the study runs it (cycles_peer.render_direct_lighting: the scene's SPHRECT filter)."""
    args = dict(samples=SAMPLES, seed=0, threads=0, width=WIDTH, height=HEIGHT, time_limit=None,
                npy=str(tmp_path / "cycles.npy"), json=str(tmp_path / "cycles.json"), exr=str(tmp_path / "cycles.exr"))
    cycles_peer().render_direct_lighting(scene, args)
    return np.load(args["npy"])[..., 0].astype(np.float64)


def set_filter(scene, name, width):
    scene.sphrect.pixel_filter, scene.sphrect.filter_width = name.upper(), width
    bpy.context.view_layer.update()  # the exporter reads the evaluated scene


@pytest.mark.parametrize("name", sorted(FILTERS))
def test_edge_matches_cycles_pixel_by_pixel(corner_scene, name, tmp_path):
    set_filter(corner_scene, name, FILTERS[name])
    ours = render_sphrect(corner_scene)
    cycles = render_cycles_peer(corner_scene, tmp_path)
    assert corner_scene.cycles.pixel_filter_type == name.upper()
    expected = expected_corner(name, FILTERS[name])
    difference = np.abs(ours - cycles).max()
    print(f"{name} {FILTERS[name]}: max per-pixel |SPHRECT - Cycles| {difference:.4f}, to the convolution: "
          f"SPHRECT {np.abs(ours - expected).max():.4f}, Cycles {np.abs(cycles - expected).max():.4f}")
    assert difference <= PIXEL_TOLERANCE
    assert np.abs(ours - expected).max() <= PIXEL_TOLERANCE
    assert np.abs(cycles - expected).max() <= PIXEL_TOLERANCE


def test_the_comparison_can_fail(corner_scene, tmp_path):
    """SPHRECT's box and Gaussian 1.5 against Cycles' Blackman-Harris 1.5 (the setting is read for Cycles after
    our renders)."""
    set_filter(corner_scene, "box", 1.0)
    box = render_sphrect(corner_scene)
    set_filter(corner_scene, "gaussian", 1.5)
    gaussian = render_sphrect(corner_scene)
    set_filter(corner_scene, "blackman_harris", 1.5)
    cycles = render_cycles_peer(corner_scene, tmp_path)
    box_difference, gaussian_difference = np.abs(box - cycles).max(), np.abs(gaussian - cycles).max()
    print(f"against Cycles' Blackman-Harris 1.5, max per-pixel difference: box {box_difference:.4f}, "
          f"Gaussian 1.5 {gaussian_difference:.4f}")
    assert box_difference > 10 * PIXEL_TOLERANCE
    assert gaussian_difference > 4 * PIXEL_TOLERANCE


def test_defaults_are_cycles_and_the_exporter_writes_them(corner_scene):
    assert (corner_scene.sphrect.pixel_filter, corner_scene.sphrect.filter_width) == ("BLACKMAN_HARRIS", 1.5)
    camera = export()[0].camera
    assert (camera.pixel_filter, camera.filter_width) == ("blackman_harris", 1.5)
    set_filter(corner_scene, "gaussian", 0.8)
    camera = export()[0].camera
    assert (camera.pixel_filter, camera.filter_width) == ("gaussian", pytest.approx(0.8))
    set_filter(corner_scene, "box", 2.5)  # Cycles renders every box 1 pixel wide
    camera = export()[0].camera
    assert (camera.pixel_filter, camera.filter_width) == ("box", 1.0)


def test_peer_reads_the_setting_or_its_default_without_registration(corner_scene):
    peer = cycles_peer()
    corner_scene.cycles.pixel_filter_type, corner_scene.cycles.filter_width = "BOX", 1.0
    if "sphrect" in corner_scene:
        for key in ("pixel_filter", "filter_width"):
            corner_scene["sphrect"].pop(key, None)
    peer.use_pixel_filter(corner_scene)  # unset: the add-on's default, which the exporter reads too
    assert (corner_scene.cycles.pixel_filter_type, corner_scene.cycles.filter_width) == ("BLACKMAN_HARRIS", 1.5)
    set_filter(corner_scene, "gaussian", 2.0)
    peer.use_pixel_filter(corner_scene)
    assert (corner_scene.cycles.pixel_filter_type, corner_scene.cycles.filter_width) == ("GAUSSIAN", 2.0)


def test_labels_are_the_module_names():
    names = addon_module("names")
    assert tuple(names.PIXEL_FILTER_LABELS) == tuple(names.PIXEL_FILTERS) == tuple(
        addon_module("native").load_sphrect().pixel_filters)


def test_film_panel_is_registered():
    assert hasattr(bpy.types, "RENDER_PT_sphrect_film")
