"""The exporter's image textures (no rendering): Image Texture nodes -> sphrect.TextureLookup and Scene.textures
(packed and on-disk images, bytes and floats, colour spaces, a missing image), Mapping transforms, the coordinates
meshes carry (UVs per corner, seams kept; Generated), texture-driven Mix Shader factors, normal maps, and the
warnings for what is not modelled."""
import dataclasses
import json

import bpy
import mathutils
import numpy as np
import pytest

import sphrect
from conftest import builders, export

RNG = np.random.default_rng(13)


def new_image(name, pixels, float_buffer=False, colorspace=None, pack=True):
    """A Blender image of `pixels` (float [H, W, 4], row 0 = bottom, as Image.pixels), packed by default."""
    height, width = pixels.shape[:2]
    image = bpy.data.images.new(name, width, height, alpha=True, float_buffer=float_buffer)
    if colorspace is not None:  # first: setting it regenerates a generated image's pixels
        image.colorspace_settings.name = colorspace
    image.pixels.foreach_set(np.ascontiguousarray(pixels, dtype=np.float32).ravel())
    if pack:
        image.pack()
    return image


def random_pixels(height=3, width=5):
    pixels = RNG.random((height, width, 4)).astype(np.float32)
    pixels[..., 3] = 1.0
    return pixels


class Tree:
    """A material's node tree built in a few lines: Tree('M').bsdf('ShaderNodeBsdfDiffuse') ..."""

    def __init__(self, name):
        self.mat = bpy.data.materials.new(name)
        self.mat.use_nodes = True
        self.nodes, self.links = self.mat.node_tree.nodes, self.mat.node_tree.links
        self.nodes.clear()
        self.out = self.nodes.new("ShaderNodeOutputMaterial")

    def node(self, node_type, **props):
        n = self.nodes.new(node_type)
        for k, v in props.items():
            setattr(n, k, v)
        return n

    def image(self, image, **props):
        n = self.node("ShaderNodeTexImage", **props)
        n.image = image
        return n

    def link(self, from_socket, to_socket):
        self.links.new(from_socket, to_socket)

    def surface(self, node):
        self.link(node.outputs[0], self.out.inputs["Surface"])
        return self.mat


def textured(name, image, socket="Color", shader="ShaderNodeBsdfDiffuse", output="Color", **image_props):
    """A material whose shader's `socket` an Image Texture of `image` drives."""
    t = Tree(name)
    bsdf = t.node(shader)
    t.link(t.image(image, **image_props).outputs[output], bsdf.inputs[socket])
    return t.surface(bsdf)


def on_plane(mat, name="Plane", **kw):
    return builders.mesh_object(name, "plane", mat, **kw)


def quiet(log):
    """Nothing unsupported and no problem but the lights these scenes have none of."""
    return log.unsupported == {} and all("no lights" in p for p in log.problems)


def material_named(scene, name):
    (m,) = [m for m in scene.materials if m.name == name]
    return m


def mesh_named(scene, name):
    (m,) = [m for m in scene.meshes if m.name == name]
    return m


def test_packed_and_on_disk_byte_images_are_blender_bytes(empty_scene, tmp_path):
    packed_pixels, disk_pixels = random_pixels(3, 5), random_pixels(4, 2)
    packed = new_image("Packed", packed_pixels)
    saved = new_image("Saved", disk_pixels, pack=False)
    saved.filepath_raw, saved.file_format = str(tmp_path / "saved.png"), "PNG"
    saved.save()
    on_disk = bpy.data.images.load(str(tmp_path / "saved.png"))
    assert on_disk.packed_file is None and not on_disk.has_data  # not loaded until the export reads it
    on_plane(textured("P", packed), "A")
    on_plane(textured("D", on_disk), "B", location=(3, 0, 0))
    on_plane(textured("P2", packed, interpolation="Closest"), "C", location=(6, 0, 0))  # the same image again
    scene, log = export()
    assert [t.name for t in scene.textures] == ["Packed", "saved.png"]  # one per image
    for texture, pixels in zip(scene.textures, (packed_pixels, disk_pixels)):
        assert texture.pixels.dtype == np.uint8 and texture.pixels.shape == pixels.shape
        np.testing.assert_array_equal(texture.pixels, np.round(pixels * 255).astype(np.uint8))  # row 0 = bottom
        assert texture.colorspace == "srgb"
    p, p2 = material_named(scene, "P"), material_named(scene, "P2")
    assert p.textures["base_color"].texture == p2.textures["base_color"].texture == 0
    assert (p.textures["base_color"].interpolation, p2.textures["base_color"].interpolation) == ("linear", "closest")
    assert material_named(scene, "D").textures["base_color"].texture == 1
    assert quiet(log)


def test_float_images_are_float32_and_linear(empty_scene):
    pixels = random_pixels() * 4.0  # beyond 1: a float image's range
    on_plane(textured("F", new_image("HDR", pixels, float_buffer=True)))
    # Blender's float buffers are scene linear whatever the image's colour space says: the buffer as Blender holds
    # it, read as linear (Cycles' builtin float images; measured: a float image marked sRGB renders as stored).
    marked = new_image("Marked", pixels, float_buffer=True, colorspace="sRGB")
    on_plane(textured("S", marked), "Other", location=(3, 0, 0))
    scene, _ = export()
    hdr, srgb = scene.textures
    assert hdr.pixels.dtype == srgb.pixels.dtype == np.float32
    np.testing.assert_array_equal(hdr.pixels, pixels)
    np.testing.assert_array_equal(srgb.pixels, pixels)
    assert hdr.colorspace == srgb.colorspace == "linear"


@pytest.mark.parametrize("colorspace, expected, warned", [("sRGB", "srgb", False), ("Non-Color", "linear", False),
                                                          ("Linear", "linear", False), ("Raw", "linear", False),
                                                          ("XYZ", "linear", True), ("Filmic Log", "linear", True)])
def test_byte_image_colour_spaces(empty_scene, colorspace, expected, warned):
    on_plane(textured("M", new_image("Img", random_pixels(), colorspace=colorspace)))
    scene, log = export()
    assert scene.textures[0].colorspace == expected
    assert (f"image colour space '{colorspace}' (read as linear) (Img)" in log.warning_text()) == warned


def test_missing_image_is_magenta_with_a_warning(empty_scene):
    gone = bpy.data.images.new("Gone", 4, 4)
    gone.source, gone.filepath = "FILE", "//no/such/file.png"
    on_plane(textured("M", gone))
    empty = Tree("NoImage")
    bsdf = empty.node("ShaderNodeBsdfPrincipled")
    empty.link(empty.node("ShaderNodeTexImage").outputs["Color"], bsdf.inputs["Base Color"])
    on_plane(empty.surface(bsdf), "Other", location=(3, 0, 0))
    scene, log = export()
    assert [t.name for t in scene.textures] == ["Gone", "(no image)"]
    for texture in scene.textures:
        assert texture.pixels.dtype == np.float32 and texture.pixels.shape == (1, 1, 4)
        assert tuple(texture.pixels.ravel()) == (1.0, 0.0, 1.0, 1.0)
    text = log.warning_text()
    assert "image 'Gone' could not be read" in text and "magenta" in text
    assert "material 'NoImage' has no image" in text


def test_exported_pixels_are_read_only_so_renderers_share_them(empty_scene):
    # Issue 27: the compare mode's renderers (up to 20) each copied every texture; a read-only array is shared.
    on_plane(textured("P", new_image("Packed", random_pixels(8, 8))))
    on_plane(textured("F", new_image("HDR", random_pixels(8, 8), float_buffer=True)), "Other", location=(3, 0, 0))
    scene, _ = export()
    assert [t.pixels.flags.writeable for t in scene.textures] == [False, False]


def test_an_image_too_large_to_export_is_magenta_with_a_warning(empty_scene, monkeypatch):
    # Issue 27: the exporter's float copy of a huge image went past the machine's memory; now it is refused first.
    # (Half the memory stands in at 1 KiB here: a 16 x 16 RGBA image's float copy takes 4 KiB.)
    monkeypatch.setattr(sphrect, "default_memory_limit", lambda: 1024)
    on_plane(textured("M", new_image("Big", random_pixels(16, 16))))
    scene, log = export()
    assert tuple(scene.textures[0].pixels.ravel()) == (1.0, 0.0, 1.0, 1.0)
    assert "image 'Big' (16 x 16) needs 0.0 GiB to export, more than half the memory: magenta" in log.warning_text()


def test_partial_alpha_gives_the_colour_cycles_reads(empty_scene):
    """Measured in Cycles 3.4 (test_texture_parity's lookups): a straight-alpha byte image's colour comes
    multiplied by its alpha (its encoded bytes, truncated), and as stored when the node's Alpha output is used; a
    float image's buffer (premultiplied in Blender) comes as stored, divided by its alpha when Alpha is used;
    Non-Color images as stored either way.  An Alpha output linked to a node that reaches no output is unused."""
    pixels = random_pixels(2, 3)
    pixels[..., 3] = [[1.0, 0.5, 0.25], [0.0, 0.75, 1.0]]
    byte, floats = new_image("Bytes", pixels), new_image("Floats", pixels, float_buffer=True)
    data = new_image("Data", pixels, colorspace="Non-Color")
    for i, image in enumerate((byte, floats, data)):
        on_plane(textured(f"Color{i}", image), f"A{i}", location=(3 * i, 0, 0))
        alpha_used = textured(f"Alpha{i}", image)  # the same image, its Alpha output also used
        tree = alpha_used.node_tree
        tree.links.new(tree.nodes["Image Texture"].outputs["Alpha"], tree.nodes["Diffuse BSDF"].inputs["Roughness"])
        on_plane(alpha_used, f"B{i}", location=(3 * i, 3, 0))
    dangling = textured("Dangling", byte)  # Alpha linked to a node that reaches no output: Cycles drops it
    tree = dangling.node_tree
    tree.links.new(tree.nodes["Image Texture"].outputs["Alpha"], tree.nodes.new("ShaderNodeMath").inputs[0])
    on_plane(dangling, "C", location=(0, 6, 0))
    scene, log = export()
    texture = lambda name: scene.textures[material_named(scene, name).textures["base_color"].texture]
    alpha = pixels[..., 3:]
    as_bytes = lambda p: np.round(p * 255).astype(np.uint8)
    premultiplied = as_bytes(pixels).astype(int)
    premultiplied[..., :3] = premultiplied[..., :3] * premultiplied[..., 3:] // 255  # Cycles' integer premultiply
    byte_alpha = premultiplied[..., 3:] / 255  # unassociated: divided back by the alpha (in float: not bytes)
    expected = {"Color0": premultiplied.astype(np.uint8),
                "Alpha0": np.concatenate([premultiplied[..., :3] / 255 / np.where(byte_alpha > 0, byte_alpha, 1),
                                          byte_alpha], axis=2).astype(np.float32),
                "Color1": pixels,
                "Alpha1": np.concatenate([np.where((alpha > 0) & (alpha < 1), pixels[..., :3] / np.where(
                    alpha > 0, alpha, 1), pixels[..., :3]), alpha], axis=2).astype(np.float32),
                "Color2": as_bytes(pixels), "Alpha2": as_bytes(pixels), "Dangling": premultiplied.astype(np.uint8)}
    for name, values in expected.items():
        np.testing.assert_allclose(texture(name).pixels.astype(np.float64), values, atol=1e-6, err_msg=name)
    assert len(scene.textures) == 5  # the Non-Color image once
    assert texture("Alpha0").name == "Bytes (unassociated alpha)"


def test_interpolation_extension_output_and_what_is_approximated(empty_scene):
    image = new_image("Img", random_pixels())
    on_plane(textured("Clip", image, extension="CLIP", interpolation="Closest", output="Alpha"), "A")
    on_plane(textured("Cubic", image, interpolation="Cubic", projection="BOX", extension="EXTEND"), "B",
             location=(3, 0, 0))
    scene, log = export()
    clip, cubic = material_named(scene, "Clip").textures["base_color"], material_named(scene, "Cubic").textures[
        "base_color"]
    assert (clip.extension, clip.interpolation, clip.output) == ("clip", "closest", "alpha")
    assert (cubic.extension, cubic.interpolation, cubic.output) == ("extend", "linear", "color")
    text = log.warning_text()
    assert "Image Texture interpolation 'Cubic' (Linear used) (Cubic)" in text
    assert "Image Texture projection 'BOX' (Flat used) (Cubic)" in text
    assert "Clip" not in text


def principled_textured(image):
    """A Principled BSDF of Base Color, Roughness, Metallic, Specular and Emission each from an Image Texture (one
    image)."""
    t = Tree("PBR")
    bsdf = t.node("ShaderNodeBsdfPrincipled")
    bsdf.inputs["Emission Strength"].default_value = 0.5
    for socket in ("Base Color", "Roughness", "Metallic", "Specular", "Emission"):
        reroute = t.node("NodeReroute")  # links through reroutes are followed
        t.link(t.image(image).outputs["Color"], reroute.inputs[0])
        t.link(reroute.outputs[0], bsdf.inputs[socket])
    return t.surface(bsdf)


def test_every_textured_input_of_each_shader(empty_scene):
    image = new_image("Img", random_pixels(), colorspace="Non-Color")
    on_plane(principled_textured(image), "A")
    on_plane(textured("Glossy", image, "Roughness", shader="ShaderNodeBsdfGlossy"), "B", location=(3, 0, 0))
    glass = textured("Glass", image, "Roughness", shader="ShaderNodeBsdfGlass")
    on_plane(glass, "C", location=(6, 0, 0))
    tree = glass.node_tree
    tree.links.new(tree.nodes.new("ShaderNodeTexImage").outputs["Color"], tree.nodes["Glass BSDF"].inputs["Color"])
    scene, log = export()
    assert sorted(material_named(scene, "PBR").textures) == sorted(sphrect.scene.TEXTURED_INPUTS)
    assert material_named(scene, "PBR").kind == "principled"
    assert list(material_named(scene, "Glossy").textures) == ["roughness"]
    assert sorted(material_named(scene, "Glass").textures) == ["base_color", "roughness"]
    assert "PBR" not in log.warning_text() and "linked" not in log.warning_text()


def test_other_linked_inputs_stay_warnings_naming_the_node(empty_scene):
    image = new_image("Img", random_pixels())
    t = Tree("Other")
    bsdf = t.node("ShaderNodeBsdfPrincipled")
    t.link(t.node("ShaderNodeTexSky").outputs["Color"], bsdf.inputs["Base Color"])  # not compiled
    t.link(t.image(image).outputs["Color"], bsdf.inputs["Sheen Tint"])  # not one of TEXTURED_INPUTS
    math_node = t.node("ShaderNodeMath")
    t.link(t.image(image).outputs["Color"], math_node.inputs[0])
    t.link(math_node.outputs[0], bsdf.inputs["Roughness"])  # a texture through another node: a node program
    t.link(math_node.outputs[0], bsdf.inputs["Alpha"])  # (an Image Texture's is a mix factor: test_transparent_parity)
    on_plane(t.surface(bsdf))
    scene, log = export()
    assert material_named(scene, "Other").textures == {}
    assert list(material_named(scene, "Other").programs) == ["roughness"]  # test_node_programs.py
    text = log.warning_text()
    for warning in ("linked 'Base Color' input (Sky Texture)", "Principled Alpha linked from a node other than an "
                    "Image Texture (1 used)", "linked 'Sheen Tint' input (Image Texture)"):
        assert warning in text
    assert "Roughness" not in text


def mapped(name, image, vector_type, location, rotation, scale, source=("ShaderNodeTexCoord", "UV")):
    t = Tree(name)
    bsdf = t.node("ShaderNodeBsdfDiffuse")
    mapping = t.node("ShaderNodeMapping", vector_type=vector_type)
    for socket, value in (("Location", location), ("Rotation", rotation), ("Scale", scale)):
        if socket in mapping.inputs and mapping.inputs[socket].enabled:
            mapping.inputs[socket].default_value = value
    coordinates = t.node(source[0])
    t.link(coordinates.outputs[source[1]], mapping.inputs["Vector"])
    t.link(mapping.outputs["Vector"], t.image(image).inputs["Vector"])
    t.link(t.nodes["Image Texture"].outputs["Color"], bsdf.inputs["Color"])
    return t.surface(bsdf)


MAPPING = dict(location=(0.3, -0.2, 0.5), rotation=(0.4, -0.7, 1.1), scale=(2.0, 0.5, 3.0))


def test_mapping_point_texture_and_vector_transforms(empty_scene):
    image = new_image("Img", random_pixels())
    for i, kind in enumerate(("POINT", "TEXTURE", "VECTOR")):
        source = ("ShaderNodeTexCoord", "Generated") if kind == "TEXTURE" else ("ShaderNodeTexCoord", "UV")
        on_plane(mapped(kind, image, kind, source=source, **MAPPING), kind, location=(3 * i, 0, 0))
    scene, log = export()
    # Blender's Mapping Point: out = T R S in, Euler XYZ (mathutils' own composition, not the exporter's code).
    trs = np.array(mathutils.Matrix.LocRotScale(mathutils.Vector(MAPPING["location"]),
                                                mathutils.Euler(MAPPING["rotation"], "XYZ"),
                                                mathutils.Vector(MAPPING["scale"])))
    lookups = {k: material_named(scene, k).textures["base_color"] for k in ("POINT", "TEXTURE", "VECTOR")}
    np.testing.assert_allclose(lookups["POINT"].transform, trs[:3], atol=1e-6)
    np.testing.assert_allclose(lookups["TEXTURE"].transform, np.linalg.inv(trs)[:3], atol=1e-6)
    vector = trs.copy()
    vector[:3, 3] = 0
    np.testing.assert_allclose(lookups["VECTOR"].transform, vector[:3], atol=1e-6)
    assert [lookups[k].coordinates for k in ("POINT", "TEXTURE", "VECTOR")] == ["uv", "generated", "uv"]
    assert quiet(log)
    # The meshes carry what their material reads.
    assert mesh_named(scene, "POINT").uvs is not None and mesh_named(scene, "POINT").generated is None
    assert mesh_named(scene, "TEXTURE").uvs is None and mesh_named(scene, "TEXTURE").generated is not None


def test_unlinked_vector_and_uv_map_node_read_the_uvs_others_warn(empty_scene):
    image = new_image("Img", random_pixels())
    t = Tree("UVMapNode")
    bsdf = t.node("ShaderNodeBsdfDiffuse")
    uv_node = t.node("ShaderNodeUVMap")
    t.link(uv_node.outputs["UV"], t.image(image).inputs["Vector"])
    t.link(t.nodes["Image Texture"].outputs["Color"], bsdf.inputs["Color"])
    plane = on_plane(t.surface(bsdf), "A")
    plane.data.uv_layers.new(name="Second")  # not the active render one
    uv_node.uv_map = "Second"
    on_plane(mapped("Normal", image, "NORMAL", **MAPPING), "B", location=(3, 0, 0))
    on_plane(mapped("Object", image, "POINT", source=("ShaderNodeTexCoord", "Object"), **MAPPING), "C",
             location=(6, 0, 0))
    on_plane(textured("Unlinked", image), "D", location=(9, 0, 0))
    scene, log = export()
    for name in ("UVMapNode", "Normal", "Object", "Unlinked"):
        lookup = material_named(scene, name).textures["base_color"]
        assert lookup.coordinates == "uv"
        if name != "UVMapNode":
            np.testing.assert_array_equal(lookup.transform, np.eye(3, 4))
    text = log.warning_text()
    assert "UV map 'Second' named by a node, not the render UV map (that one used) (A)" in text
    assert "Mapping node of type 'NORMAL' (ignored) (Normal)" in text
    assert "Image Texture vector from 'Object' (UV used) (Object)" in text
    assert "Unlinked" not in text


def blender_corner_uvs(obj):
    """The render UV map at each loop-triangle corner, read one by one (the slow, obvious way)."""
    mesh = obj.data
    mesh.calc_loop_triangles()
    layer = mesh.uv_layers.active
    return np.array([[layer.data[l].uv[:] for l in tri.loops] for tri in mesh.loop_triangles])


def test_cube_uvs_per_corner_keep_seams(empty_scene):
    image = new_image("Img", random_pixels())
    cube = builders.mesh_object("Cube", "cube", textured("T", image), location=(1, 2, 3), rotation=(0.3, 0, 0))
    builders.mesh_object("Plain", "cube", builders.material("Plain"), location=(4, 0, 0))
    scene, log = export()
    mesh = mesh_named(scene, "Cube")
    expected = blender_corner_uvs(cube)
    assert mesh.uvs.dtype == np.float32 and mesh.uvs.shape == (36, 2)
    np.testing.assert_allclose(mesh.uvs[mesh.triangles], expected, atol=0)
    # Unwelded: the cube's 8 corners carry as many distinct UVs as Blender's loops give them (14 in the default
    # cube's cross layout: the seams).
    positions = np.round(mesh.vertices, 5)
    exported_pairs = {(tuple(p), tuple(uv)) for p, uv in zip(positions, mesh.uvs)}
    layer = cube.data.uv_layers.active
    blender_pairs = {(l.vertex_index, tuple(layer.data[l.index].uv)) for l in cube.data.loops}
    assert len({p for p, _ in exported_pairs}) == 8
    assert len(exported_pairs) == len(blender_pairs) == 14
    assert mesh_named(scene, "Plain").uvs is None and mesh_named(scene, "Plain").generated is None
    assert quiet(log)


def test_generated_coordinates_span_the_cube(empty_scene):
    image = new_image("Img", random_pixels())
    t = Tree("Gen")
    bsdf = t.node("ShaderNodeBsdfDiffuse")
    t.link(t.node("ShaderNodeTexCoord").outputs["Generated"], t.image(image).inputs["Vector"])
    t.link(t.nodes["Image Texture"].outputs["Color"], bsdf.inputs["Color"])
    cube = builders.mesh_object("Cube", "cube", t.surface(bsdf), location=(5, 0, 0), scale=(2, 1, 0.5), size=3)
    scene, log = export()
    mesh = mesh_named(scene, "Cube")
    assert mesh.uvs is None and mesh.generated.dtype == np.float32
    # Auto texture space = the bounds: local (-1.5..1.5) -> (0..1) on every axis, whatever the object's scale.
    assert mesh.generated.min() == pytest.approx(0.0, abs=1e-6) and mesh.generated.max() == pytest.approx(1.0)
    world = np.array(cube.matrix_world)
    back_to_local = (np.linalg.inv(world) @ np.c_[mesh.vertices, np.ones(len(mesh.vertices))].T).T[:, :3]
    np.testing.assert_allclose(mesh.generated, (back_to_local + 1.5) / 3.0, atol=1e-5)
    assert quiet(log)


def test_textured_mesh_without_uv_map_reads_zero_with_a_warning(empty_scene):
    plane = on_plane(textured("T", new_image("Img", random_pixels())))
    plane.data.uv_layers.remove(plane.data.uv_layers[0])
    scene, log = export()
    assert not mesh_named(scene, "Plane").uvs.any()
    assert "textured meshes without a UV map (UVs (0, 0), as Cycles reads) (Plane)" in log.warning_text()


def mix_of(name, image, fac_image=True, outer_fac=None):
    """Mix(red diffuse, blue diffuse) with its factor from `image` (or 0.25), optionally inside
    Mix(that, a green diffuse, outer_fac)."""
    t = Tree(name)
    red, blue = t.node("ShaderNodeBsdfDiffuse"), t.node("ShaderNodeBsdfDiffuse")
    red.inputs["Color"].default_value, blue.inputs["Color"].default_value = (1, 0, 0, 1), (0, 0, 1, 1)
    mix = t.node("ShaderNodeMixShader")
    t.link(red.outputs[0], mix.inputs[1])
    t.link(blue.outputs[0], mix.inputs[2])
    if fac_image:
        t.link(t.image(image).outputs["Color"], mix.inputs[0])
    else:
        mix.inputs[0].default_value = 0.25
    if outer_fac is None:
        return t.surface(mix)
    green = t.node("ShaderNodeBsdfDiffuse")
    green.inputs["Color"].default_value = (0, 1, 0, 1)
    outer = t.node("ShaderNodeMixShader")
    outer.inputs[0].default_value = outer_fac
    t.link(mix.outputs[0], outer.inputs[1])
    t.link(green.outputs[0], outer.inputs[2])
    return t.surface(outer)


def test_texture_driven_mix_factors_and_their_complements(empty_scene):
    image = new_image("Mask", random_pixels(), colorspace="Non-Color")
    on_plane(mix_of("Mix", image), "A")
    on_plane(mix_of("Nested", image, outer_fac=0.4), "B", location=(3, 0, 0))
    on_plane(mix_of("Plain", image, fac_image=False), "C", location=(6, 0, 0))
    scene, log = export()
    mix = material_named(scene, "Mix")
    assert mix.kind == "mix"
    got = [(l.weight, l.material.base_color, [f.complement for f in l.factors]) for l in mix.layers]
    assert got == [(1.0, (1.0, 0.0, 0.0), [True]), (1.0, (0.0, 0.0, 1.0), [False])]
    assert all(f.lookup.texture == 0 and f.lookup.coordinates == "uv" for l in mix.layers for f in l.factors)
    nested = material_named(scene, "Nested")
    got = [(round(l.weight, 6), l.material.base_color, [f.complement for f in l.factors]) for l in nested.layers]
    assert got == [(0.6, (1.0, 0.0, 0.0), [True]), (0.6, (0.0, 0.0, 1.0), [False]), (0.4, (0.0, 1.0, 0.0), [])]
    # Untextured diffuse layers still merge into one diffuse (the diffuse-only kernel).
    plain = material_named(scene, "Plain")
    assert plain.kind == "diffuse" and plain.base_color == pytest.approx((0.75, 0.0, 0.25))
    assert mesh_named(scene, "A").uvs is not None and mesh_named(scene, "C").uvs is None
    assert "grey diffuse" not in log.warning_text()


def luminance_mean(pixels):
    """The mean of a Non-Color byte image's colour read as a scalar (Rec.709 luminance, Cycles' rgb_to_y)."""
    return float((np.round(pixels[..., :3] * 255) / 255 @ np.array([0.2126, 0.7152, 0.0722])).mean())


def test_textured_principled_layers_become_one_the_renderer_holds(empty_scene):
    """The renderer's mix holds one Principled BSDF: two under a texture-driven factor are averaged, each weighted
    by its factor's image mean (warned), and the scene builds."""
    pixels = random_pixels()
    image = new_image("Mask", pixels, colorspace="Non-Color")
    t = Tree("PP")
    a, b = t.node("ShaderNodeBsdfPrincipled"), t.node("ShaderNodeBsdfPrincipled")
    a.inputs["Base Color"].default_value, b.inputs["Base Color"].default_value = (0.9, 0.1, 0.1, 1), (0.1, 0.2, 0.7, 1)
    b.inputs["Roughness"].default_value = 0.9
    mix = t.node("ShaderNodeMixShader")
    t.link(a.outputs[0], mix.inputs[1])
    t.link(b.outputs[0], mix.inputs[2])
    fac = t.image(image)
    t.link(fac.outputs["Color"], mix.inputs[0])
    t.link(fac.outputs["Color"], b.inputs["Base Color"])
    on_plane(t.surface(mix))
    mean = luminance_mean(pixels)
    scene, log = export()
    pp = material_named(scene, "PP")
    (layer,) = pp.layers if pp.kind == "mix" else [sphrect.MaterialLayer(1.0, pp)]
    assert layer.factors == [] and layer.weight == pytest.approx(1.0)
    assert layer.material.roughness == pytest.approx((1 - mean) * 0.5 + mean * 0.9)
    assert "base_color" in layer.material.textures  # the textured one's
    assert "a mix of 2 Principled BSDFs, textured ones among them" in log.warning_text()
    sphrect.Renderer(scene, techniques="rectangle")  # builds: one Principled BSDF


def test_emission_under_a_texture_factor_is_a_program(empty_scene):
    pixels = random_pixels()
    image = new_image("Mask", pixels, colorspace="Non-Color")
    t = Tree("Glow")
    diffuse, glow = t.node("ShaderNodeBsdfDiffuse"), t.node("ShaderNodeEmission")
    glow.inputs["Strength"].default_value = 4.0
    principled = t.node("ShaderNodeBsdfPrincipled")  # its own emission under the complement
    principled.inputs["Emission"].default_value = (1.0, 0.5, 0.25, 1.0)
    principled.inputs["Emission Strength"].default_value = 2.0
    inner, outer = t.node("ShaderNodeMixShader"), t.node("ShaderNodeMixShader")
    t.link(diffuse.outputs[0], inner.inputs[1])
    t.link(glow.outputs[0], inner.inputs[2])
    t.link(t.image(image).outputs["Color"], inner.inputs[0])
    t.link(principled.outputs[0], outer.inputs[1])
    t.link(inner.outputs[0], outer.inputs[2])
    outer.inputs[0].default_value = 0.5
    t.link(t.nodes["Image Texture"].outputs["Color"], outer.inputs[0])  # the same mask drives both
    on_plane(t.surface(outer))
    scene, log = export()
    glow_material = material_named(scene, "Glow")
    # Both emissions vary with the mask (node programs of the image times the factors, summed: test_node_programs.py).
    assert glow_material.emission == (1.0, 1.0, 1.0) and "emission" in glow_material.programs
    assert sum(i.op == "image" for i in glow_material.programs["emission"].instructions) == 3  # fac, fac; 1 - fac
    assert all(l.material.emission == (0.0, 0.0, 0.0) for l in glow_material.layers)
    assert "Glow" not in log.warning_text()
    sphrect.Renderer(scene, techniques="rectangle")  # builds: no layer under a factor emits


def normal_mapped(name, image, strength=0.7, space="TANGENT", shader="ShaderNodeBsdfPrincipled"):
    t = Tree(name)
    bsdf = t.node(shader)
    normal_map = t.node("ShaderNodeNormalMap", space=space)
    normal_map.inputs["Strength"].default_value = strength
    t.link(t.image(image).outputs["Color"], normal_map.inputs["Color"])
    t.link(normal_map.outputs["Normal"], bsdf.inputs["Normal"])
    return t.surface(bsdf)


def test_normal_maps(empty_scene):
    image = new_image("Bumps", random_pixels(), colorspace="Non-Color")
    on_plane(normal_mapped("NM", image), "A", rotation=(0.2, 0.0, 0.7), scale=(0.5, 2.0, 1.0))
    on_plane(normal_mapped("Object", image, space="OBJECT"), "B", location=(3, 0, 0))
    t = Tree("Bump")
    bsdf = t.node("ShaderNodeBsdfDiffuse")
    bump = t.node("ShaderNodeBump")
    t.link(t.image(image).outputs["Color"], bump.inputs["Height"])
    t.link(bump.outputs["Normal"], bsdf.inputs["Normal"])
    on_plane(t.surface(bsdf), "C", location=(6, 0, 0))
    scene, log = export()
    nm = material_named(scene, "NM")
    assert nm.normal_map is not None and nm.normal_map.texture == 0 and nm.normal_map_strength == pytest.approx(0.7)
    assert nm.textures == {}
    assert mesh_named(scene, "A").uvs is not None  # the normal map's tangents need them
    # ... and the object's linear map (Cycles applies normal maps in the object's space).
    matrix = np.array(bpy.data.objects["A"].matrix_world)
    np.testing.assert_allclose(mesh_named(scene, "A").object_linear, matrix[:3, :3])
    assert mesh_named(scene, "B").object_linear is None
    assert material_named(scene, "Object").normal_map is None and material_named(scene, "Bump").normal_map is None
    assert material_named(scene, "Bump").normal_program is not None  # a Bump node's graph (test_bump.py)
    assert mesh_named(scene, "B").uvs is None
    text = log.warning_text()
    assert "Normal Map space 'OBJECT' (ignored) (Object)" in text
    assert "Bump" not in text
    assert "NM" not in text


def test_a_mix_shares_its_layers_normal_map(empty_scene):
    image = new_image("Bumps", random_pixels(), colorspace="Non-Color")
    other = new_image("Other", random_pixels(), colorspace="Non-Color")

    def two_layers(name, second_image):
        t = Tree(name)
        mix = t.node("ShaderNodeMixShader")
        for i, img in ((1, image), (2, second_image)):
            bsdf = t.node("ShaderNodeBsdfDiffuse" if i == 1 else "ShaderNodeBsdfGlossy")
            normal_map = t.node("ShaderNodeNormalMap")
            t.link(t.image(img).outputs["Color"], normal_map.inputs["Color"])
            t.link(normal_map.outputs["Normal"], bsdf.inputs["Normal"])
            t.link(bsdf.outputs[0], mix.inputs[i])
        return t.surface(mix)
    on_plane(two_layers("Same", image), "A")
    on_plane(two_layers("Different", other), "B", location=(3, 0, 0))
    scene, log = export()
    for name, texture in (("Same", 0), ("Different", 0)):
        m = material_named(scene, name)
        assert m.kind == "mix" and m.normal_map.texture == texture
        assert all(l.material.normal_map is None for l in m.layers)
    text = log.warning_text()
    assert "shaders of a mix with different normal maps or Bump nodes (the first one used for all) (Different)" in text
    assert "(Same)" not in text


def test_textures_survive_the_scene_file(empty_scene, tmp_path):
    image = new_image("Img", random_pixels())
    on_plane(textured("T", image))
    scene, _ = export()
    path = str(tmp_path / "t.sphrect.npz")
    sphrect.save_scene(scene, path)
    loaded = sphrect.load_scene(path)
    np.testing.assert_array_equal(loaded.textures[0].pixels, scene.textures[0].pixels)
    as_json = lambda materials: json.loads(json.dumps([dataclasses.asdict(m) for m in materials]))
    assert as_json(loaded.materials) == as_json(scene.materials)
    assert loaded.materials[1].textures["base_color"] == scene.materials[1].textures["base_color"]
    np.testing.assert_array_equal(mesh_named(loaded, "Plane").uvs, mesh_named(scene, "Plane").uvs)


def test_an_emitters_image_colour_is_a_lookup(empty_scene):
    """An Emission shader whose Color an Image Texture drives (a lit logo, a screen): the lookup on the emission
    (Material.textures["emission"]), the Strength its multiplier, unwarned; a missing image is Cycles' magenta (the
    lookup of a missing texture) -- a third-party studio file was 2.6x too dark with the default colour."""
    pixels = random_pixels(4, 6)
    for name, image in (("Screen", new_image("Img", pixels, colorspace="Non-Color")), ("Lost", None)):
        t = Tree(name)
        emission = t.node("ShaderNodeEmission")
        emission.inputs["Strength"].default_value = 3.0
        image_node = t.image(image) if image is not None else t.node("ShaderNodeTexImage")
        t.link(image_node.outputs["Color"], emission.inputs["Color"])
        on_plane(t.surface(emission), name=name, location=(3.0 * len(bpy.data.objects), 0.0, 0.0))
    scene, log = export()
    for name in ("Screen", "Lost"):
        m = material_named(scene, name)
        assert m.emission == pytest.approx((3.0, 3.0, 3.0)) and "emission" in m.textures
    lost = scene.textures[material_named(scene, "Lost").textures["emission"].texture]
    assert sphrect.texture_color_mean(lost.pixels, lost.colorspace == "srgb") == pytest.approx((1.0, 0.0, 1.0)) \
        if lost.pixels is not None else lost.path == ""
    assert "emitter" not in log.warning_text()


def test_a_world_mirror_ball_image_is_baked(empty_scene):
    """A world the renderer cannot take as it is (here a mirror-ball Environment Texture; equirectangular ones are
    image worlds, test_environment_world.py) is baked by Cycles into an image world (world_bake.py, stood in for
    here), not its image's mean colour."""
    from test_environment_world import stand_in_bake
    pixels = random_pixels(4, 8)
    world = bpy.data.worlds.new("Sky")
    world.use_nodes = True
    nodes = world.node_tree.nodes
    env = nodes.new("ShaderNodeTexEnvironment")
    env.projection = "MIRROR_BALL"
    env.image = new_image("Sky", pixels, colorspace="Non-Color")
    world.node_tree.links.new(env.outputs["Color"], nodes["Background"].inputs["Color"])
    empty_scene.world = world
    ground = Tree("Ground")
    on_plane(ground.surface(ground.node("ShaderNodeBsdfDiffuse")))
    with stand_in_bake() as baked:
        scene, log = export()
    assert baked == ["Sky"] and scene.world.environment is not None
    assert "mean colour" not in log.warning_text()
