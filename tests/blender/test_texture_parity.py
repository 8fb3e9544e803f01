"""Image textures as Cycles 3.4 shows them at max_bounces 0.

Renders (test_cycles_parity's: Cycles 2048 spp, SPHRECT 512, fixed seeds, mean relative difference over 4x4
blocks): a plane seen from above, lit by a rectangle, whose material reads images generated here (numpy ->
bpy.data.images.new, packed): Base Color from an sRGB byte image with Linear filtering (Cycles filters the encoded
bytes, then decodes: so does the renderer) and with Closest filtering and Clip extension through a Mapping node;
Roughness from a Non-Color image on a metal; a Mix Shader factor from a colour image (its luminance); a
tangent-space normal map of a smooth bump pattern; a sphere textured through its Generated coordinates.  Measured
when written: 0.01-0.19% (the normal map 1.04% before the renderer had Cycles' bump shadowing term, below).

Lookups (no SPHRECT render): an emissive plane under an orthographic camera shows Cycles' lookup at each pixel
centre; the exporter's textures, UVs / Generated, Mapping transforms, filters and extensions read back by a numpy
model of Cycles' lookup give the same values (1e-7 for Closest, a few 1e-4 for Linear: Cycles' pixel jitter);
and a sun-lit normal-mapped plane's shading from the exported map, which Cycles multiplies by its bump shadowing
term (bump_shadowing_term in kernel/closure/bsdf.h, on diffuse closures whose normal is bumped).
"""
import math

import bpy
import mathutils
import numpy as np
import pytest

from conftest import addon_module, builders, export, render, set_resolution
from test_cycles_parity import HEIGHT, WIDTH, difference_to_cycles, mean_relative_difference, render_cycles
from test_texture_export import Tree, new_image

pytestmark = pytest.mark.slow

# The models agree exactly here (the lookups, filters and colour decoding are Cycles'), so the bound is the
# other parity tests' for exact models: what is left is the two renders' noise.
TOLERANCE = 0.01


def plane_scene(scene, mat):
    """A 5 m plane of `mat` filling the view from above, a rectangle light off to one side."""
    builders.mesh_object("Plane", "plane", mat, size=5.0)
    builders.camera((0.0, -0.6, 4.0), (0.0, 0.0, 0.0), lens=35.0)
    lamp = builders.area_light("Light", "RECTANGLE", size=1.5, size_y=1.0, power=300.0, location=(1.5, 1.0, 2.5),
                               visible=False)
    builders.aim(lamp, (0.0, 0.0, 0.0))
    set_resolution(scene, WIDTH, HEIGHT)
    scene.sphrect.technique = "RECTANGLE"
    bpy.context.view_layer.update()
    return scene


def colour_checks(size=8, seed=3):
    """An image of random, strongly contrasting colours: filtering across texels shows in the render."""
    rng = np.random.default_rng(seed)
    pixels = rng.choice([0.05, 0.3, 0.95], size=(size, size, 4)).astype(np.float32)
    pixels[..., 3] = 1.0
    return pixels


def smooth_pattern(size=64, seed=5):
    """Smooth values in [0, 1] (a few sines), the same in every channel."""
    y, x = np.mgrid[0:size, 0:size] / size
    v = 0.5 + 0.25 * np.sin(2 * math.pi * (2 * x + 0.3)) + 0.2 * np.cos(2 * math.pi * (3 * y - x))
    pixels = np.repeat(np.clip(v, 0.0, 1.0)[..., None], 4, axis=2).astype(np.float32)
    pixels[..., 3] = 1.0
    return pixels


def bump_normals(size=64, bumps=3, amplitude=0.04):
    """A tangent-space normal map (Blender's encoding, colour = 0.5 n + 0.5) of the height
    amplitude * sin(2 pi bumps u) sin(2 pi bumps v), u and v across the image."""
    v, u = (np.mgrid[0:size, 0:size] + 0.5) / size  # row 0 = bottom = v near 0
    k = 2 * math.pi * bumps
    dh_du = amplitude * k * np.cos(k * u) * np.sin(k * v)
    dh_dv = amplitude * k * np.sin(k * u) * np.cos(k * v)
    n = np.stack([-dh_du, -dh_dv, np.ones_like(u)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    pixels = np.concatenate([0.5 * n + 0.5, np.ones((size, size, 1))], axis=-1)
    return pixels.astype(np.float32)


def image_node(t, image, interpolation="Linear", extension="REPEAT", mapping=None):
    node = t.image(image, interpolation=interpolation, extension=extension)
    if mapping is not None:
        m = t.node("ShaderNodeMapping")
        for socket, value in mapping.items():
            m.inputs[socket].default_value = value
        t.link(t.node("ShaderNodeTexCoord").outputs["UV"], m.inputs["Vector"])
        t.link(m.outputs["Vector"], node.inputs["Vector"])
    return node


def base_color_srgb_linear():
    t = Tree("BaseLinear")
    bsdf = t.node("ShaderNodeBsdfPrincipled")
    image = new_image("Checks", colour_checks(), colorspace="sRGB")
    tex = image_node(t, image, mapping={"Scale": (1.5, 1.5, 1.0)})  # tiled: Repeat
    t.link(tex.outputs["Color"], bsdf.inputs["Base Color"])
    return t.surface(bsdf)


def base_color_closest_clip():
    t = Tree("BaseClosest")
    bsdf = t.node("ShaderNodeBsdfDiffuse")
    image = new_image("Checks", colour_checks(), colorspace="sRGB")
    tex = image_node(t, image, "Closest", "CLIP", mapping={"Scale": (1.4, 1.4, 1.0), "Location": (-0.2, -0.2, 0.0)})
    t.link(tex.outputs["Color"], bsdf.inputs["Color"])
    return t.surface(bsdf)


def roughness_non_color():
    t = Tree("Roughness")
    bsdf = t.node("ShaderNodeBsdfPrincipled")
    bsdf.inputs["Base Color"].default_value = (0.9, 0.75, 0.5, 1.0)
    bsdf.inputs["Metallic"].default_value = 1.0
    image = new_image("Rough", 0.15 + 0.6 * smooth_pattern(), colorspace="Non-Color")
    t.link(image_node(t, image).outputs["Color"], bsdf.inputs["Roughness"])
    return t.surface(bsdf)


def mix_factor():
    t = Tree("MixFactor")
    diffuse, glossy = t.node("ShaderNodeBsdfDiffuse"), t.node("ShaderNodeBsdfGlossy")
    diffuse.inputs["Color"].default_value = (0.8, 0.25, 0.1, 1.0)
    glossy.inputs["Roughness"].default_value = 0.3
    glossy.distribution = "GGX"
    mix = t.node("ShaderNodeMixShader")
    t.link(diffuse.outputs[0], mix.inputs[1])
    t.link(glossy.outputs[0], mix.inputs[2])
    image = new_image("Mask", colour_checks(6, seed=11), colorspace="sRGB")  # a colour: its luminance is the factor
    t.link(image_node(t, image).outputs["Color"], mix.inputs["Fac"])
    return t.surface(mix)


def normal_map():
    t = Tree("NormalMap")
    bsdf = t.node("ShaderNodeBsdfPrincipled")
    bsdf.inputs["Base Color"].default_value = (0.7, 0.7, 0.7, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.4
    node = t.node("ShaderNodeNormalMap")
    image = new_image("Bumps", bump_normals(), colorspace="Non-Color")
    t.link(image_node(t, image).outputs["Color"], node.inputs["Color"])
    t.link(node.outputs["Normal"], bsdf.inputs["Normal"])
    return t.surface(bsdf)


PLANE_CASES = {"base_color_srgb_linear": base_color_srgb_linear, "base_color_closest_clip": base_color_closest_clip,
               "roughness_non_color": roughness_non_color, "mix_factor": mix_factor, "normal_map": normal_map}


@pytest.mark.parametrize("case", sorted(PLANE_CASES))
def test_textured_plane_matches_cycles(empty_scene, case, tmp_path):
    scene = plane_scene(empty_scene, PLANE_CASES[case]())
    exported, log = export()
    assert exported.textures and "Plane" in [m.name for m in exported.meshes]
    assert log.unsupported == {}
    difference, ours, cycles = difference_to_cycles(scene, f"texture {case}", tmp_path)
    assert cycles[..., :3].max() > 0
    assert difference <= TOLERANCE


def test_generated_coordinates_on_a_sphere_match_cycles(empty_scene, tmp_path):
    t = Tree("Generated")
    bsdf = t.node("ShaderNodeBsdfDiffuse")
    tex = t.image(new_image("Checks", colour_checks(), colorspace="sRGB"))
    t.link(t.node("ShaderNodeTexCoord").outputs["Generated"], tex.inputs["Vector"])
    t.link(tex.outputs["Color"], bsdf.inputs["Color"])
    builders.mesh_object("Ground", "plane", builders.material("Ground", (0.5, 0.5, 0.5)), size=8)
    ball = builders.mesh_object("Ball", "uv_sphere", t.surface(bsdf), location=(0.0, 0.0, 1.0), segments=48,
                                ring_count=24)
    builders.smooth(ball)
    lamp = builders.area_light("Light", "RECTANGLE", size=2.0, size_y=1.2, power=400.0, location=(1.2, -2.6, 3.0),
                               visible=False)
    builders.aim(lamp, (0.0, 0.0, 0.6))
    set_resolution(empty_scene, WIDTH, HEIGHT)
    empty_scene.sphrect.technique = "RECTANGLE"
    bpy.context.view_layer.update()
    exported, _ = export()
    assert [m.generated is not None for m in exported.meshes if m.name == "Ball"] == [True]
    difference, _, _ = difference_to_cycles(empty_scene, "texture generated sphere", tmp_path)
    assert difference <= TOLERANCE


def test_the_texture_comparison_can_fail(empty_scene, tmp_path):
    """The Linear sRGB plane rendered with its image read as Non-Color (not decoded) is far from Cycles'."""
    scene = plane_scene(empty_scene, base_color_srgb_linear())
    cycles = render_cycles(scene, str(tmp_path / "cycles.exr"), samples=256)  # the gap is far above its noise
    scene.render.engine = "SPHRECT"
    scene.sphrect.samples, scene.sphrect.passes, scene.sphrect.light_samples = 64, 1, 2
    assert mean_relative_difference(render()["images"]["rectangle"], cycles) < 0.02
    image = bpy.data.images["Checks"]
    pixels = np.array(image.pixels[:], dtype=np.float32)
    image.colorspace_settings.name = "Non-Color"  # regenerates the generated image: its pixels again
    image.pixels.foreach_set(pixels)
    undecoded = mean_relative_difference(render()["images"]["rectangle"], cycles)
    print(f"texture read undecoded: mean relative difference to Cycles {undecoded:.4f}")
    assert undecoded > 0.05


# The exported lookups against Cycles without the renderer: an emissive plane framed by an orthographic camera
# (each pixel one point of the plane, Cycles' colour there exactly the texture's), read back from what the exporter
# wrote -- Scene.textures, Mesh.uvs / generated, TextureLookup's transform, filter and extension -- by a numpy model
# of Cycles 3.4's image lookup (kernel/device/cpu/image.h: texel centres at (i + 0.5) / size, row 0 = bottom,
# Clip reading texels outside the image as 0 -- Linear then fades to black over half a texel, no hard edge;
# color_srgb_to_linear after filtering).
EMISSION_SIDE = 32


def srgb_to_linear(c):
    return np.where(c < 0.04045, np.maximum(c, 0.0) / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def cycles_lookup(texture, lookup, points):
    """The lookup's output at `points` ([N, 3] texture coordinates before its transform), float64 [N, 3]."""
    p = points @ np.asarray(lookup.transform)[:, :3].T + np.asarray(lookup.transform)[:, 3]
    x, y = p[:, 0], p[:, 1]
    pixels = texture.pixels.astype(np.float64) / (255.0 if texture.pixels.dtype == np.uint8 else 1.0)
    height, width = pixels.shape[:2]

    def fetch(ix, iy):
        if lookup.extension == "repeat":
            return pixels[np.mod(iy, height), np.mod(ix, width)]
        inside = (ix >= 0) & (ix < width) & (iy >= 0) & (iy < height)
        values = pixels[np.clip(iy, 0, height - 1), np.clip(ix, 0, width - 1)]
        return values if lookup.extension == "extend" else values * inside[:, None]

    if lookup.interpolation == "closest":
        value = fetch(np.floor(x * width).astype(int), np.floor(y * height).astype(int))
    else:
        fx, fy = x * width - 0.5, y * height - 0.5
        ix, iy = np.floor(fx).astype(int), np.floor(fy).astype(int)
        tx, ty = (fx - ix)[:, None], (fy - iy)[:, None]
        value = ((1 - ty) * ((1 - tx) * fetch(ix, iy) + tx * fetch(ix + 1, iy))
                 + ty * ((1 - tx) * fetch(ix, iy + 1) + tx * fetch(ix + 1, iy + 1)))
    if lookup.output == "alpha":
        return np.repeat(value[:, 3:4], 3, axis=1)
    rgb = value[:, :3]
    return srgb_to_linear(rgb) if texture.colorspace == "srgb" else rgb


def plane_points(mesh, attribute):
    """The mesh attribute (uvs as (u, v, 0), or generated) at each pixel centre of the orthographic view, by
    barycentric interpolation over the exported triangles (row 0 = the image's top)."""
    side = EMISSION_SIDE
    centres = (np.arange(side) + 0.5) / side * 2.0 - 1.0
    xs, ys = np.meshgrid(centres, -centres)
    q = np.c_[xs.ravel(), ys.ravel()]
    values = getattr(mesh, attribute)
    values = np.c_[values, np.zeros(len(values))] if values.shape[1] == 2 else values
    out = np.full((len(q), 3), np.nan)
    for tri in mesh.triangles:
        a, b, c = mesh.vertices[tri, :2].astype(np.float64)
        m = np.array([b - a, c - a]).T
        l1, l2 = np.linalg.solve(m, (q - a).T)
        inside = (l1 >= -1e-9) & (l2 >= -1e-9) & (l1 + l2 <= 1 + 1e-9)
        va, vb, vc = values[tri].astype(np.float64)
        out[inside] = (va + np.outer(l1, vb - va) + np.outer(l2, vc - va))[inside]
    return out


def emission_plane(scene, build):
    """A 2 m plane whose material's Emission Color and Diffuse Color build(tree) links, seen from straight above
    by an orthographic camera that frames it exactly.  Returns (tree, emission, diffuse): the Surface is linked to
    the diffuse for the export (whose lookup it gives), to the emission for Cycles (which then shows the lookup's
    value)."""
    t = Tree("Probe")
    emission, diffuse = t.node("ShaderNodeEmission"), t.node("ShaderNodeBsdfDiffuse")
    source = build(t)
    t.link(source, emission.inputs["Color"])
    t.link(source, diffuse.inputs["Color"])
    builders.mesh_object("Plane", "plane", t.surface(diffuse), size=2.0)
    cam = builders.camera((0.0, 0.0, 3.0), (0.0, 0.0, 0.0))
    cam.rotation_euler = (0.0, 0.0, 0.0)
    cam.data.type, cam.data.ortho_scale = "ORTHO", 2.0
    set_resolution(scene, EMISSION_SIDE, EMISSION_SIDE)
    bpy.context.view_layer.update()
    return t, emission, diffuse


def render_cycles_at_pixel_centres(scene, path):
    """Cycles at render_cycles' settings (max_bounces 0, no denoising, EXR) but a pixel filter of Cycles' smallest
    width: each sample within a few thousandths of a pixel of its pixel's centre."""
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device, c.samples, c.use_adaptive_sampling, c.use_denoising, c.max_bounces, c.seed = "CPU", 4, False, False, 0, 0
    c.pixel_filter_type, c.filter_width = "GAUSSIAN", 0.01  # Cycles 3.4 makes every box filter 1 pixel wide
    settings = scene.render.image_settings
    settings.file_format, settings.color_mode, settings.color_depth = "OPEN_EXR", "RGBA", "32"
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    return addon_module("images").read_image_rgba(path)


def _mapped(t, node, vector_type, source="UV", **values):
    m = t.node("ShaderNodeMapping", vector_type=vector_type)
    for socket, value in values.items():
        m.inputs[socket].default_value = value
    t.link(t.node("ShaderNodeTexCoord").outputs[source], m.inputs["Vector"])
    t.link(m.outputs["Vector"], node.inputs["Vector"])
    return node


def _alpha_image():
    pixels = colour_checks(6, seed=7)
    pixels[..., 3] = np.random.default_rng(2).choice([1.0, 0.6, 0.3], size=(6, 6))
    return pixels


def _alpha_used(t, node):
    """Uses the node's Alpha output where it changes nothing -- max(alpha, 1) as the emission strength, and the
    diffuse roughness (a warning) for the export -- so Cycles unassociates its colour (its graph keeps only nodes
    that reach the output; so does the exporter's test of the Alpha output)."""
    node.interpolation = "Closest"  # the exporter divides per texel: exact with Closest
    one = t.node("ShaderNodeMath", operation="MAXIMUM")
    one.inputs[1].default_value = 1.0
    t.link(node.outputs["Alpha"], one.inputs[0])
    t.link(one.outputs[0], t.nodes["Emission"].inputs["Strength"])
    t.link(one.outputs[0], t.nodes["Diffuse BSDF"].inputs["Roughness"])
    return node


EMISSION_CASES = {
    # sRGB bytes filtered then decoded, through a Point mapping (rotation, scale, offset) that repeats the image.
    "srgb_linear_point_repeat": lambda t: _mapped(
        t, t.image(new_image("Img", colour_checks())), "POINT", Location=(0.1, -0.2, 0.0),
        Rotation=(0.0, 0.0, 0.5), Scale=(1.7, 1.3, 1.0)).outputs["Color"],
    "srgb_closest_texture_extend": lambda t: _mapped(
        t, t.image(new_image("Img", colour_checks()), interpolation="Closest", extension="EXTEND"), "TEXTURE",
        Location=(0.2, 0.1, 0.0), Rotation=(0.0, 0.0, -0.3), Scale=(0.8, 0.7, 1.0)).outputs["Color"],
    "float_linear_generated_clip": lambda t: _mapped(
        t, t.image(new_image("Img", 3.0 * smooth_pattern(16), float_buffer=True), extension="CLIP"), "POINT",
        "Generated", Location=(-0.15, -0.1, 0.0), Scale=(1.3, 1.2, 1.0)).outputs["Color"],
    "non_color_alpha_output": lambda t: t.image(new_image("Img", _alpha_image(), colorspace="Non-Color"))
    .outputs["Alpha"],
    "straight_alpha_color": lambda t: t.image(new_image("Img", _alpha_image())).outputs["Color"],
    "straight_alpha_color_alpha_used": lambda t: _alpha_used(t, t.image(new_image("Img", _alpha_image())))
    .outputs["Color"],
    "float_alpha_color_alpha_used": lambda t: _alpha_used(
        t, t.image(new_image("Img", _alpha_image(), float_buffer=True))).outputs["Color"],
}
# Closest lookups: a pixel whose centre is within Cycles' jitter (a 0.01-pixel filter) of a texel edge may read
# the neighbour; Linear ones differ by at most the jitter times the gradient, and float32 rounding.
LOOKUP_TOLERANCE = 5e-3


@pytest.mark.parametrize("case", sorted(EMISSION_CASES))
def test_exported_lookups_reproduce_cycles_image_lookup(empty_scene, case, tmp_path):
    t, emission, diffuse = emission_plane(empty_scene, EMISSION_CASES[case])
    exported, log = export()
    assert set(log.unsupported) <= {"linked 'Roughness' input (Math)"}  # _alpha_used's
    (probe,) = [m for m in exported.materials if m.name == "Probe"]
    lookup = probe.textures["base_color"]
    (mesh,) = [m for m in exported.meshes if m.name == "Plane"]
    points = plane_points(mesh, "generated" if lookup.coordinates == "generated" else "uvs")
    expected = cycles_lookup(exported.textures[lookup.texture], lookup, points)
    t.link(emission.outputs[0], t.out.inputs["Surface"])
    cycles = render_cycles_at_pixel_centres(empty_scene, str(tmp_path / "emission.exr"))
    cycles = cycles[..., :3].reshape(-1, 3).astype(np.float64)
    error = np.abs(cycles - expected) / np.maximum(expected, 0.05)
    print(f"lookup {case}: median {np.median(error):.2e}, 99th percentile {np.percentile(error, 99):.2e}")
    if lookup.interpolation == "linear":
        assert np.median(error) <= LOOKUP_TOLERANCE / 5 and np.percentile(error, 99) <= LOOKUP_TOLERANCE
    else:
        assert np.mean(error > LOOKUP_TOLERANCE) <= 0.01


def bump_shadowing_term(n, bumped, light):
    """Cycles 3.4's bump_shadowing_term(N, N_bumped, omega_in) for unit vectors ([N, 3] bumped)."""
    g = (light @ n) / np.maximum((bumped @ light) * (bumped @ n), 1e-12)
    return np.where(g >= 1, 1.0, np.where(g < 0, 0.0, -g ** 3 + g ** 2 + g))


def test_exported_normal_map_reproduces_cycles_diffuse_shading(empty_scene, tmp_path):
    """A white diffuse plane under a sun (radiance cos(N_bumped, L) for an irradiance of pi), normal-mapped: the
    exported map, read by the numpy lookup and turned into normals in the UVs' tangent frame (T = +x, B = +y on
    Blender's plane), gives Cycles' image once Cycles' bump shadowing term is applied (within 0.1%; 0.5% apart
    without it)."""
    light = np.array([0.6, 0.3, 0.75]) / np.linalg.norm([0.6, 0.3, 0.75])

    def build(t):
        normal_map = t.node("ShaderNodeNormalMap")
        image = new_image("Bumps", bump_normals(), colorspace="Non-Color")
        t.link(image_node(t, image).outputs["Color"], normal_map.inputs["Color"])
        t.link(normal_map.outputs["Normal"], t.nodes["Diffuse BSDF"].inputs["Normal"])
        white = t.node("ShaderNodeRGB")  # the diffuse colour (an RGB node: folded to its constant, white)
        white.outputs[0].default_value = (1.0, 1.0, 1.0, 1.0)
        t.nodes["Diffuse BSDF"].inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        return white.outputs[0]
    emission_plane(empty_scene, build)
    sun = builders.other_light("Sun", "SUN", math.pi)
    sun.rotation_euler = mathutils.Vector(-light).to_track_quat("-Z", "Y").to_euler()
    bpy.context.view_layer.update()
    exported, log = export()
    assert not log.unsupported
    (probe,) = [m for m in exported.materials if m.name == "Probe"]
    lookup = probe.normal_map
    (mesh,) = [m for m in exported.meshes if m.name == "Plane"]
    c = cycles_lookup(exported.textures[lookup.texture], lookup, plane_points(mesh, "uvs"))
    bumped = 2 * c - 1
    bumped /= np.linalg.norm(bumped, axis=1, keepdims=True)
    cosine = np.maximum(bumped @ light, 0.0)
    cycles = render_cycles_at_pixel_centres(empty_scene, str(tmp_path / "sun.exr"))[..., 0].ravel()
    with_term = cosine * bump_shadowing_term(np.array([0.0, 0.0, 1.0]), bumped, light)
    relative = lambda expected: float(np.mean(np.abs(cycles - expected) / np.maximum(expected, 0.05)))
    print(f"normal map under a sun: {relative(with_term):.2e} with Cycles' bump shadowing term, "
          f"{relative(cosine):.2e} without")
    assert relative(with_term) <= 1e-3 < relative(cosine)
