"""Node groups (io/exporter/node_groups.py), read as Cycles inlines them: a material whose shaders sit in a group
(nested, with inputs linked or set outside) exports as the same material without the group, and renders as Cycles
renders it."""
import dataclasses

import bpy
import numpy as np
import pytest

from conftest import export
from test_cycles_parity import difference_to_cycles
from test_glass_parity import sphere_scene
from test_texture_export import Tree, new_image, random_pixels

TOLERANCE = 0.01


def new_group(name, inputs, output):
    """A shader node group of `inputs` ((socket type, name), ...) and one shader output: (group, its Group Input
    node, its Group Output node)."""
    group = bpy.data.node_groups.new(name, "ShaderNodeTree")
    for socket_type, socket_name in inputs:
        group.inputs.new(socket_type, socket_name)
    group.outputs.new("NodeSocketShader", output)
    return group, group.nodes.new("NodeGroupInput"), group.nodes.new("NodeGroupOutput")


def principled_group(name="Shiny"):
    """A group: Principled BSDF (metallic 0.3) with Base Color and Roughness from the group's inputs, through a
    reroute, its BSDF the group's output."""
    group, gin, gout = new_group(name, [("NodeSocketColor", "Color"), ("NodeSocketFloat", "Roughness")], "BSDF")
    nodes, links = group.nodes, group.links
    bsdf = nodes.new("ShaderNodeBsdfPrincipled")
    bsdf.inputs["Metallic"].default_value = 0.3
    reroute = nodes.new("NodeReroute")
    links.new(gin.outputs["Color"], reroute.inputs[0])
    links.new(reroute.outputs[0], bsdf.inputs["Base Color"])
    links.new(gin.outputs["Roughness"], bsdf.inputs["Roughness"])
    links.new(bsdf.outputs[0], gout.inputs["BSDF"])
    return group


def nested_group():
    """A group holding principled_group() mixed 0.3 with a Glossy BSDF, the Mix factor from its own input."""
    group, gin, gout = new_group("Outer", [("NodeSocketColor", "Color"), ("NodeSocketFloat", "Fac")], "Shader")
    nodes, links = group.nodes, group.links
    inner = nodes.new("ShaderNodeGroup")
    inner.node_tree = principled_group("Inner")
    inner.inputs["Roughness"].default_value = 0.45
    links.new(gin.outputs["Color"], inner.inputs["Color"])
    glossy = nodes.new("ShaderNodeBsdfGlossy")
    glossy.inputs["Roughness"].default_value = 0.25
    mix = nodes.new("ShaderNodeMixShader")
    links.new(gin.outputs["Fac"], mix.inputs[0])
    links.new(inner.outputs[0], mix.inputs[1])
    links.new(glossy.outputs[0], mix.inputs[2])
    links.new(mix.outputs[0], gout.inputs["Shader"])
    return group


def grouped(name, group, **inputs):
    t = Tree(name)
    node = t.node("ShaderNodeGroup")
    node.node_tree = group
    for socket, value in inputs.items():
        node.inputs[socket].default_value = value
    return t, node


def flat_principled(name, color, roughness):
    t = Tree(name)
    bsdf = t.node("ShaderNodeBsdfPrincipled")
    bsdf.inputs["Metallic"].default_value = 0.3
    bsdf.inputs["Base Color"].default_value = color
    bsdf.inputs["Roughness"].default_value = roughness
    return t, bsdf


def same(a, b):
    return dataclasses.replace(a, name="") == dataclasses.replace(b, name="")


def test_a_grouped_material_exports_as_its_flat_twin(empty_scene):
    image = new_image("Img", random_pixels())
    t, node = grouped("Grouped", principled_group(), Roughness=0.4)
    t.link(t.image(image).outputs["Color"], node.inputs["Color"])  # linked outside the group
    t.surface(node)
    # (A linked input's own value is unused; the group's is its interface default, black.)
    f, bsdf = flat_principled("Flat", (0.0, 0.0, 0.0, 1.0), 0.4)
    f.link(f.image(image).outputs["Color"], bsdf.inputs["Base Color"])
    f.surface(bsdf)
    constant, _ = grouped("Constant", principled_group("Shiny2"), Roughness=0.6, Color=(0.2, 0.5, 0.7, 1.0))
    constant.surface(_)
    twin, twin_bsdf = flat_principled("Twin", (0.2, 0.5, 0.7, 1.0), 0.6)
    twin.surface(twin_bsdf)
    for i, mat in enumerate((t.mat, f.mat, constant.mat, twin.mat)):
        bpy.ops.mesh.primitive_plane_add(location=(3.0 * i, 0.0, 0.0))
        bpy.context.active_object.data.materials.append(mat)
    scene, log = export()
    by_name = {m.name: m for m in scene.materials}
    assert by_name["Grouped"].kind == "principled" and "base_color" in by_name["Grouped"].textures
    assert same(by_name["Grouped"], by_name["Flat"])
    assert same(by_name["Constant"], by_name["Twin"])
    assert "Group" not in log.warning_text()


def test_a_nested_group_with_a_mix_matches_cycles(empty_scene, tmp_path):
    t, node = grouped("Nested", nested_group(), Fac=0.3, Color=(0.8, 0.35, 0.2, 1.0))
    mat = t.surface(node)
    scene = sphere_scene(empty_scene, mat)
    exported, log = export()
    (m,) = [m for m in exported.materials if m.name == "Nested"]
    assert sorted((l.material.kind, round(l.weight, 6)) for l in m.layers) == [("glossy_bsdf", 0.3),
                                                                               ("principled", 0.7)]
    (p,) = [l.material for l in m.layers if l.material.kind == "principled"]
    assert (p.roughness, p.metallic) == (pytest.approx(0.45), pytest.approx(0.3))
    assert p.base_color == pytest.approx((0.8, 0.35, 0.2))
    difference, ours, cycles = difference_to_cycles(scene, "nested node groups", tmp_path)
    assert difference <= TOLERANCE
    assert np.abs(ours[..., :3].mean() / cycles[..., :3].mean() - 1) < 0.01
