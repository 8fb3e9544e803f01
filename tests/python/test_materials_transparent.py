"""Transparent BSDF (kind 'transparent') and Principled Alpha (a 'mix' with a white transparent layer): camera and
shadow rays go on through the surface filtered by its colour.  A sheet at z = 1 above a diffuse floor, the light
above both: the floor is seen through the sheet and lit through it, so each channel of the floor's closed-form
image is scaled by the sheet's colour twice.  Per-pixel t-tests over independent replicates, family-wise
false-failure rate 1e-4 per test; the exact identities are deterministic."""
import numpy as np
import pytest

import sphrect
from render_testing import expected_plane_image, pixel_t_test, plane_mesh, polygon_irradiance, replicate_images, \
    top_camera

RADIANCE = 10.0
LIGHT_Z = 2.5
LIGHT_VERTS = [(-0.6, -0.6, LIGHT_Z), (0.6, -0.6, LIGHT_Z), (0.6, 0.6, LIGHT_Z), (-0.6, 0.6, LIGHT_Z)]
FLOOR = (0.7, 0.7, 0.7)
SHEET_Z = 1.0


def light():
    # Emits downwards; invisible to the camera above it.
    return sphrect.RectLight(corner=(-0.6, 0.6, LIGHT_Z), edge_x=(1.2, 0.0, 0.0), edge_y=(0.0, -1.2, 0.0),
                             radiance=(RADIANCE,) * 3, visible=False)


def two_plane_mesh(size, z_sheet):
    floor, sheet = plane_mesh(size), plane_mesh(size, z_sheet)
    return sphrect.Mesh(vertices=np.concatenate([floor.vertices, sheet.vertices]),
                        triangles=np.concatenate([floor.triangles, sheet.triangles + 4]),
                        material_ids=np.array([0, 0, 1, 1], np.int32), name="floor and sheet")


def scene(sheet, sheets=1, **camera):
    meshes = [two_plane_mesh(1.5, SHEET_Z)]
    materials = [sphrect.Material(name="floor", base_color=FLOOR), sheet]
    for k in range(1, sheets):  # more sheets, stacked between the first and the floor
        m = plane_mesh(1.5, SHEET_Z * (1 - k / (sheets + 1)))
        meshes.append(sphrect.Mesh(vertices=m.vertices, triangles=m.triangles,
                                   material_ids=np.array([1, 1], np.int32), name=f"sheet {k}"))
    return sphrect.Scene(camera=top_camera(8, 8, half=1.0, **camera), materials=materials, meshes=meshes,
                         lights=[light()])


def floor_image(cam):
    return expected_plane_image(cam, FLOOR[0], lambda p: RADIANCE * polygon_irradiance(p, (0.0, 0.0, 1.0), LIGHT_VERTS))


def sheet_irradiance_image(cam):
    """The sheet's own Lambertian radiance per unit albedo (its points are the floor's shifted to z = SHEET_Z)."""
    def irradiance(p):
        q = p.copy()
        q[..., 2] = SHEET_Z
        return RADIANCE * polygon_irradiance(q, (0.0, 0.0, 1.0), LIGHT_VERTS)
    return expected_plane_image(cam, 1.0, irradiance)


def render(s, samples=16, seed=3, technique="rectangle", **kw):
    r = sphrect.Renderer(s, techniques=technique, seed=seed, **kw)
    r.render(samples)
    return r.image(technique)


@pytest.mark.parametrize("color", [(1.0, 1.0, 1.0), (0.5, 0.25, 0.9)])
def test_coloured_sheet_filters_the_view_and_the_light(color):
    s = scene(sphrect.Material(kind="transparent", base_color=color))
    cam = s.camera
    img = render(s)
    # The sheet alone (opaque_weight 0): every camera ray goes through, deterministically; shadow rays too.
    reps = replicate_images(s, ["rectangle"], replicates=6, samples=16)
    ok, p, alpha = pixel_t_test(reps["rectangle"], floor_image(cam) * color[0] ** 2, 1e-4)
    assert ok, f"worst p {p:.2e} < {alpha:.2e}"
    floor_only = render(sphrect.Scene(camera=cam, materials=s.materials[:1], meshes=[plane_mesh(1.5)],
                                      lights=[light()]))
    for ch in range(3):  # the same camera samples and light points: exact up to float rounding
        np.testing.assert_allclose(img[..., ch], floor_only[..., ch] * color[ch] ** 2, rtol=2e-6, atol=1e-7)


def test_principled_alpha_mix_shows_both_the_sheet_and_the_floor():
    a = 0.3
    principled = sphrect.Material(kind="principled", base_color=(0.5, 0.5, 0.5), roughness=1.0, specular=0.0)
    diffuse = sphrect.Material(base_color=(0.5, 0.5, 0.5))
    clear = sphrect.Material(kind="transparent", base_color=(1.0, 1.0, 1.0))
    sheet = sphrect.Material(kind="mix",
                             layers=[sphrect.MaterialLayer(1 - a, clear), sphrect.MaterialLayer(a, diffuse)])
    s = scene(sheet)
    cam = s.camera
    expected = a * 0.5 * sheet_irradiance_image(cam) + (1 - a) * (1 - a) * floor_image(cam)
    reps = replicate_images(s, ["rectangle", "area"], replicates=8, samples=32)
    for t, r in reps.items():
        ok, p, alpha = pixel_t_test(r, expected, 1e-4 / 2)
        assert ok, f"{t}: worst p {p:.2e} < {alpha:.2e}"
    # A Principled sheet renders (its Burley lobe differs from Lambert: brightness checked, not equality).
    img = render(scene(sphrect.Material(kind="mix", layers=[sphrect.MaterialLayer(1 - a, clear),
                                                            sphrect.MaterialLayer(a, principled)])), samples=64)
    assert 0.8 * expected.mean() < img[..., 0].mean() < 1.2 * expected.mean()


def test_more_sheets_than_the_transparent_limit_are_black():
    clear = sphrect.Material(kind="transparent", base_color=(1.0, 1.0, 1.0))
    limit = sphrect.MAX_TRANSPARENT_HITS
    below = render(scene(clear, sheets=limit))
    assert below[..., 0].min() > 0
    np.testing.assert_allclose(render(scene(clear, sheets=limit + 1))[..., :3], 0)


def test_transparent_film_alpha_through_a_sheet():
    grey = sphrect.Material(kind="transparent", base_color=(0.4, 0.4, 0.4))
    s = sphrect.Scene(camera=sphrect.Camera(**{**top_camera(8, 8).__dict__, "film_transparent": True}),
                      materials=[grey], meshes=[plane_mesh(1.5, SHEET_Z)], lights=[light()])
    r = sphrect.Renderer(s, techniques="rectangle", seed=1)
    r.render(8)
    np.testing.assert_allclose(r.image("rectangle")[..., 3], 0.6, atol=1e-6)


def test_alpha_texture_cuts_the_sheet_out_per_texel():
    """A Principled Alpha from an image (exported as a mix whose factors read its alpha): a 2 x 1 image of alpha
    0 (left half, transparent) and 1 (right half, an opaque black sheet).  The right half is black; the left
    quarter of the view (x < -0.5) is the floor alone exactly, its rays to the light (x in [-0.6, 0.6]) crossing the
    sheet only where it is transparent; in between the opaque half may shadow the floor."""
    pixels = np.array([[[0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]], np.float32)
    lookup = sphrect.TextureLookup(0, output="alpha", interpolation="closest")
    clear = sphrect.Material(kind="transparent", base_color=(1.0, 1.0, 1.0))
    black = sphrect.Material(base_color=(0.0, 0.0, 0.0))
    sheet = sphrect.Material(kind="mix", layers=[
        sphrect.MaterialLayer(1.0, clear, factors=[sphrect.MixFactor(lookup, complement=True)]),
        sphrect.MaterialLayer(1.0, black, factors=[sphrect.MixFactor(lookup)])])
    s = scene(sheet)
    mesh = s.meshes[0]
    mesh.uvs = np.zeros((8, 2), np.float32)
    mesh.uvs[4:] = (mesh.vertices[4:, :2] + 1.5) / 3.0  # the sheet's square onto [0, 1]^2 (its x = 0 at u = 0.5)
    s.textures = [sphrect.Texture(pixels=pixels, colorspace="linear")]
    img = render(s)[..., 0]
    floor_only = render(sphrect.Scene(camera=s.camera, materials=s.materials[:1], meshes=[plane_mesh(1.5)],
                                      lights=[light()]))[..., 0]
    w = img.shape[1]  # 8 pixels over x in [-1, 1]
    assert np.all(img[:, w // 2:] == 0)
    np.testing.assert_allclose(img[:, : w // 4], floor_only[:, : w // 4], rtol=2e-6)
    assert np.all(img[:, : w // 2] <= floor_only[:, : w // 2] * (1 + 2e-6)) and img[:, : w // 2].min() > 0
    assert img[:, w // 4: w // 2].sum() < 0.99 * floor_only[:, w // 4: w // 2].sum()  # the cut-out's shadow


def test_transparent_kind_round_trips_through_the_scene_file(tmp_path):
    path = tmp_path / "s.sphrect.npz"
    s = scene(sphrect.Material(name="sheet", kind="transparent", base_color=(0.5, 0.25, 0.9)))
    sphrect.save_scene(s, path)
    loaded = sphrect.load_scene(path)
    assert loaded.materials[1].kind == "transparent"
    assert loaded.materials[1].base_color == pytest.approx((0.5, 0.25, 0.9))
    np.testing.assert_array_equal(render(loaded), render(s))


def test_transparent_material_with_emission_is_refused():
    s = scene(sphrect.Material(kind="transparent", emission=(1.0, 1.0, 1.0)))
    with pytest.raises(ValueError, match="no emission"):
        sphrect.Renderer(s)


def test_a_textured_transparent_colour_lets_rays_through_its_image():
    """Transparent BSDF Color from an image: its own (unlinked) colour black, the image white on the left half and
    black on the right; the left quarter sees and lights the floor as if the sheet were not there."""
    pixels = np.array([[[1.0, 1.0, 1.0], [0.0, 0.0, 0.0]]], np.float32)
    sheet = sphrect.Material(kind="transparent", base_color=(0.0, 0.0, 0.0),
                             textures={"base_color": sphrect.TextureLookup(0, interpolation="closest")})
    s = scene(sheet)
    s.meshes[0].uvs = np.zeros((8, 2), np.float32)
    s.meshes[0].uvs[4:] = (s.meshes[0].vertices[4:, :2] + 1.5) / 3.0
    s.textures = [sphrect.Texture(pixels=pixels, colorspace="linear")]
    img = render(s)[..., 0]
    floor_only = render(sphrect.Scene(camera=s.camera, materials=s.materials[:1], meshes=[plane_mesh(1.5)],
                                      lights=[light()]))[..., 0]
    w = img.shape[1]
    assert np.all(img[:, w // 2:] == 0)
    np.testing.assert_allclose(img[:, : w // 4], floor_only[:, : w // 4], rtol=2e-6)
