"""Pixel filters (Camera.pixel_filter, filter_width; render/pixel_filter.h): the image of a sharp corner is its
convolution with the separable filter, the 1-px box is the renderer's image before filters, bad settings are
refused and the settings survive the scene file.

Settings: an emissive corner and a rectangle light's corner under an orthographic camera against their
convolution with box 1 and 2, Gaussian 0.7 and 1.5, Blackman-Harris 1.5 and 3, per pixel: t-test over 16
replicates x 256 spp, Sidak family-wise false-failure rate 1e-3 per case, allowing the table's 2/1023."""
import dataclasses
import json

import numpy as np
import pytest
from scipy import integrate, stats

import sphrect
from chi2 import sidak_alpha
from render_testing import top_camera

W = H = 16
EDGE_X, EDGE_Y = 7.3, 8.6  # film pixels: the emitter covers film x > EDGE_X and y < EDGE_Y (its upper-right quadrant)
# The table holds the inverse CDF at 1023 intervals of equal mass, linear between them: the image is the exact
# convolution to within one interval's mass in x plus one in y.
TABLE_TOLERANCE = 2 / 1023


def filter_cdf(name, width):
    """The filter's CDF over offsets from the pixel centre (pixels), by quadrature of Cycles' function."""
    if name == "box":
        return lambda v: np.clip(v / width + 0.5, 0.0, 1.0)
    if name == "gaussian":
        radius, f = 1.5 * width, lambda v: np.exp(-2.0 * (2.0 * v / width) ** 2)
    else:
        radius = width
        f = lambda v: (0.35875 - 0.48829 * np.cos(2 * np.pi * (v / (2 * width) + 0.5))
                       + 0.14128 * np.cos(4 * np.pi * (v / (2 * width) + 0.5))
                       - 0.01168 * np.cos(6 * np.pi * (v / (2 * width) + 0.5)))
    total = integrate.quad(f, -radius, radius, epsabs=1e-13)[0]
    return np.vectorize(lambda v: 0.0 if v <= -radius else 1.0 if v >= radius else
                        integrate.quad(f, -radius, v, epsabs=1e-13)[0] / total)


def expected_corner(name, width):
    """Per pixel: P(its sample's film x > EDGE_X) P(film y < EDGE_Y), the sample at the pixel centre plus the
    filter's offset in x and, independently, in y."""
    cdf = filter_cdf(name, width)
    centres = np.arange(W) + 0.5
    right = 1.0 - cdf(EDGE_X - centres)        # [W]
    above = cdf(EDGE_Y - (np.arange(H) + 0.5))  # [H]
    return above[:, None] * right[None, :]


def corner_scene(emitter, pixel_filter=None, filter_width=None):
    """An orthographic top camera over a corner of radiance 1 (an emissive mesh or a rectangle light facing the
    camera), nothing else: every camera sample sees 1 or 0."""
    cam = top_camera(W, H, half=1.0)
    if pixel_filter is not None:
        cam.pixel_filter = pixel_filter
    if filter_width is not None:
        cam.filter_width = filter_width
    hw, hh, _, _ = cam.image_plane()
    x0, y0 = (2 * EDGE_X / W - 1) * hw, (1 - 2 * EDGE_Y / H) * hh
    scene = sphrect.Scene(camera=cam, materials=[sphrect.Material(base_color=(0, 0, 0), emission=(1, 1, 1))])
    if emitter == "mesh":
        v = np.array([[x0, y0, 0], [5, y0, 0], [5, 5, 0], [x0, 5, 0]], np.float32)
        scene.meshes.append(sphrect.Mesh(vertices=v, triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32)))
    else:  # one-sided, emitting up (+Z) to the camera; in pixels it partly covers, Exact Light Edges would apply
        scene.lights.append(sphrect.RectLight(corner=(x0, y0, 0), edge_x=(5 - x0, 0, 0), edge_y=(0, 5 - y0, 0),
                                              radiance=(1, 1, 1)))
    return scene


def replicates(scene, count=16, samples=256):
    images = []
    for rep in range(count):
        r = sphrect.Renderer(scene, techniques="rectangle", seed=500 + rep)
        r.render(samples)
        images.append(r.image("rectangle")[..., 0].astype(np.float64))
    return np.array(images)


def agrees_with(reps, expected, family_alpha=1e-3):
    """Per-pixel two-sided t-test of the replicate means against `expected`, allowing TABLE_TOLERANCE; the
    family-wise false failure rate over the pixels is family_alpha (Sidak).  Returns (passed, worst p)."""
    k = reps.shape[0]
    excess = np.maximum(np.abs(reps.mean(axis=0) - expected) - TABLE_TOLERANCE, 0.0)
    se = np.sqrt(reps.var(axis=0, ddof=1) / k) + 1e-9
    p = 2 * stats.t.sf(excess / se, df=k - 1)
    return bool(p.min() >= sidak_alpha(family_alpha, expected.size)), float(p.min())


@pytest.mark.parametrize("emitter", ["mesh", "rect_light"])
@pytest.mark.parametrize("pixel_filter,width", [("blackman_harris", 1.5), ("gaussian", 1.5), ("box", 1.0),
                                                ("box", 2.0), ("blackman_harris", 3.0), ("gaussian", 0.7)])
@pytest.mark.slow
def test_corner_is_its_convolution_with_the_filter(emitter, pixel_filter, width):
    # 16 replicates x 256 samples; false failure rate 1e-3 per case.  The rectangle light checks that Exact Light
    # Edges (the 1-px box's coverage) is off for other filters.
    reps = replicates(corner_scene(emitter, pixel_filter, width))
    passed, p = agrees_with(reps, expected_corner(pixel_filter, width))
    assert passed, f"{pixel_filter} {width}: worst p {p:.3g}"


def test_the_comparison_can_fail():
    """The box's image is not Blackman-Harris 1.5's convolution, nor is Gaussian 1.5's."""
    for rendered in ("box", "gaussian"):
        width = 1.0 if rendered == "box" else 1.5
        reps = replicates(corner_scene("mesh", rendered, width), count=8, samples=128)
        passed, _ = agrees_with(reps, expected_corner("blackman_harris", 1.5))
        assert not passed, rendered


def test_box_of_width_one_is_the_image_without_filters():
    """Camera's default is the 1-px box: setting it explicitly changes no bit (the pattern point is the pixel
    jitter, and Exact Light Edges still applies)."""
    for emitter in ("mesh", "rect_light"):
        default = corner_scene(emitter)
        explicit = corner_scene(emitter, "box", 1.0)
        assert (default.camera.pixel_filter, default.camera.filter_width) == ("box", 1.0)
        a, b = (sphrect.render(s, samples=16, techniques="rectangle", seed=3)["rectangle"] for s in (default, explicit))
        np.testing.assert_array_equal(a, b)


def test_box_light_edges_stay_exact_and_other_filters_estimate_them():
    """With the 1-px box the rectangle light's partly covered pixels are exact (no noise: Exact Light Edges);
    with another filter, estimated from the samples (noise across seeds)."""
    def spread(scene):
        return replicates(scene, count=3, samples=8).std(axis=0).max()
    assert spread(corner_scene("rect_light")) < 1e-6
    assert spread(corner_scene("rect_light", "blackman_harris", 1.5)) > 1e-3


@pytest.mark.parametrize("field,value,message", [
    ("pixel_filter", "mitchell", "camera pixel_filter must be 'box', 'gaussian' or 'blackman_harris', got 'mitchell'"),
    ("pixel_filter", "BOX", "pixel_filter must be"),
    ("filter_width", 0.0, "filter_width must be a number of pixels in [0.01, 10]"),
    ("filter_width", -1.5, "filter_width must be"),
    ("filter_width", 10.5, "filter_width must be"),
    ("filter_width", float("nan"), "filter_width must be"),
    ("filter_width", "1.5", "filter_width must be"),
    ("filter_width", True, "filter_width must be"),
])
def test_bad_filter_settings_are_refused(field, value, message):
    scene = corner_scene("mesh")
    setattr(scene.camera, field, value)
    with pytest.raises(ValueError, match=message.replace("[", r"\[").replace("]", r"\]")):
        sphrect.Renderer(scene, techniques="rectangle")


def test_limits_are_accepted():
    for width in (sphrect.MIN_PIXEL_FILTER_WIDTH, 0.01, 10.0):
        sphrect.Renderer(corner_scene("mesh", "gaussian", width), techniques="rectangle")


def test_native_names_are_the_package_names():
    assert sphrect.pixel_filters == ("box", "gaussian", "blackman_harris")
    assert sphrect.scene.PIXEL_FILTERS == tuple(sphrect.pixel_filters)


def test_filter_survives_the_scene_file(tmp_path):
    scene = corner_scene("mesh", "blackman_harris", 1.5)
    path = str(tmp_path / "s.sphrect.npz")
    sphrect.save_scene(scene, path)
    loaded = sphrect.load_scene(path)
    assert (loaded.camera.pixel_filter, loaded.camera.filter_width) == ("blackman_harris", 1.5)
    np.testing.assert_array_equal(sphrect.render(loaded, samples=8, techniques="rectangle", seed=2)["rectangle"],
                                  sphrect.render(scene, samples=8, techniques="rectangle", seed=2)["rectangle"])


def test_files_before_version_8_load_as_the_unit_box(tmp_path):
    scene = corner_scene("mesh")
    path = str(tmp_path / "old.sphrect.npz")
    sphrect.save_scene(scene, path)
    with np.load(path) as f:
        arrays = {name: f[name] for name in f.files}
    meta = json.loads(bytes(arrays["scene.json"]).decode("utf-8"))
    meta["version"] = 7
    for key in ("pixel_filter", "filter_width"):
        del meta["camera"][key]
    arrays["scene.json"] = np.frombuffer(json.dumps(meta).encode("utf-8"), dtype=np.uint8)
    np.savez(path, **arrays)
    loaded = sphrect.load_scene(path)
    assert (loaded.camera.pixel_filter, loaded.camera.filter_width) == ("box", 1.0)
    assert dataclasses.asdict(loaded.camera) == dataclasses.asdict(scene.camera)
