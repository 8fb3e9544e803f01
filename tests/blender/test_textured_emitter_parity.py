"""Textured emitters as Cycles 3.4 shows them at max_bounces 0: an emissive plane whose Emission Color an Image
Texture drives (a window with bars, mostly dark) lights a floor; SPHRECT evaluates the image per point for camera
rays, BSDF rays and light samples and samples the plane by its blocks' power and solid angle.

Render comparison as test_cycles_parity's (Cycles 2048 spp, SPHRECT 512, fixed seeds, mean relative difference over
lit 4x4 blocks), bound 1% as the other exact models'.  Also the exporter's side: the lookup on the emission, no
warning; under a texture-driven Mix factor a node program of the image times the factor."""
import math

import bpy
import numpy as np
import pytest

from conftest import builders, export, set_resolution
from test_cycles_parity import HEIGHT, WIDTH, difference_to_cycles
from test_texture_export import Tree, material_named, new_image

TOLERANCE = 0.01


def window_with_bars(size=32):
    """A bright window, two thirds of it covered by dark bars, in a dark frame (RGBA, row 0 the bottom)."""
    pixels = np.full((size, size, 4), 0.02, np.float32)
    pixels[..., 3] = 1.0
    inner = slice(size // 8, size - size // 8)
    pixels[inner, inner, :3] = (1.0, 0.85, 0.6)
    for k in range(size // 8, size - size // 8, 6):
        pixels[inner, k:k + 4, :3] = 0.02
    return pixels


def emitter_material(name="Window", strength=6.0, interpolation="Linear"):
    t = Tree(name)
    emission = t.node("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = strength
    image = t.image(new_image("Bars", window_with_bars(), colorspace="sRGB"), interpolation=interpolation)
    t.link(image.outputs["Color"], emission.inputs["Color"])
    return t.surface(emission)


def window_scene(scene):
    builders.mesh_object("Floor", "plane", builders.material("Floor", (0.6, 0.6, 0.6)), size=6.0)
    # The window 1.5 m up, tilted towards the camera's side of the floor, seen by the camera too.
    builders.mesh_object("Window", "plane", emitter_material(), location=(0.0, 0.6, 1.5),
                         rotation=(math.radians(200), 0.0, 0.0), scale=(1.0, 0.6, 1.0))
    builders.camera((0.0, -3.2, 3.0), (0.0, 0.2, 0.3), lens=30.0)
    set_resolution(scene, WIDTH, HEIGHT)
    scene.sphrect.technique = "RECTANGLE"
    bpy.context.view_layer.update()
    return scene


@pytest.mark.slow
def test_textured_emitter_lighting_a_floor_matches_cycles(empty_scene, tmp_path):
    scene = window_scene(empty_scene)
    exported, log = export()
    window = material_named(exported, "Window")
    assert "emission" in window.textures and window.emission == pytest.approx((6.0, 6.0, 6.0))
    assert not [k for k in log.unsupported if "emitter" in k or "emission" in k]
    difference, ours, cycles = difference_to_cycles(scene, "textured emitter", tmp_path)
    assert cycles[..., :3].max() > 0
    assert difference <= TOLERANCE


def test_emission_image_is_a_lookup_and_a_mix_factor_keeps_the_mean(empty_scene):
    """An Emission shader and a Principled Emission from an Image Texture: a lookup on the emission, strength the
    multiplier, unwarned; under a texture-driven Mix Shader factor the image's mean colour, warned."""
    builders.mesh_object("A", "plane", emitter_material("Direct", strength=3.0))
    t = Tree("Principled")
    p = t.node("ShaderNodeBsdfPrincipled")
    p.inputs["Emission Strength"].default_value = 2.0
    t.link(t.image(bpy.data.images["Bars"]).outputs["Color"], p.inputs["Emission"])
    builders.mesh_object("B", "plane", t.surface(p), location=(3.0, 0.0, 0.0))
    t = Tree("UnderFactor")
    mix = t.node("ShaderNodeMixShader")
    emission = t.node("ShaderNodeEmission")
    t.link(t.image(bpy.data.images["Bars"]).outputs["Color"], emission.inputs["Color"])
    t.link(t.image(bpy.data.images["Bars"]).outputs["Alpha"], mix.inputs[0])
    t.link(emission.outputs[0], mix.inputs[2])
    t.link(t.node("ShaderNodeBsdfDiffuse").outputs[0], mix.inputs[1])
    builders.mesh_object("C", "plane", t.surface(mix), location=(6.0, 0.0, 0.0))
    scene, log = export()
    direct, principled = material_named(scene, "Direct"), material_named(scene, "Principled")
    assert direct.emission == pytest.approx((3.0,) * 3) and "emission" in direct.textures
    assert principled.emission == pytest.approx((2.0,) * 3) and "emission" in principled.textures
    under = material_named(scene, "UnderFactor")
    # Under the factor: a node program of the image times the factor's (test_node_programs.py), unwarned.
    assert "emission" not in under.textures and "emission" in under.programs and max(under.emission) > 0
    warnings = log.warning_text()
    assert "UnderFactor" not in warnings
    assert "Direct" not in warnings and "Principled" not in warnings
