"""The Light Path node (render/svm/program.h RayContext) against Cycles 3.4: scenes whose look rests on it render as
Cycles renders them (test_cycles_parity's measure: mean relative difference over 4x4 blocks <= 1%), and the node
replaced by its socket's own value, as before the renderer knew it, is clearly further off (>= 5%: the test can
fail).  The two renders are SPHRECT's at fixed seeds and Cycles' deterministic one; measured figures in
docs/materials.md (Light Path)."""
import math

import bpy
import pytest

from conftest import addon_module, builders, export
from test_node_programs import Case, check, combine, node_values_against_cycles, parity_view
from test_texture_export import Tree, material_named

NODE_MISSING_AT_LEAST = 0.05  # a render with the node replaced by its own value is at least this far from Cycles
OUTPUTS = ("Is Camera Ray", "Is Shadow Ray", "Is Diffuse Ray", "Is Glossy Ray", "Is Singular Ray", "Is Reflection Ray",
           "Is Transmission Ray", "Ray Length", "Ray Depth", "Diffuse Depth", "Glossy Depth", "Transparent Depth",
           "Transmission Depth")


def output_case(name):
    """The Emission colour (the output, Generated x, Generated y): the output as a camera ray's hit reads it."""
    def out(t, a, b, gx, gy):
        return combine(t, t.node("ShaderNodeLightPath").outputs[name], gx, gy)
    return Case(f"Light Path {name}", out)


def test_every_output_of_a_camera_ray_hit_matches_cycles(empty_scene, tmp_path):
    """test_node_programs' per-node harness (max abs difference <= 1e-3, relative above 1): each output of the node
    at camera rays' hits on planes under an orthographic camera (Is Camera Ray 1, Ray Length from the near clipping
    plane, every other output 0)."""
    check(node_values_against_cycles(empty_scene, [output_case(name) for name in OUTPUTS], tmp_path))


def transparent_for(t, output, shader):
    """`shader` mixed with a Transparent BSDF by the Light Path's `output`: transparent to those rays."""
    mix = t.node("ShaderNodeMixShader")
    t.link(t.node("ShaderNodeLightPath").outputs[output], mix.inputs[0])
    t.link(shader.outputs[0], mix.inputs[1])
    t.link(t.node("ShaderNodeBsdfTransparent").outputs[0], mix.inputs[2])
    return t.surface(mix)


def camera_invisible_emitter():
    """An Emission mixed with a Transparent BSDF by Is Camera Ray: the camera sees through it, it lights the rest."""
    t = Tree("Hidden glow")
    glow = t.node("ShaderNodeEmission")
    glow.inputs["Color"].default_value = (1.0, 0.7, 0.4, 1)
    glow.inputs["Strength"].default_value = 6.0
    return transparent_for(t, "Is Camera Ray", glow)


def shadowless_occluder():
    """A diffuse plate mixed with a Transparent BSDF by Is Shadow Ray: seen, but casting no shadow."""
    t = Tree("No shadow")
    diffuse = t.node("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (0.2, 0.5, 0.8, 1)
    return transparent_for(t, "Is Shadow Ray", diffuse)


def ray_kind_emitter():
    """An Emission whose colour is bluish for diffuse rays and orange for the others (camera, light samples, glossy
    rays), its strength 2 + the ray's length (a camera ray's a tenth of it, so that the floor weighs in the
    measure): each way of reaching an emitter reads another value, and a light sample and a BSDF ray of the same
    direction disagree as they do in Cycles."""
    t = Tree("Ray kinds")
    light_path = t.node("ShaderNodeLightPath")
    color = t.node("ShaderNodeMixRGB", blend_type="MIX")
    color.inputs["Color1"].default_value = (1.0, 0.45, 0.1, 1)
    color.inputs["Color2"].default_value = (0.4, 0.45, 0.9, 1)
    t.link(light_path.outputs["Is Diffuse Ray"], color.inputs["Fac"])
    strength = t.node("ShaderNodeMath", operation="ADD")
    t.link(light_path.outputs["Ray Length"], strength.inputs[0])
    strength.inputs[1].default_value = 2.0
    dim = t.node("ShaderNodeMath", operation="MULTIPLY_ADD")
    t.link(light_path.outputs["Is Camera Ray"], dim.inputs[0])
    dim.inputs[1].default_value, dim.inputs[2].default_value = -0.9, 1.0
    product = t.node("ShaderNodeMath", operation="MULTIPLY")
    t.link(strength.outputs[0], product.inputs[0])
    t.link(dim.outputs[0], product.inputs[1])
    glow = t.node("ShaderNodeEmission")
    t.link(color.outputs[0], glow.inputs["Color"])
    t.link(product.outputs[0], glow.inputs["Strength"])
    return t.surface(glow)


def depth_glow():
    """An Emission whose strength is 1 + Transparent Depth, seen by the camera through tinted Transparent BSDFs."""
    t = Tree("Depth glow")
    strength = t.node("ShaderNodeMath", operation="ADD")
    t.link(t.node("ShaderNodeLightPath").outputs["Transparent Depth"], strength.inputs[0])
    strength.inputs[1].default_value = 1.0
    glow = t.node("ShaderNodeEmission")
    glow.inputs["Color"].default_value = (0.9, 0.6, 0.3, 1)
    t.link(strength.outputs[0], glow.inputs["Strength"])
    return t.surface(glow)


def tinted_glass():
    t = Tree("Tint")
    clear = t.node("ShaderNodeBsdfTransparent")
    clear.inputs["Color"].default_value = (0.9, 0.95, 0.9, 1)  # white alone the exporter leaves out
    return t.surface(clear)


def floor(kind="diffuse"):
    if kind == "diffuse":
        return builders.mesh_object("Floor", "plane", builders.material("Floor", (0.8, 0.8, 0.8)), size=6.0)
    return builders.mesh_object("Floor", "plane", builders.material("Floor", (0.7, 0.7, 0.7), kind="principled",
                                                                    roughness=0.35), size=6.0)


def build(case):
    """The scene of `case`; returns the name of the material holding the node."""
    if case == "camera_invisible_emitter":
        floor()
        builders.mesh_object("Panel", "plane", camera_invisible_emitter(), size=1.2, location=(0.0, 0.3, 0.9),
                             rotation=(math.radians(20), 0.0, 0.0))
        builders.mesh_object("Box", "cube", builders.material("Box", (0.7, 0.4, 0.2)), size=0.5,
                             location=(0.6, -0.2, 0.25), rotation=(0.0, 0.0, 0.5))
        parity_view(bpy.context.scene, light=False)
        return "Hidden glow"
    if case == "shadowless_occluder":
        floor()
        builders.mesh_object("Plate", "plane", shadowless_occluder(), size=1.0, location=(0.3, 0.0, 1.0))
        builders.mesh_object("Box", "cube", builders.material("Box", (0.7, 0.4, 0.2)), size=0.5,
                             location=(-0.8, 0.4, 0.25), rotation=(0.0, 0.0, 0.5))
        parity_view(bpy.context.scene, light=True)
        return "No shadow"
    if case == "transparent_depth":
        builders.mesh_object("Glow", "plane", depth_glow(), size=4.0)
        tint = tinted_glass()
        builders.mesh_object("Pane 1", "plane", tint, size=1.6, location=(-0.4, 0.0, 0.4))
        builders.mesh_object("Pane 2", "plane", tint, size=1.6, location=(0.4, 0.3, 0.8))
        parity_view(bpy.context.scene, light=False)
        return "Depth glow"
    floor(kind="principled")
    builders.mesh_object("Panel", "plane", ray_kind_emitter(), size=1.0, location=(0.0, 0.6, 0.8),
                         rotation=(math.radians(35), 0.0, 0.0))
    parity_view(bpy.context.scene, light=False)
    return "Ray kinds"


@pytest.mark.slow
@pytest.mark.parametrize("case", ["camera_invisible_emitter", "shadowless_occluder", "ray_kinds", "transparent_depth"])
def test_light_path_scenes_render_as_in_cycles(empty_scene, tmp_path, case, monkeypatch):
    """Each case within 1% of Cycles, unwarned; with the node unknown to the compiler (its outputs read their own
    value, 0, as before) at least NODE_MISSING_AT_LEAST off."""
    from test_cycles_parity import difference_to_cycles
    scene = empty_scene
    name = build(case)
    exported, log = export()
    assert name not in log.warning_text()
    assert any(i.op == "global" for p in _programs(material_named(exported, name)) for i in p.instructions)
    difference, ours, cycles = difference_to_cycles(scene, f"Light Path, {case}", tmp_path)
    assert difference <= 0.01
    node_program = addon_module("io.exporter.node_program")
    monkeypatch.delitem(node_program._NODE_COMPILERS, "ShaderNodeLightPath")
    without, _, _ = difference_to_cycles(scene, f"Light Path, {case}, the node ignored", tmp_path, cycles=cycles)
    assert without >= NODE_MISSING_AT_LEAST


def _programs(material):
    """Every NodeProgram of a sphrect.Material (its inputs', its layers' factors', recursively)."""
    yield from (p for p in material.programs.values() if p is not None)
    for layer in material.layers:
        yield from (f.program for f in layer.factors if f.program is not None)
        yield from _programs(layer.material)


def test_only_the_linked_outputs_are_compiled(empty_scene):
    """As Cycles' LightPathNode::compile: a program reads the outputs something is linked from, each once, and the
    node is not warned."""
    t = Tree("Two outputs")
    light_path = t.node("ShaderNodeLightPath")
    add = t.node("ShaderNodeMath", operation="ADD")
    t.link(light_path.outputs["Ray Depth"], add.inputs[0])
    t.link(light_path.outputs["Is Glossy Ray"], add.inputs[1])
    times = t.node("ShaderNodeMath", operation="MULTIPLY")
    t.link(light_path.outputs["Ray Depth"], times.inputs[0])
    t.link(add.outputs[0], times.inputs[1])
    glow = t.node("ShaderNodeEmission")
    t.link(times.outputs[0], glow.inputs["Strength"])
    builders.mesh_object("Glow", "plane", t.surface(glow))
    exported, log = export()
    assert "Two outputs" not in log.warning_text()
    program = material_named(exported, "Two outputs").programs["emission"]
    node_program = addon_module("io.exporter.node_program")
    sphrect = addon_module("native").load_sphrect()
    assert node_program.program_globals(sphrect, program) == {"ray_depth", "is_glossy_ray"}
    assert sum(i.op == "global" for i in program.instructions) == 2
