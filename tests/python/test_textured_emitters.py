"""Textured emitters: an emissive mesh whose Material.textures["emission"] drives its colour, evaluated per point by
camera rays, BSDF rays and light samples; a textured rectangle sampled by its blocks' power and solid angle
(core/rectangle_blocks.h, sphrect.sample_rectangle_blocks).

Statistical tests use fixed seeds.  The chi-square test of the block sampler fails falsely with probability 1e-3
(chi2.py's Sidak share); the per-pixel t-tests (render_testing.pixel_t_test) with FAMILY_ALPHA = 1e-4 over all their
pixels and configurations."""
import numpy as np
import pytest

import sphrect
from chi2 import LightConfig, adaptive_cell_integrals, grid_edges, light_coordinates, pearson, sidak_alpha
from render_testing import (expected_plane_image, pixel_t_test, plane_mesh, polygon_irradiance, replicate_images,
                            save_as_older_version, top_camera)
from sphrect.render import build_native_scene

FAMILY_ALPHA = 1e-4
ALBEDO = 0.5
RADIANCE = 2.0
SQUARE = [[-0.5, -0.4, 1], [0.6, -0.4, 1], [0.6, 0.5, 1], [-0.5, 0.5, 1]]
UVS = [[0, 0], [1, 0], [1, 1], [0, 1]]
# The emitter's left half in uv (u < 1/2): what a 2 x 1 image, white then black, read 'closest', lights.
LEFT_HALF = [[-0.5, -0.4, 1], [0.05, -0.4, 1], [0.05, 0.5, 1], [-0.5, 0.5, 1]]


def ground():
    g = plane_mesh()
    g.material_ids = np.zeros(2, np.int32)
    return g


def textured_scene(pixels, vertices=SQUARE, uvs=UVS, triangles=((0, 1, 2), (0, 2, 3)), interpolation="closest",
                   cam=None, colorspace="linear"):
    panel = sphrect.Mesh(vertices=np.asarray(vertices, np.float32), triangles=np.asarray(triangles, np.int32),
                         uvs=np.asarray(uvs, np.float32), material_ids=np.ones(len(triangles), np.int32),
                         name="panel")
    lookup = sphrect.TextureLookup(texture=0, interpolation=interpolation)
    materials = [sphrect.Material(name="ground", base_color=(ALBEDO,) * 3),
                 sphrect.Material(name="panel", base_color=(0, 0, 0), emission=(RADIANCE,) * 3,
                                  textures={"emission": lookup})]
    texture = sphrect.Texture(name="image", pixels=np.asarray(pixels, np.float32), colorspace=colorspace)
    return sphrect.Scene(camera=cam or top_camera(height_above=0.5), meshes=[ground(), panel], materials=materials,
                         textures=[texture])


HALF_BLACK = [[[1, 1, 1], [0, 0, 0]]]


def test_a_textured_quad_is_one_rectangle_light_and_textured():
    native, warnings = build_native_scene(textured_scene(HALF_BLACK))
    assert native.num_area_lights == 1 and not warnings
    assert {"emissive_meshes", "textures"} <= set(native.features)


# Its right half at a quarter of the left: every block keeps a power of its own, so that the per-pixel t-test sees
# the block sampler's usual noise (a black block is chosen with the floor's ~1% probability only: a rare event that
# 12 replicates of 32 light samples cannot average, which test_half_black_texture_halves_the_irradiance measures
# instead).
TWO_TONE = [[[1, 1, 1], [0.25, 0.25, 0.25]]]
RIGHT_HALF = [[0.05, -0.4, 1], [0.6, -0.4, 1], [0.6, 0.5, 1], [0.05, 0.5, 1]]


@pytest.mark.parametrize("blocks", [True, False])
@pytest.mark.parametrize("technique", ["rectangle", "area", "triangles"])
def test_two_tone_texture_against_closed_form(technique, blocks):
    """A quad whose image is white on its left half and 1/4 on its right lights the plane as its two halves of those
    radiances do (Lambert's polygon formula)."""
    cam = top_camera(height_above=0.5)
    scene = textured_scene(TWO_TONE, cam=cam)
    expected = expected_plane_image(cam, ALBEDO, lambda P: RADIANCE * (polygon_irradiance(P, (0, 0, 1), LEFT_HALF) +
                                                                         0.25 * polygon_irradiance(P, (0, 0, 1),
                                                                                                   RIGHT_HALF)))
    reps = replicate_images(scene, [technique], 12, 16, emission_blocks=blocks)
    ok, p_min, alpha = pixel_t_test(reps[technique], expected, FAMILY_ALPHA / 6)
    assert ok, f"{technique}, blocks {blocks}: worst p = {p_min:.3g} < {alpha:.3g}"


@pytest.mark.parametrize("blocks", [True, False])
def test_half_black_texture_halves_the_irradiance(blocks):
    """White on its left half, black on its right: the plane is lit exactly as by the left half alone; at the point
    symmetric under the quad (its centre's foot), half the untextured quad's irradiance.  The image's mean and the
    centre pixel within 0.5% of the closed form at 1024 samples (their noise is ~0.1%; a fixed seed)."""
    cam = top_camera(width=11, height=11, half=0.55, height_above=0.5)
    shift = np.array([0.05, 0.05, 0.0])  # the quad centred over the origin, under the centre pixel
    square, left = np.asarray(SQUARE) - shift, np.asarray(LEFT_HALF) - shift
    scene = textured_scene(HALF_BLACK, vertices=square, cam=cam)
    centre = np.zeros((1, 3))
    e_half = polygon_irradiance(centre, (0, 0, 1), left)[0]
    assert e_half == pytest.approx(0.5 * polygon_irradiance(centre, (0, 0, 1), square)[0], rel=1e-12)
    expected = expected_plane_image(cam, ALBEDO, lambda P: RADIANCE * polygon_irradiance(P, (0, 0, 1), left))
    r = sphrect.Renderer(scene, techniques=["rectangle"], emission_blocks=blocks, seed=5)
    assert r.render(1024)
    image = r.image("rectangle")[..., 0]
    assert image.mean() == pytest.approx(expected.mean(), rel=5e-3)
    assert image[5, 5] == pytest.approx(expected[5, 5], rel=5e-3)
    assert expected[5, 5] == pytest.approx(ALBEDO / np.pi * RADIANCE * e_half, rel=5e-3)  # the pixel's average


@pytest.mark.slow
@pytest.mark.parametrize("light_selection", ["power", "tree"])
@pytest.mark.parametrize("mis", ["power", "balance", "none"])
def test_mis_and_selection_agree_with_the_closed_form(mis, light_selection):
    """BSDF rays that hit the textured emitter (MIS, on the diffuse hits too) read its image at their hit; with a
    second, untextured light so that selection matters."""
    cam = top_camera(height_above=0.5)
    scene = textured_scene(HALF_BLACK, cam=cam)
    other = [[0.8, -0.3, 0.9], [1.2, -0.3, 0.9], [1.2, 0.1, 0.9], [0.8, 0.1, 0.9]]
    scene.lights.append(sphrect.RectLight(corner=tuple(other[0]), edge_x=(0.4, 0, 0), edge_y=(0, 0.4, 0),
                                          radiance=(0.7,) * 3, two_sided=True))
    expected = expected_plane_image(cam, ALBEDO, lambda P: RADIANCE * polygon_irradiance(P, (0, 0, 1), LEFT_HALF) +
                                    0.7 * polygon_irradiance(P, (0, 0, 1), other))
    reps = replicate_images(scene, ["rectangle"], 12, 16, mis=mis, light_selection=light_selection,
                            bsdf_samples_on_diffuse=True)
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, FAMILY_ALPHA / 6)
    assert ok, f"{mis}/{light_selection}: worst p = {p_min:.3g} < {alpha:.3g}"


def test_camera_sees_the_texels():
    """A camera looking up at the emitter (a 4 x 4 image, 'closest', filling the view) sees each texel's radiance."""
    rng = np.random.default_rng(3)
    pixels = rng.uniform(0.1, 1.0, (4, 4, 3)).astype(np.float32)
    # Camera at z = 0.5 looking up (+Z) at the square [-0.5, 0.5]^2 of the plane z = 1.
    cam = sphrect.Camera(width=8, height=8, type="orthographic", ortho_scale=1.0,
                         to_world=[[1, 0, 0, 0], [0, -1, 0, 0], [0, 0, -1, 0.5], [0, 0, 0, 1]])
    square = [[-0.5, -0.5, 1], [0.5, -0.5, 1], [0.5, 0.5, 1], [-0.5, 0.5, 1]]
    scene = textured_scene(pixels, vertices=square, cam=cam)
    r = sphrect.Renderer(scene, techniques=["rectangle"], seed=1)
    assert r.render(4)
    image = r.image("rectangle")[..., :3]
    # Image row 0 is the top (+y, as the camera's up is -y of the world... read through the camera).
    for py in range(8):
        for px in range(8):
            ray_x = -0.5 + (px + 0.5) / 8
            ray_y = 0.5 - (py + 0.5) / 8
            ray_y = -ray_y  # the camera's y axis is the world's -y
            texel = pixels[int((ray_y + 0.5) * 4), int((ray_x + 0.5) * 4)]
            np.testing.assert_allclose(image[py, px], RADIANCE * texel, rtol=1e-5)


@pytest.mark.parametrize("technique", ["rectangle", "rectangle_projected"])
def test_blocks_and_whole_light_sampling_converge_to_the_same_image(technique):
    """A window with bars (a mostly dark image, 'linear'): the block sampler and sampling the whole light by the
    technique are both unbiased -- their images agree within their noise (per-pixel t-test of the difference)."""
    bars = np.zeros((16, 16, 3), np.float32)
    bars[2:14, 2:5] = bars[2:14, 11:14] = 1.0
    cam = top_camera(width=8, height=8, height_above=0.5)
    scene = textured_scene(bars, cam=cam, interpolation="linear")
    a = replicate_images(scene, [technique], 12, 16, emission_blocks=True)[technique]
    b = replicate_images(scene, [technique], 12, 16, emission_blocks=False)[technique]
    ok, p_min, alpha = pixel_t_test(a - b, np.zeros(a.shape[1:]), FAMILY_ALPHA / 2, rel_tol=0)
    assert ok, f"{technique}: worst p = {p_min:.3g} < {alpha:.3g}"
    assert a.mean() > 1e-3


def test_block_sampler_chi_square():
    """sphrect.sample_rectangle_blocks against its own pdf (rectangle_blocks_pdf) through chi2.py's cells and
    Pearson statistic, on lights seen from above, from the side and grazing; and a wrong pdf fails."""
    weights = np.array([[0.0, 1.0, 3.0], [0.5, 0.0, 2.0]])  # radiance of 3 x 2 blocks, two of them black
    configs = [LightConfig("above", (0.2, 0.3, 1.0), (-0.5, -0.5, 0.0), (1.2, 0.0, 0.0), (0.0, 0.8, 0.0)),
               LightConfig("side", (2.0, 0.1, 0.4), (-0.5, -0.5, 0.0), (1.2, 0.0, 0.0), (0.0, 0.8, 0.0)),
               LightConfig("grazing", (0.3, 0.2, 1e-3), (-0.5, -0.5, 0.0), (1.2, 0.0, 0.0), (0.0, 0.8, 0.0))]
    alpha = sidak_alpha(1e-3, len(configs))

    def run(config, factor=1.0):
        origin, corner, ex, ey = config.light_args()
        # Block edges are cell edges too, so the pdf is smooth within every cell.
        s_edges = np.union1d(grid_edges(config, 24, 0), np.linspace(0, 1, 4))
        t_edges = np.union1d(grid_edges(config, 24, 1), np.linspace(0, 1, 3))
        area = np.linalg.norm(np.cross(ex, ey))
        h = abs(np.dot(np.cross(ex, ey) / area, origin - corner))

        def integrand(s, t):
            P = corner + s[:, None] * ex + t[:, None] * ey
            pdf = sphrect.rectangle_blocks_pdf(origin, corner, ex, ey, weights, P).astype(np.float64)
            pdf = pdf * np.where(s < 1 / 3, factor, 1.0)
            return pdf * h * area / np.linalg.norm(P - origin, axis=1) ** 3

        probability = adaptive_cell_integrals(integrand, s_edges, t_edges)
        n = 300_000
        uv = sphrect.pattern("independent", n, seed=7)
        points, pdf = sphrect.sample_rectangle_blocks(origin, corner, ex, ey, weights, uv)
        valid = pdf > 0
        s, t = light_coordinates(points[valid], config)
        observed, _, _ = np.histogram2d(np.clip(s, 0, 1), np.clip(t, 0, 1), bins=[s_edges, t_edges])
        return pearson(observed, probability, int(np.count_nonzero(~valid)), n)

    for config in configs:
        statistic, dof, p_value, _, worst = run(config)
        assert p_value >= alpha, f"{config}: chi2 {statistic:.1f} / {dof} dof, p = {p_value:.3g}; {worst}"
    # A pdf 10% off on the first column of blocks is detected.
    assert run(configs[0], factor=1.1)[2] < alpha


def test_block_sampler_with_one_block_is_the_rectangle_map():
    o, corner, ex, ey = (0.2, 0.3, 1.0), (-0.5, -0.5, 0.0), (1.2, 0.0, 0.0), (0.0, 0.8, 0.0)
    uv = sphrect.pattern("independent", 1000, seed=2)
    p_blocks, pdf_blocks = sphrect.sample_rectangle_blocks(o, corner, ex, ey, [[1.0]], uv)
    p_map, pdf_map = sphrect.sample("rectangle", o, corner, ex, ey, uv)
    np.testing.assert_allclose(p_blocks, p_map, atol=1e-6)
    np.testing.assert_allclose(pdf_blocks, pdf_map, rtol=1e-6)


def test_emission_texture_round_trips_through_the_file(tmp_path):
    scene = textured_scene(HALF_BLACK)
    path = tmp_path / "t.sphrect.npz"
    sphrect.save_scene(scene, path)
    loaded = sphrect.load_scene(path)
    assert loaded.materials[1].textures["emission"] == scene.materials[1].textures["emission"]
    assert tuple(loaded.materials[1].emission) == scene.materials[1].emission
    a = sphrect.Renderer(scene, seed=1)
    b = sphrect.Renderer(loaded, seed=1)
    assert a.render(4) and b.render(4)
    np.testing.assert_array_equal(a.image("rectangle"), b.image("rectangle"))
    # A version-11 file (before emission textures) loads as before: constant emission.
    old = tmp_path / "old.sphrect.npz"
    save_as_older_version(path, old, 11, lambda meta: meta["materials"][1]["textures"].pop("emission"))
    assert "emission" not in sphrect.load_scene(old).materials[1].textures


def test_emission_texture_in_a_mix_layer_is_refused():
    scene = textured_scene(HALF_BLACK)
    textured = scene.materials[1]
    scene.materials[1] = sphrect.Material(name="mix", kind="mix", layers=[sphrect.MaterialLayer(1.0, textured)])
    with pytest.raises(ValueError, match="emission texture"):
        build_native_scene(scene)
    # On the mix itself it is taken, but not beside emitting layers.
    scene.materials[1] = sphrect.Material(name="mix", kind="mix", emission=(RADIANCE,) * 3,
                                          textures={"emission": textured.textures["emission"]},
                                          layers=[sphrect.MaterialLayer(1.0, sphrect.Material())])
    build_native_scene(scene)
    scene.materials[1].layers[0].material.emission = (1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="emitting layers"):
        build_native_scene(scene)
