"""Image textures in the renderer: lookups bound to material inputs, Mix factors, normal maps, images from
pixels or files (OpenImageIO), the scene file.  Most checks are identities with an untextured scene that must
render the same (deterministic renders: no false failures); the rest compare with closed-form values."""
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh, top_camera
from sphrect._native import svm_color as svm

SRGB_128 = ((128 / 255 + 0.055) / 1.055) ** 2.4  # the sRGB decoding of byte 128


def plane_with_uvs(size=1.0):
    """The square [-size, size]^2 of z = 0, UVs (0, 0) at (-size, -size) to (1, 1) at (size, size)."""
    v = np.array([[-size, -size, 0], [size, -size, 0], [size, size, 0], [-size, size, 0]], np.float32)
    uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32)
    return sphrect.Mesh(vertices=v, triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32), uvs=uv,
                        generated=np.c_[uv, np.zeros(4, np.float32)], name="plane")


def lit_scene(material, textures=(), width=16, height=16):
    light = sphrect.RectLight(corner=(-1.0, -1.0, 2.0), edge_x=(2.0, 0.0, 0.0), edge_y=(0.0, 2.0, 0.0),
                              radiance=(3.0, 3.0, 3.0), two_sided=True, visible=False)
    return sphrect.Scene(camera=top_camera(width, height), materials=[material], meshes=[plane_with_uvs()],
                         lights=[light], textures=list(textures))


def render(scene, spp=8, **kw):
    r = sphrect.Renderer(scene, techniques="rectangle", seed=3, threads=2, **kw)
    r.render(spp)
    return r.image("rectangle")[..., :3]


def constant(value, dtype=np.float32):
    return sphrect.Texture(name="c", pixels=np.array(value, dtype).reshape(1, 1, -1), colorspace="linear")


LOOKUP = sphrect.TextureLookup(0)


def assert_same_render(a, b):
    """Equal but for float rounding: a textured hit's point comes from the barycentrics, an untextured flat one's
    from the ray (relative differences ~1e-7)."""
    np.testing.assert_allclose(a, b, rtol=1e-5, atol=1e-7)


@pytest.mark.parametrize("kind,fields", [
    ("diffuse", {}), ("principled", {"metallic": 0.3, "clearcoat": 0.5}), ("glass", {"ior": 1.5}),
    ("glossy_bsdf", {})])
def test_constant_base_color_texture_renders_as_the_constant(kind, fields):
    color = (0.25, 0.5, 0.75)
    plain = sphrect.Material(kind=kind, base_color=color, roughness=0.4, **fields)
    textured = sphrect.Material(kind=kind, base_color=(0.8, 0.8, 0.8), roughness=0.4, **fields,
                                textures={"base_color": LOOKUP})
    assert_same_render(render(lit_scene(textured, [constant(color)])), render(lit_scene(plain)))


@pytest.mark.parametrize("name", ["roughness", "metallic", "specular"])
def test_constant_scalar_texture_renders_as_the_constant(name):
    value = 0.35
    base = dict(kind="principled", base_color=(0.6, 0.4, 0.2), roughness=0.5, metallic=0.2, specular=0.5)
    plain = sphrect.Material(**{**base, name: value})
    # A scalar input reads a colour's luminance (Rec.709 weights sum to 1: grey v reads v).
    textured = sphrect.Material(**base, textures={name: LOOKUP})
    a = render(lit_scene(textured, [constant((value, value, value))]))
    b = render(lit_scene(plain))
    np.testing.assert_allclose(a, b, rtol=2e-6, atol=1e-7)


def test_alpha_output_reads_the_alpha_channel():
    plain = sphrect.Material(base_color=(0.3, 0.3, 0.3))
    textured = sphrect.Material(textures={"base_color": sphrect.TextureLookup(0, output="alpha")})
    assert_same_render(render(lit_scene(textured, [constant((1.0, 0.0, 0.0, 0.3))])), render(lit_scene(plain)))


def test_mix_factor_from_a_texture_weights_the_layers():
    fac = 0.25
    a_mat = sphrect.Material(base_color=(0.9, 0.1, 0.1))
    b_mat = sphrect.Material(kind="glossy_bsdf", base_color=(0.2, 0.8, 0.2), roughness=0.3)
    plain = sphrect.Material(kind="mix", layers=[sphrect.MaterialLayer(1 - fac, a_mat),
                                                 sphrect.MaterialLayer(fac, b_mat)])
    factor = lambda complement: [sphrect.MixFactor(LOOKUP, complement=complement)]
    textured = sphrect.Material(kind="mix", layers=[sphrect.MaterialLayer(1.0, a_mat, factor(True)),
                                                    sphrect.MaterialLayer(1.0, b_mat, factor(False))])
    np.testing.assert_allclose(render(lit_scene(textured, [constant((fac, fac, fac))])),
                               render(lit_scene(plain)), rtol=1e-5, atol=1e-7)


def test_srgb_byte_image_decodes_after_the_lookup():
    plain = sphrect.Material(base_color=(SRGB_128,) * 3)
    tex = sphrect.Texture(pixels=np.full((1, 1, 3), 128, np.uint8), colorspace="srgb")
    textured = sphrect.Material(textures={"base_color": LOOKUP})
    np.testing.assert_allclose(render(lit_scene(textured, [tex])), render(lit_scene(plain)), rtol=1e-5)
    linear = sphrect.Texture(pixels=np.full((1, 1, 3), 128, np.uint8), colorspace="linear")
    np.testing.assert_allclose(render(lit_scene(textured, [linear])),
                               render(lit_scene(sphrect.Material(base_color=(128 / 255,) * 3))), rtol=1e-5)


def checker_scene(interpolation="closest", extension="repeat", transform=None, width=16):
    """A 2x2 checker (bottom-left black, bottom-right white), unlit: the base colour seen through a sun
    straight above (radiance = albedo E / pi at every point)."""
    pixels = np.array([[[0.0], [1.0]], [[1.0], [0.0]]], np.float32)  # rows bottom to top
    lookup = sphrect.TextureLookup(0, interpolation=interpolation, extension=extension,
                                   transform=transform if transform is not None else np.eye(3, 4).tolist())
    scene = lit_scene(sphrect.Material(textures={"base_color": lookup}),
                      [sphrect.Texture(pixels=pixels, colorspace="linear")], width=width, height=width)
    scene.lights = [sphrect.SunLight(direction=(0, 0, -1), irradiance=(np.pi, np.pi, np.pi))]
    return scene


def test_closest_checker_shows_its_texels_bottom_row_first():
    img = render(checker_scene())[..., 0]
    h = img.shape[0] // 2
    # Image row 0 is the top: the texture's top row (white, black) is the image's top half.
    np.testing.assert_allclose(img[:h, :h], 1.0, rtol=1e-6)
    np.testing.assert_allclose(img[:h, h:], 0.0, atol=1e-7)
    np.testing.assert_allclose(img[h:, :h], 0.0, atol=1e-7)
    np.testing.assert_allclose(img[h:, h:], 1.0, rtol=1e-6)


def test_linear_checker_is_bilinear_between_texel_centres():
    # One sample per pixel at the pixel's centre would be exact; averaged over the pixel, the bilinear ramp is
    # linear along each axis, so the pixel mean equals the value at its centre too.
    img = render(checker_scene("linear", "extend"), spp=64, pattern="stratified")[..., 0]
    n = img.shape[0]
    centres = (np.arange(n) + 0.5) / n  # u of each image column, v = 1 - row's
    u, v = np.meshgrid(centres, 1 - centres)
    tx, ty = np.clip(u * 2 - 0.5, 0, 1), np.clip(v * 2 - 0.5, 0, 1)
    # Texels (0,0) = 0, (1,0) = 1, (0,1) = 1, (1,1) = 0.
    expected = (1 - ty) * tx + ty * (1 - tx)
    np.testing.assert_allclose(img, expected, atol=0.02)


def test_repeat_and_clip_outside_the_unit_square():
    # Mapping by 2: the checker repeats twice across the plane; clipped, only its first quarter shows.
    scale = [[2, 0, 0, 0], [0, 2, 0, 0], [0, 0, 1, 0]]
    repeat = render(checker_scene(transform=scale))[..., 0]
    clip = render(checker_scene(extension="clip", transform=scale))[..., 0]
    q = repeat.shape[0] // 4
    np.testing.assert_allclose(repeat[:q, :q], 1.0, rtol=1e-6)        # top-left: texel (0, 1) of the 2nd period
    np.testing.assert_allclose(repeat[:q, q:2 * q], 0.0, atol=1e-7)
    half = repeat.shape[0] // 2
    np.testing.assert_array_equal(clip[half:, :half], repeat[half:, :half])  # the bottom-left period, u, v < 1
    np.testing.assert_allclose(clip[:half, :], 0.0, atol=1e-7)        # v > 1: clipped to black
    np.testing.assert_allclose(clip[:, half:], 0.0, atol=1e-7)


def test_generated_coordinates_read_the_mesh_attribute():
    uv = render(checker_scene())
    scene = checker_scene()
    scene.materials[0].textures["base_color"].coordinates = "generated"
    np.testing.assert_array_equal(render(scene), uv)


def test_flat_normal_map_keeps_the_normal_and_a_tilted_one_tilts_it():
    # A glossy lobe: no bump shadowing term (Cycles applies it to diffuse lobes only), so a constant tilted map
    # must equal smooth normals tilted the same way.
    mat = sphrect.Material(kind="glossy_bsdf", base_color=(0.7, 0.7, 0.7), roughness=0.4)
    plain = render(lit_scene(mat))
    flat = sphrect.Material(**{**mat.__dict__, "normal_map": LOOKUP})
    np.testing.assert_allclose(render(lit_scene(flat, [constant((0.5, 0.5, 1.0))])), plain, rtol=1e-5, atol=1e-7)
    # Tilting towards +u (= +x here) and towards +v (= +y): the tangent and bitangent frame of the UVs.
    for tilt in ((0.3, 0.0, 1.0), (0.0, -0.4, 1.0)):
        n = np.array(tilt) / np.linalg.norm(tilt)
        tilted_map = render(lit_scene(flat, [constant(tuple((n + 1) / 2))]))
        scene = lit_scene(mat)
        scene.meshes[0].normals = np.tile(n.astype(np.float32), (4, 1))
        np.testing.assert_allclose(tilted_map, render(scene), rtol=1e-4, atol=1e-6)
    # Half strength: normalize(N + (N_map - N) / 2).
    n = np.array([0.3, 0.0, 1.0]) / np.linalg.norm([0.3, 0.0, 1.0])
    half = sphrect.Material(**{**flat.__dict__, "normal_map_strength": 0.5})
    m = np.array([0.0, 0.0, 1.0]) + (n - [0.0, 0.0, 1.0]) * 0.5
    scene = lit_scene(mat)
    scene.meshes[0].normals = np.tile((m / np.linalg.norm(m)).astype(np.float32), (4, 1))
    np.testing.assert_allclose(render(lit_scene(half, [constant(tuple((n + 1) / 2))])), render(scene),
                               rtol=1e-4, atol=1e-6)


def test_a_map_tilting_the_normal_past_the_viewer_is_kept_valid_for_reflection():
    # Cycles 3.4 passes a closure's Normal input through ensure_valid_reflection: a tangent-space map that leans
    # the normal so far that the view would reflect below the surface (a missing map's magenta, (1, 0, 1), leans
    # it 45 degrees in two axes; here 80 degrees) shades with the normal turned back, as smooth normals set to
    # that turned normal do.  It was shaded with the leaning normal: a black glossy surface (third-party chair).
    mat = sphrect.Material(kind="glossy_bsdf", base_color=(0.7, 0.7, 0.7), roughness=0.4)
    lean = np.array([np.sin(np.radians(80)), 0.0, np.cos(np.radians(80))])
    mapped = render(lit_scene(sphrect.Material(**{**mat.__dict__, "normal_map": LOOKUP}),
                              [constant(tuple((lean + 1) / 2))]))
    up = np.array([0.0, 0.0, 1.0])
    turned = svm.ensure_valid_reflection(up, up, lean)[0]  # orthographic camera: I = +z everywhere
    assert turned[2] > lean[2] + 0.1  # the case turns the normal
    scene = lit_scene(mat)
    scene.meshes[0].normals = np.tile(np.asarray(turned, np.float32), (4, 1))
    np.testing.assert_allclose(mapped, render(scene), rtol=1e-4, atol=1e-6)
    assert mapped.mean() > 0.01


def bump_shadowing_term(n0, n, wi):
    """Cycles' bump_shadowing_term, written from Chiang et al. 2019."""
    g = (n0 @ wi) / ((n @ wi) * (n0 @ n))
    return 1.0 if not 0 <= g < 1 else g + g * g - g ** 3


def test_normal_mapped_diffuse_has_cycles_bump_shadowing():
    # A sun at a grazing angle to the plane lights a Lambert plane whose map tilts the normal towards it:
    # radiance = albedo / pi * E * (n . wi) * term(n0, n, wi).
    n = np.array([0.5, 0.0, 1.0]) / np.linalg.norm([0.5, 0.0, 1.0])
    wi = np.array([0.9, 0.0, 0.25]) / np.linalg.norm([0.9, 0.0, 0.25])
    mat = sphrect.Material(base_color=(0.5, 0.5, 0.5), normal_map=LOOKUP)
    scene = lit_scene(mat, [constant(tuple((n + 1) / 2))])
    scene.lights = [sphrect.SunLight(direction=tuple(-wi), irradiance=(2.0, 2.0, 2.0))]
    img = render(scene, spp=1)
    term = bump_shadowing_term(np.array([0.0, 0.0, 1.0]), n, wi)
    assert term < 0.99  # the case exercises the term
    np.testing.assert_allclose(img, 0.5 / np.pi * 2.0 * (n @ wi) * term, rtol=1e-5)


def write_ppm(path, pixels):
    """A binary PPM (P6) of uint8 [H, W, 3], top row first (the file's order)."""
    h, w, _ = pixels.shape
    with open(path, "wb") as f:
        f.write(b"P6 %d %d 255\n" % (w, h))
        f.write(np.ascontiguousarray(pixels, np.uint8).tobytes())


def test_image_file_loads_as_its_pixels(tmp_path):
    rng = np.random.default_rng(5)
    pixels = rng.integers(0, 256, (4, 6, 3), dtype=np.uint8)  # bottom row first, as Blender's
    path = tmp_path / "image.ppm"
    write_ppm(path, pixels[::-1])
    mat = sphrect.Material(textures={"base_color": sphrect.TextureLookup(0, interpolation="closest")})
    from_file = render(lit_scene(mat, [sphrect.Texture(path=str(path))]))
    from_pixels = render(lit_scene(mat, [sphrect.Texture(pixels=pixels)]))
    np.testing.assert_array_equal(from_file, from_pixels)


def test_missing_image_file_is_magenta_with_a_warning(tmp_path):
    mat = sphrect.Material(textures={"base_color": LOOKUP})
    with pytest.warns(RuntimeWarning, match="magenta"):
        img = render(lit_scene(mat, [sphrect.Texture(name="gone", path=str(tmp_path / "gone.png"))]))
    magenta = render(lit_scene(sphrect.Material(base_color=(1.0, 0.0, 1.0))))
    assert_same_render(img, magenta)


@pytest.mark.parametrize("kind", ["device", "fifo", "folder", "nul byte"])
def test_a_path_that_is_not_a_regular_file_is_a_missing_image(tmp_path, kind):
    # A device or a FIFO made the image reader spin or block forever (issue 27): now each is Cycles' missing image,
    # warned.  In a child process, so that the old behaviour fails the test on its timeout instead of hanging it.
    path = {"device": "/dev/zero", "folder": str(tmp_path), "nul byte": str(tmp_path / "a.png") + "\0.png"}.get(kind)
    if kind == "fifo":
        path = str(tmp_path / "fifo")
        os.mkfifo(path)
    code = f"""
import warnings, numpy as np, sphrect, sys
sys.path.insert(0, {os.path.dirname(__file__)!r})
from test_render_textures import LOOKUP, assert_same_render, lit_scene, render
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    img = render(lit_scene(sphrect.Material(textures={{"base_color": LOOKUP}}), [sphrect.Texture(path={path!r})]))
magenta = render(lit_scene(sphrect.Material(base_color=(1.0, 0.0, 1.0))))
assert_same_render(img, magenta)
print([str(w.message) for w in caught])
"""
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert "magenta" in run.stdout and ("regular file" in run.stdout or "NUL" in run.stdout), run.stdout


@pytest.mark.parametrize("dtype", [np.uint16, np.uint32])
def test_unsigned_integer_texels_are_scaled_by_their_range(dtype):
    # uint16 pixels (what a 16-bit PNG gives through numpy) were used raw, ~65535x too bright (issue 27): an unsigned
    # image is its values over the type's largest, as the same file read by path is.
    top = np.iinfo(dtype).max
    levels = np.array([0, top // 4, top // 2, top], dtype)
    pixels = levels[np.arange(12).reshape(2, 2, 3) % 4].astype(dtype)
    mat = sphrect.Material(textures={"base_color": sphrect.TextureLookup(0, interpolation="closest")})
    as_integers = render(lit_scene(mat, [sphrect.Texture(pixels=pixels, colorspace="linear")]))
    as_floats = render(lit_scene(mat, [sphrect.Texture(pixels=(pixels / np.float64(top)).astype(np.float32),
                                                       colorspace="linear")]))
    np.testing.assert_array_equal(as_integers, as_floats)


def test_signed_integer_texels_are_refused_with_their_dtype():
    mat = sphrect.Material(textures={"base_color": LOOKUP})
    with pytest.raises(ValueError, match="int32"):
        render(lit_scene(mat, [sphrect.Texture(pixels=np.ones((2, 2, 3), np.int32))]))


def test_textures_survive_the_scene_file(tmp_path):
    scene = checker_scene("linear")
    scene.textures.append(sphrect.Texture(name="bytes", pixels=np.full((2, 2, 4), 200, np.uint8)))
    scene.materials[0].normal_map = sphrect.TextureLookup(1)
    path = str(tmp_path / "s.sphrect.npz")
    sphrect.save_scene(scene, path)
    loaded = sphrect.load_scene(path)
    assert loaded.textures[1].pixels.dtype == np.uint8
    np.testing.assert_array_equal(render(loaded), render(scene))


def image_file_scene(folder):
    """A scene reading `folder`/image.ppm by the relative path 'image.ppm' (the current directory must be
    `folder`), and the same image from its pixels."""
    pixels = np.random.default_rng(9).integers(0, 256, (4, 6, 3), dtype=np.uint8)
    write_ppm(folder / "image.ppm", pixels[::-1])
    mat = sphrect.Material(textures={"base_color": sphrect.TextureLookup(0, interpolation="closest")})
    return lit_scene(mat, [sphrect.Texture(path="image.ppm")]), lit_scene(mat, [sphrect.Texture(pixels=pixels)])


def test_a_relative_texture_path_is_relative_to_the_scene_file(tmp_path, monkeypatch):
    # It was read from the current directory: the same scene file rendered magenta from anywhere else (issue 27).
    (tmp_path / "scene").mkdir()
    (tmp_path / "elsewhere").mkdir()
    monkeypatch.chdir(tmp_path / "scene")
    scene, from_pixels = image_file_scene(tmp_path / "scene")
    sphrect.save_scene(scene, "s.sphrect.npz")
    monkeypatch.chdir(tmp_path / "elsewhere")
    loaded = sphrect.load_scene(str(tmp_path / "scene" / "s.sphrect.npz"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no missing image
        np.testing.assert_array_equal(render(loaded), render(from_pixels))
    assert loaded.textures[0].path == str(tmp_path / "scene" / "image.ppm")


def test_a_scene_saved_again_elsewhere_names_the_same_texture_file(tmp_path, monkeypatch):
    # save -> load -> save in another folder -> load, and a relative path saved from another directory than the
    # file's: each time the file the scene in memory reads.
    for folder in ("images", "a", "b", "run"):
        (tmp_path / folder).mkdir()
    monkeypatch.chdir(tmp_path / "images")
    scene, from_pixels = image_file_scene(tmp_path / "images")
    sphrect.save_scene(scene, str(tmp_path / "a" / "s.sphrect.npz"))  # 'image.ppm' of images/, stored relative to a/
    monkeypatch.chdir(tmp_path / "run")
    again = sphrect.load_scene(str(tmp_path / "a" / "s.sphrect.npz"))
    sphrect.save_scene(again, str(tmp_path / "b" / "s.sphrect.npz"))
    for name in ("a", "b"):
        loaded = sphrect.load_scene(str(tmp_path / name / "s.sphrect.npz"))
        assert loaded.textures[0].path == str(tmp_path / "images" / "image.ppm"), name
        np.testing.assert_array_equal(render(loaded), render(from_pixels))


def test_textured_scene_reports_its_features():
    r = sphrect.Renderer(checker_scene(), techniques="rectangle")
    assert "textures" in r.features and "normal_maps" not in r.features
    r = sphrect.Renderer(lit_scene(sphrect.Material()), techniques="rectangle")
    assert "textures" not in r.features


def test_missing_uvs_are_warned():
    scene = checker_scene()
    scene.meshes = [plane_mesh(1.0)]
    with pytest.warns(RuntimeWarning, match="UV coordinates the mesh does not have"):
        sphrect.Renderer(scene, techniques="rectangle")


@pytest.mark.parametrize("change,message", [
    (lambda s: setattr(s.materials[0].textures["base_color"], "texture", 3), "not an index"),
    (lambda s: setattr(s.materials[0].textures["base_color"], "interpolation", "cubic"), "interpolation"),
    (lambda s: setattr(s.materials[0].textures["base_color"], "extension", "mirror"), "extension"),
    (lambda s: setattr(s.materials[0].textures["base_color"], "transform", np.eye(3)), "3x4"),
    (lambda s: s.materials[0].textures.update(sheen=sphrect.TextureLookup(0)), "no input 'sheen'"),
    (lambda s: setattr(s.materials[0], "textures", [LOOKUP]), "textures must be a dict"),
    (lambda s: setattr(s.materials[0], "kind", "mix"), "material 'default': a mix's textures are its layers'"),
    (lambda s: setattr(s.textures[0], "colorspace", "aces"), "colorspace"),
    (lambda s: setattr(s.textures[0], "pixels", np.zeros((2, 2, 5), np.float32)), "1..4"),
    (lambda s: setattr(s.meshes[0], "uvs", np.zeros((3, 2), np.float32)), "uvs must have shape"),
])
def test_bad_textures_are_clear_errors(change, message):
    scene = checker_scene()
    change(scene)
    with pytest.raises(ValueError, match=message):
        sphrect.Renderer(scene, techniques="rectangle")


def test_emitting_layer_with_a_texture_factor_is_refused():
    glow = sphrect.Material(emission=(1.0, 1.0, 1.0))
    mat = sphrect.Material(kind="mix", layers=[sphrect.MaterialLayer(1.0, glow, [sphrect.MixFactor(LOOKUP)])])
    with pytest.raises(ValueError, match="constant emission"):
        sphrect.Renderer(lit_scene(mat, [constant((0.5, 0.5, 0.5))]), techniques="rectangle")


def test_normal_map_is_applied_in_object_space():
    # A plane scaled 2.5x along x as an object: Cycles maps the tangent-space normal in object space, then
    # transforms it as a normal (by L^-T), which tilts it less along the stretched axis.
    mat = sphrect.Material(kind="glossy_bsdf", base_color=(0.7, 0.7, 0.7), roughness=0.4, normal_map=LOOKUP)
    n = np.array([0.3, 0.0, 1.0]) / np.linalg.norm([0.3, 0.0, 1.0])
    linear = np.diag([2.5, 1.0, 1.0])
    scene = lit_scene(mat, [constant(tuple((n + 1) / 2))])
    local = scene.meshes[0].vertices.copy()
    scene.meshes[0].vertices = (local @ linear.T).astype(np.float32)
    scene.meshes[0].object_linear = linear.tolist()
    expected_normal = np.linalg.inv(linear).T @ n
    expected_normal /= np.linalg.norm(expected_normal)
    smooth = lit_scene(sphrect.Material(kind="glossy_bsdf", base_color=(0.7, 0.7, 0.7), roughness=0.4))
    smooth.meshes[0].vertices = scene.meshes[0].vertices
    smooth.meshes[0].normals = np.tile(expected_normal.astype(np.float32), (4, 1))
    np.testing.assert_allclose(render(scene), render(smooth), rtol=1e-4, atol=1e-6)
    # In world space (no object_linear) the tilt is the map's own, visibly different.
    scene.meshes[0].object_linear = None
    assert np.abs(render(scene) - render(smooth)).max() > 1e-3


def test_openimageio_is_loaded_only_for_image_files(tmp_path):
    # Its ~250 shared libraries cost an import half a second: sphrect loads its reader module on first use.
    import subprocess
    import sys
    write_ppm(tmp_path / "a.ppm", np.zeros((2, 2, 3), np.uint8))
    code = ("import sphrect, numpy as np, re\n"
            "maps = lambda: open('/proc/self/maps').read()\n"
            "before = 'libOpenImageIO' in maps()\n"
            "m = sphrect.Material(textures={'base_color': sphrect.TextureLookup(0)})\n"
            f"s = sphrect.Scene(camera=sphrect.Camera(width=4, height=4), materials=[m], "
            f"textures=[sphrect.Texture(path={str(tmp_path / 'a.ppm')!r})], "
            "lights=[sphrect.PointLight(position=(0, 0, 1), intensity=(1, 1, 1))])\n"
            "sphrect.Renderer(s)\n"
            "print(before, 'libOpenImageIO' in maps())\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["False", "True"]


def test_texture_scalar_mean_is_the_mean_of_decoded_clamped_texels():
    grey = np.full((2, 2, 3), 128, np.uint8)
    assert sphrect.texture_scalar_mean(grey, True, False) == pytest.approx(SRGB_128, rel=1e-6)
    assert sphrect.texture_scalar_mean(grey, False, False) == pytest.approx(128 / 255, rel=1e-6)
    rgba = np.array([[[1.0, 0.0, 0.0, 0.25], [4.0, 4.0, 4.0, 0.75]]], np.float32)  # luminance 0.2126, 4 -> 1
    assert sphrect.texture_scalar_mean(rgba, False, False) == pytest.approx((0.2126 + 1.0) / 2, rel=1e-6)
    assert sphrect.texture_scalar_mean(rgba, False, True) == pytest.approx(0.5)


def test_texture_color_mean_is_the_mean_decoded_colour():
    srgb = np.array([[[128, 0, 255], [0, 128, 255]]], np.uint8)
    assert sphrect.texture_color_mean(srgb, True) == pytest.approx((SRGB_128 / 2, SRGB_128 / 2, 1.0), rel=1e-6)
    floats = np.array([[[4.0, 0.5, 0.0], [0.0, 0.5, 2.0]]], np.float32)  # not clamped: an emitter's colour
    assert sphrect.texture_color_mean(floats, False) == pytest.approx((2.0, 0.5, 1.0), rel=1e-6)
