"""A light's node tree as Cycles 3.4 shades a light: its Emission's colour x strength multiplies the light's, and an
Image Texture on that colour is a rectangle or ellipse light's texture, read where Cycles reads it on a light --
Geometry > Parametric along the light's axes, Texture Coordinate > Object / Generated the point in world space, the
UV map (a light has none) the image's corner.

Render comparison as test_cycles_parity's (Cycles 2048 spp, SPHRECT 512, fixed seeds, mean relative difference over
lit 4x4 blocks), bound 1% as the other exact models'; each scene also fails with the texture ignored or turned (the
test's own check that it can fail)."""
import math

import bpy
import numpy as np
import pytest

from conftest import builders, export, set_resolution
from test_cycles_parity import HEIGHT, WIDTH, difference_to_cycles, mean_relative_difference
from test_texture_export import new_image
from test_textured_emitter_parity import window_with_bars

TOLERANCE = 0.01


def light_tree(light, source="parametric", strength=1.0, color_image=None, mapping_scale=None):
    """Gives `light` (a bpy Light) an Emission of `strength` whose Color is `color_image` (an Image Texture, Closest)
    read at `source` ('parametric', 'object', 'generated', 'uv', 'none': unlinked), through a Mapping of
    `mapping_scale` if given."""
    light.use_nodes = True
    tree = light.node_tree
    emission = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeEmission")
    emission.inputs["Strength"].default_value = strength
    if color_image is None:
        return emission
    tex = tree.nodes.new("ShaderNodeTexImage")
    tex.image, tex.interpolation = color_image, "Closest"
    tree.links.new(tex.outputs["Color"], emission.inputs["Color"])
    vector = None
    if source == "parametric":
        vector = tree.nodes.new("ShaderNodeNewGeometry").outputs["Parametric"]
    elif source in {"object", "generated", "uv"}:
        vector = tree.nodes.new("ShaderNodeTexCoord").outputs[source.title() if source != "uv" else "UV"]
    if vector is not None and mapping_scale is not None:
        mapping = tree.nodes.new("ShaderNodeMapping")
        mapping.inputs["Scale"].default_value = mapping_scale
        tree.links.new(vector, mapping.inputs["Vector"])
        vector = mapping.outputs["Vector"]
    if vector is not None:
        tree.links.new(vector, tex.inputs["Vector"])
    return emission


def textured_light_scene(scene, shape="RECTANGLE", source="parametric", mapping_scale=None):
    """A 1.6 x 1 m area light (turned 30 degrees about Z, tilted 20 about X) 1.2 m above a grey floor, its colour a
    window with bars, seen by the camera."""
    builders.mesh_object("Floor", "plane", builders.material("Floor", (0.6, 0.6, 0.6)), size=8.0)
    obj = builders.area_light("Window", shape=shape, size=1.6, size_y=1.0, power=150.0, location=(0.2, 0.4, 1.2),
                              rotation=(math.radians(20), 0.0, math.radians(30)))
    image = bpy.data.images.get("Bars") or new_image("Bars", window_with_bars(), colorspace="sRGB")
    light_tree(obj.data, source, strength=2.0, color_image=image, mapping_scale=mapping_scale)
    builders.camera((0.0, -3.4, 2.6), (0.2, 0.4, 0.4), lens=28.0)
    set_resolution(scene, WIDTH, HEIGHT)
    scene.sphrect.technique = "RECTANGLE"
    bpy.context.view_layer.update()
    return scene


@pytest.mark.slow
@pytest.mark.parametrize("shape, source, mapping_scale", [("RECTANGLE", "parametric", None),
                                                          ("ELLIPSE", "parametric", None),
                                                          ("RECTANGLE", "object", (0.7, 0.7, 1.0))])
def test_textured_area_light_matches_cycles(empty_scene, tmp_path, shape, source, mapping_scale):
    scene = textured_light_scene(empty_scene, shape, source, mapping_scale)
    exported, log = export()
    (light,) = exported.lights
    assert light.texture is not None
    assert not [k for k in log.unsupported if "light" in k or "Image Texture" in k], log.unsupported
    # 8 light samples: the world-space image's many small tiles are noisy at 2 (1.2% at 512 x 1 sample; 0.36% at 4096).
    difference, ours, cycles = difference_to_cycles(scene, f"textured {shape.lower()} light ({source})", tmp_path,
                                                    light_samples=8)
    assert cycles[..., :3].max() > 0
    assert difference <= TOLERANCE
    # The comparison can fail: the same light with its image turned half a turn (its transform about the centre).
    light.texture.transform = (np.array([[-1, 0, 0, 1], [0, -1, 0, 1], [0, 0, 1, 0], [0, 0, 0, 1]]) @
                               np.vstack([light.texture.transform, [0, 0, 0, 1]]))[:3].tolist()
    import sphrect
    turned = sphrect.Renderer(exported, techniques=["rectangle"], seed=1)
    turned.render(256)
    assert mean_relative_difference(turned.image("rectangle"), cycles) > 3 * TOLERANCE


def test_emission_colour_and_strength_multiply_every_light(empty_scene):
    """A point light's Emission (colour (0.5, 1, 1), strength 3) scales its intensity, unwarned; a Blackbody of 3000 K
    on the colour folds to Cycles' colour (node programs), unwarned; a Noise Texture there varies over the light:
    warned, the colour's own value used; a tree without a surface on its output emits nothing (skipped)."""
    point = builders.other_light("Plain", "POINT", 100.0)
    scaled = builders.other_light("Scaled", "POINT", 100.0, location=(2, 0, 0))
    emission = light_tree(scaled.data, strength=3.0)
    emission.inputs["Color"].default_value = (0.5, 1.0, 1.0, 1.0)
    warm = builders.other_light("Warm", "POINT", 100.0, location=(4, 0, 0))
    tree = warm.data.node_tree if warm.data.use_nodes else None
    emission = light_tree(warm.data)
    blackbody = warm.data.node_tree.nodes.new("ShaderNodeBlackbody")
    blackbody.inputs["Temperature"].default_value = 3000.0
    warm.data.node_tree.links.new(blackbody.outputs[0], emission.inputs["Color"])
    noisy = builders.other_light("Noisy", "POINT", 100.0, location=(8, 0, 0))
    emission = light_tree(noisy.data)
    noise = noisy.data.node_tree.nodes.new("ShaderNodeTexNoise")
    noisy.data.node_tree.links.new(noise.outputs["Color"], emission.inputs["Color"])
    dark = builders.other_light("Dark", "POINT", 100.0, location=(6, 0, 0))
    light_tree(dark.data)
    out = next(n for n in dark.data.node_tree.nodes if n.bl_idname == "ShaderNodeOutputLight")
    for link in list(out.inputs["Surface"].links):
        dark.data.node_tree.links.remove(link)
    del tree, point
    scene, log = export()
    lights = {l.name: l for l in scene.lights}
    assert set(lights) == {"Plain", "Scaled", "Warm", "Noisy"}
    plain = lights["Plain"].intensity[0]
    assert np.allclose(lights["Scaled"].intensity, np.array([1.5, 3.0, 3.0]) * plain)
    import sphrect
    warm_rgb = np.maximum(np.asarray(sphrect._native.svm_color.blackbody(3000.0), dtype=float).ravel()[:3], 0)
    assert np.allclose(lights["Warm"].intensity, warm_rgb * plain, rtol=1e-5)
    assert np.allclose(lights["Noisy"].intensity, plain)  # the Color socket's own white
    warnings = log.warning_text()
    assert "a node graph varying over a light on its 'Color' (its own value used) (Noisy)" in warnings
    assert "Scaled" not in warnings and "Plain" not in warnings and "Warm" not in warnings
    assert "light 'Dark' has no power: skipped" in "\n".join(log.problems)


def test_uv_and_unlinked_vectors_read_the_corner_texel(empty_scene):
    """A light has no UV map: Cycles reads (0, 0, 0) -- the image's corner texel over the whole light -- for an
    unlinked vector and Texture Coordinate > UV alike; an unsupported vector source is warned."""
    pixels = np.zeros((2, 2, 4), np.float32)
    pixels[..., 3] = 1
    pixels[0, 0, :3] = (1.0, 0.0, 0.0)  # row 0 the bottom: texel (0, 0) red, the rest black
    image = new_image("Corner", pixels)
    for i, source in enumerate(["none", "uv", "normal"]):
        obj = builders.area_light(f"L_{source}", power=100.0, location=(3 * i, 0, 2))
        emission = light_tree(obj.data, "uv" if source == "uv" else "none", color_image=image)
        if source == "normal":
            tree = obj.data.node_tree
            tex = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeTexImage")
            tree.links.new(tree.nodes.new("ShaderNodeTexCoord").outputs["Normal"], tex.inputs["Vector"])
        del emission
    scene, log = export()
    lights = {l.name: l for l in scene.lights}
    for name in ("L_none", "L_uv"):
        assert np.allclose(np.array(lights[name].texture.transform)[:, :4], 0.0), name
    assert "Image Texture vector of a light from 'Normal' (UV used) (L_normal)" in log.warning_text()
