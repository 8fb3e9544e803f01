"""The links the exporter follows, as Cycles 3.4 compiles a node tree (io/exporter/node_groups.py), and the cost of
following them (issue 27, classes 3, 6 and 10): muted and invalid links are left out, muted nodes pass an input
on along Blender's internal links, a cycle is broken where Blender marks a link invalid, and a Mix / Add Shader
graph exports in time linear in its nodes however many paths cross it."""
import inspect
import sys

import bpy
import pytest

from conftest import addon_module, export
from test_cycles_parity import difference_to_cycles
from test_glass_parity import sphere_scene
from test_node_groups import new_group
from test_texture_export import Tree, material_named, new_image, on_plane, random_pixels

RED, GREY, BLUE = (0.8, 0.05, 0.05, 1.0), (0.5, 0.5, 0.5, 1.0), (0.05, 0.1, 0.8, 1.0)
TOLERANCE = 0.01
BALANCE_TOLERANCE = 0.0005  # the cases differ by 1e-5; the muted Mix rendered red (before) by 0.002


def diffuse(t, color):
    node = t.node("ShaderNodeBsdfDiffuse")
    node.inputs["Color"].default_value = color
    return node


def mixed(t, fac, first, second, kind="ShaderNodeMixShader"):
    """A Mix (fac) or Add Shader (fac None) of two nodes' outputs (None: that input unlinked)."""
    mix = t.node(kind)
    shaders = list(mix.inputs)[-2:]
    if fac is not None:
        mix.inputs[0].default_value = fac
    for node, socket in zip((first, second), shaders):
        if node is not None:
            t.link(node.outputs[0], socket)
    return mix


def mute_link(to_socket):
    to_socket.links[0].is_muted = True


def rgb(color, scale=1.0):
    return pytest.approx(tuple(scale * c for c in color[:3]))


def exported_material(t):
    """The exported material of Tree `t` on a plane, and the log."""
    on_plane(t.mat, t.mat.name)
    scene, log = export()
    return material_named(scene, t.mat.name), log


# -- class 3: export linear in the graph ----------------------------------------------------------------------------

DOUBLINGS = 20


def doubling_chain(name, kind, fac=None, factor_image=None):
    """A Diffuse BSDF, then DOUBLINGS Mix / Add Shaders each taking the previous node on both shader inputs: 2^20
    paths from the output to the Diffuse BSDF through DOUBLINGS + 2 nodes."""
    t = Tree(name)
    node = diffuse(t, GREY)
    for _ in range(DOUBLINGS):
        node = mixed(t, fac, node, node, kind)
        if factor_image is not None:
            t.link(t.image(factor_image).outputs["Color"], node.inputs[0])
    t.surface(node)
    return t


@pytest.fixture
def link_reads(monkeypatch):
    """Counts the exporter's reads of what feeds a shader input (materials.follow_reroutes) and stops the export
    past a budget far above a linear walk's: a walk of the graph's 2^20 paths fails at once rather than after
    hours (no timing involved)."""
    materials = addon_module("io.exporter.materials")
    follow, reads = materials.follow_reroutes, []

    def counted(socket):
        reads.append(socket)
        if len(reads) > 50 * (DOUBLINGS + 2):
            raise RuntimeError(f"{len(reads)} link reads for a graph of {DOUBLINGS + 2} nodes: not linear")
        return follow(socket)
    monkeypatch.setattr(materials, "follow_reroutes", counted)
    return reads


def test_add_shader_doublings_export_once_per_node(empty_scene, link_reads):
    """Add Shader sums closures: N Add Shaders, each doubling the previous one, are the Diffuse BSDF of weight 2^N
    (one diffuse of 2^N its colour).  The code before walked every path (2^N; 115 s at N = 16) and fails the read
    budget; now each node is read once."""
    m, log = exported_material(doubling_chain("Doublings", "ShaderNodeAddShader"))
    assert (m.kind, m.base_color) == ("diffuse", rgb(GREY, 2.0 ** DOUBLINGS))
    assert len(link_reads) < 10 * (DOUBLINGS + 2)


def test_mix_shader_doublings_export_once_per_node(empty_scene, link_reads):
    """Mix Shaders of a constant factor taking one node on both inputs weigh it (1 - f) + f = 1 each; so do
    texture-driven factors (the image's (1 - fac) + fac of the same closures: exactly the closures, no factor
    kept).  Both chains fail the read budget on the code before."""
    image = new_image("Fac", random_pixels())
    for name, fac, factor_image in (("Constant", 0.3, None), ("Textured", None, image)):
        m, _ = exported_material(doubling_chain(name, "ShaderNodeMixShader", fac, factor_image))
        assert (m.kind, m.base_color, m.textures) == ("diffuse", rgb(GREY), {}), name


def test_a_chain_deeper_than_pythons_stack_exports(empty_scene):
    """400 Add Shaders in a row, each adding one Diffuse BSDF to the previous sum, exported with Python's stack
    200 frames deep (Blender builds a longer chain slowly): the Diffuse of weight 401.  The code before recursed
    once per node: a RecursionError."""
    t = Tree("Deep")
    leaf = diffuse(t, GREY)
    node = mixed(t, None, leaf, leaf, "ShaderNodeAddShader")
    for _ in range(399):
        node = mixed(t, None, node, leaf, "ShaderNodeAddShader")
    t.surface(node)
    on_plane(t.mat, t.mat.name)
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(len(inspect.stack()) + 200)
    try:
        scene, _ = export()
    finally:
        sys.setrecursionlimit(limit)
    m = material_named(scene, "Deep")
    assert (m.kind, m.base_color) == ("diffuse", rgb(GREY, 401.0))


def test_a_shader_reached_twice_is_one_layer_of_its_summed_weight(empty_scene):
    """A Glossy BSDF under both sides of a Mix (0.3 of it directly, 0.7 through an Add Shader with a Diffuse):
    one layer of weight 0.7 + 0.3 (Cycles sums its closures; the code before gave two layers of the same lobe, the
    same image)."""
    t = Tree("Shared")
    glossy = t.node("ShaderNodeBsdfGlossy")
    t.surface(mixed(t, 0.3, mixed(t, None, glossy, diffuse(t, RED), "ShaderNodeAddShader"), glossy))
    m, _ = exported_material(t)
    assert sorted((l.material.kind, l.weight) for l in m.layers) == [("diffuse", pytest.approx(0.7)),
                                                                     ("glossy_bsdf", pytest.approx(1.0))]


# -- class 6: muted and invalid links, muted nodes ------------------------------------------------------------------

def test_muted_links_are_left_out(empty_scene):
    """A muted link is no link (Cycles skips it): the input's own value, no shader on a Surface or Mix input, no
    volume, texture, factor, Mapping or normal map.  The code before followed each of these links."""
    image = new_image("Img", random_pixels())
    surface = Tree("MutedSurface")
    surface.surface(diffuse(surface, RED))
    mute_link(surface.out.inputs["Surface"])
    color = Tree("MutedColor")
    bsdf = diffuse(color, RED)
    color.link(color.image(image).outputs["Color"], bsdf.inputs["Color"])
    mute_link(bsdf.inputs["Color"])
    color.surface(bsdf)
    factor = Tree("MutedFactor")
    mix = mixed(factor, 0.25, diffuse(factor, RED), diffuse(factor, GREY))
    factor.link(factor.image(image).outputs["Color"], mix.inputs[0])
    mute_link(mix.inputs[0])
    factor.surface(mix)
    side = Tree("MutedSide")
    mix = mixed(side, 0.5, diffuse(side, RED), diffuse(side, GREY))
    mute_link(mix.inputs[2])
    side.surface(mix)
    mapping = Tree("MutedMapping")
    bsdf, tex, node = diffuse(mapping, RED), mapping.image(image), mapping.node("ShaderNodeMapping")
    node.inputs["Location"].default_value = (0.5, 0.0, 0.0)
    mapping.link(mapping.node("ShaderNodeTexCoord").outputs["Generated"], node.inputs["Vector"])
    mapping.link(node.outputs["Vector"], tex.inputs["Vector"])
    mute_link(tex.inputs["Vector"])
    mapping.link(tex.outputs["Color"], bsdf.inputs["Color"])
    mapping.surface(bsdf)
    volume = Tree("MutedVolume")  # no Surface link and a muted Volume one: neither (black), not volume-only
    volume.link(volume.node("ShaderNodeVolumeScatter").outputs[0], volume.out.inputs["Volume"])
    mute_link(volume.out.inputs["Volume"])
    normal_maps = {}
    for name in ("MutedNormalLink", "MutedNormalMap"):
        t = normal_maps[name] = Tree(name)
        bsdf, normal_map = t.node("ShaderNodeBsdfPrincipled"), t.node("ShaderNodeNormalMap")
        t.link(t.image(image).outputs["Color"], normal_map.inputs["Color"])
        t.link(normal_map.outputs["Normal"], bsdf.inputs["Normal"])
        t.surface(bsdf)
    mute_link(normal_maps["MutedNormalLink"].nodes["Principled BSDF"].inputs["Normal"])
    normal_maps["MutedNormalMap"].nodes["Normal Map"].mute = True  # passes its Strength, unlinked: 0, no normal
    for t in (surface, color, factor, side, mapping, volume, *normal_maps.values()):
        on_plane(t.mat, t.mat.name)
    scene, log = export()
    assert "volume-only" not in log.warning_text() and "material volumes" not in log.warning_text()
    assert material_named(scene, "MutedVolume").base_color == (0.0, 0.0, 0.0)
    assert [material_named(scene, name).normal_map for name in normal_maps] == [None, None]
    assert material_named(scene, "MutedSurface").base_color == (0.0, 0.0, 0.0)
    assert "materials without a surface shader (black) (MutedSurface, MutedVolume)" in log.warning_text()
    m = material_named(scene, "MutedColor")
    assert (m.base_color, m.textures) == (rgb(RED), {})
    m = material_named(scene, "MutedFactor")
    assert (m.kind, m.base_color) == ("diffuse", rgb((0.75 * RED[0] + 0.25 * GREY[0], 0.75 * RED[1] + 0.25 * GREY[1],
                                                     0.75 * RED[2] + 0.25 * GREY[2])))
    assert material_named(scene, "MutedSide").base_color == rgb(RED, 0.5)
    lookup = material_named(scene, "MutedMapping").textures["base_color"]
    assert (lookup.coordinates, lookup.transform) == ("uv", [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]])


def test_muted_nodes_pass_their_internal_links(empty_scene):
    """Cycles replaces a muted node by Blender's internal links (node.internal_links): a muted Mix Shader passes a
    linked shader input on (the first), a muted Add Shader its linked one, a muted Mapping its Vector; a muted node
    without an internal link to an output (Image Texture, a BSDF, the Material Output) leaves what it feeds
    unlinked; an unlinked input a muted node or a reroute passes on reads 0 (Cycles' proxy's value: measured
    black in Cycles 3.4).  The code before used each muted node as if it were not."""
    image = new_image("Img", random_pixels())
    cases = {}
    muted = []
    for name, build in (("MutedMix", lambda t: mixed(t, 1.0, diffuse(t, GREY), diffuse(t, RED))),
                        ("MutedMixSecond", lambda t: mixed(t, 0.0, None, diffuse(t, RED))),
                        ("MutedAdd", lambda t: mixed(t, None, None, diffuse(t, RED), "ShaderNodeAddShader")),
                        ("MutedBsdf", lambda t: diffuse(t, RED))):
        t = cases[name] = Tree(name)
        muted.append(build(t))
        t.surface(muted[-1])
    t = cases["MutedOutput"] = Tree("MutedOutput")
    t.surface(diffuse(t, RED))
    t.out.mute = True
    t = cases["MutedImage"] = Tree("MutedImage")
    bsdf, tex = diffuse(t, RED), t.image(image)
    t.link(tex.outputs["Color"], bsdf.inputs["Color"])
    t.surface(bsdf)
    tex.mute = True
    t = cases["MutedGamma"] = Tree("MutedGamma")
    bsdf, gamma = diffuse(t, RED), t.node("ShaderNodeGamma")
    gamma.inputs["Color"].default_value = GREY
    t.link(gamma.outputs["Color"], bsdf.inputs["Color"])
    t.surface(bsdf)
    gamma.mute = True
    t = cases["Reroute"] = Tree("Reroute")
    bsdf = diffuse(t, RED)
    t.link(t.node("NodeReroute").outputs[0], bsdf.inputs["Color"])
    t.surface(bsdf)
    t = cases["MutedMapping"] = Tree("MutedMapping")
    bsdf, tex, mapping = diffuse(t, RED), t.image(image), t.node("ShaderNodeMapping")
    mapping.inputs["Location"].default_value = (0.5, 0.0, 0.0)
    t.link(t.node("ShaderNodeTexCoord").outputs["Generated"], mapping.inputs["Vector"])
    t.link(mapping.outputs["Vector"], tex.inputs["Vector"])
    t.link(tex.outputs["Color"], bsdf.inputs["Color"])
    t.surface(bsdf)
    mapping.mute = True
    assert [(l.from_socket.name, l.to_socket.name) for l in mapping.internal_links] == [("Vector", "Vector")]
    for node in muted:
        node.mute = True
    for t in cases.values():
        on_plane(t.mat, t.mat.name)
    scene, log = export()
    color = lambda name: material_named(scene, name).base_color
    assert color("MutedMix") == rgb(GREY) and color("MutedMixSecond") == rgb(RED) and color("MutedAdd") == rgb(RED)
    assert color("MutedBsdf") == color("MutedOutput") == (0.0, 0.0, 0.0)
    assert "materials without a surface shader (black) (MutedBsdf, MutedOutput)" in log.warning_text()
    m = material_named(scene, "MutedImage")
    assert (m.base_color, m.textures) == (rgb(RED), {})
    assert color("MutedGamma") == color("Reroute") == (0.0, 0.0, 0.0)
    lookup = material_named(scene, "MutedMapping").textures["base_color"]
    assert (lookup.coordinates, lookup.transform) == ("generated", [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]])


def tinting_group():
    """A group mixing its Shader input half and half with a blue Diffuse BSDF, its Fac linked from outside."""
    group, gin, gout = new_group("Tint", [("NodeSocketShader", "Shader"), ("NodeSocketFloat", "Fac")], "Shader")
    nodes, links = group.nodes, group.links
    mix, blue = nodes.new("ShaderNodeMixShader"), nodes.new("ShaderNodeBsdfDiffuse")
    blue.inputs["Color"].default_value = BLUE
    links.new(gin.outputs["Shader"], mix.inputs[1])
    links.new(blue.outputs[0], mix.inputs[2])
    links.new(gin.outputs["Fac"], mix.inputs[0])
    links.new(mix.outputs[0], gout.inputs["Shader"])
    return group


def test_muted_group_nodes_and_links_inside_groups(empty_scene):
    """A muted Group node passes its shader input on; a muted link inside a group is left out there (the Mix
    factor's own value, 0.5, not the Group node's input, 1)."""
    group = tinting_group()
    cases = {}
    for name in ("Grouped", "MutedGroup", "MutedInside"):
        t = cases[name] = Tree(name)
        node = t.node("ShaderNodeGroup")
        node.node_tree = group if name != "MutedInside" else group.copy()
        node.inputs["Fac"].default_value = 1.0
        t.link(diffuse(t, RED).outputs[0], node.inputs["Shader"])
        t.surface(node)
        on_plane(t.mat, name)
    cases["MutedGroup"].nodes["Group"].mute = True
    inner = cases["MutedInside"].nodes["Group"].node_tree
    inner.nodes["Mix Shader"].inputs[0].default_value = 0.5
    mute_link(inner.nodes["Mix Shader"].inputs[0])
    scene, _ = export()
    color = lambda name: material_named(scene, name).base_color
    assert color("Grouped") == rgb(BLUE)
    assert color("MutedGroup") == rgb(RED)
    assert color("MutedInside") == rgb(tuple(0.5 * (r + b) for r, b in zip(RED, BLUE)))


def test_invalid_links_are_left_out(empty_scene):
    """A link Blender marks invalid (here a shader output into a Mix factor, a float) is no link to Cycles: the
    factor's own value (the code before read it as a linked factor it does not model: grey diffuse)."""
    t = Tree("Invalid")
    mix = mixed(t, 0.25, diffuse(t, RED), diffuse(t, GREY))
    t.link(diffuse(t, BLUE).outputs[0], mix.inputs[0])
    assert not mix.inputs[0].links[0].is_valid
    t.surface(mix)
    m, log = exported_material(t)
    assert m.base_color == rgb(tuple(0.75 * r + 0.25 * g for r, g in zip(RED, GREY)))
    assert "grey diffuse" not in log.warning_text()


def test_muted_world_nodes_and_links(empty_scene):
    """The world's Background colour from an Environment Texture through a muted link is its own; a muted Volume
    Scatter is no medium; a muted Background is a black world."""
    world = bpy.context.scene.world
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    nodes.clear()
    out, background = nodes.new("ShaderNodeOutputWorld"), nodes.new("ShaderNodeBackground")
    background.inputs["Color"].default_value = GREY
    links.new(background.outputs[0], out.inputs["Surface"])
    environment = nodes.new("ShaderNodeTexEnvironment")
    environment.image = new_image("Sky", random_pixels())
    links.new(environment.outputs["Color"], background.inputs["Color"]).is_muted = True
    scatter = nodes.new("ShaderNodeVolumeScatter")
    links.new(scatter.outputs[0], out.inputs["Volume"])
    scatter.mute = True
    scene, log = export()
    assert (scene.world.background, scene.world.medium) == (rgb(GREY), None)
    assert "Environment" not in log.warning_text()
    background.mute = True
    assert export()[0].world.background == (0.0, 0.0, 0.0)


# -- class 10: cycles -----------------------------------------------------------------------------------------------

def mix_cycle():
    """Two Mix Shaders (0.5) feeding each other's first shader input, each with a Diffuse on its second (red on
    the one the output reads, grey on the other): Blender marks one of the two links between them invalid."""
    t = Tree("Cycle")
    a, b = mixed(t, 0.5, None, diffuse(t, RED)), mixed(t, 0.5, None, diffuse(t, GREY))
    t.link(b.outputs[0], a.inputs[1])
    t.link(a.outputs[0], b.inputs[1])
    t.surface(a)
    return t, a, b


def test_a_mix_shader_cycle_is_broken_where_blender_marks_it_invalid(empty_scene):
    """Blender 3.4.1 marks one link of the cycle invalid (here the first made, from A into B), Cycles ignores it:
    A = 0.5 red + 0.5 B, B = 0.5 grey.  The code before recursed round the cycle: a RecursionError."""
    t, a, b = mix_cycle()
    into_a, into_b = a.inputs[1].links[0], b.inputs[1].links[0]
    assert [into_a.is_valid, into_b.is_valid] == [True, False]
    m, _ = exported_material(t)
    assert (m.kind, m.base_color) == ("diffuse", rgb(tuple(0.5 * r + 0.25 * g for r, g in zip(RED, GREY))))


def test_groups_nested_too_deep_are_warned_and_left_out(empty_scene):
    """Groups nested 17 deep (MAX_GROUP_DEPTH 16): the link through the deepest is left out and said so (Blender
    refuses a group inside itself; the code before left it out silently)."""
    inner, _, gout = new_group("Level0", [], "Shader")
    red = inner.nodes.new("ShaderNodeBsdfDiffuse")
    red.inputs["Color"].default_value = RED
    inner.links.new(red.outputs[0], gout.inputs[0])
    for level in range(1, 17):
        outer, _, gout = new_group(f"Level{level}", [], "Shader")
        node = outer.nodes.new("ShaderNodeGroup")
        node.node_tree = inner
        outer.links.new(node.outputs[0], gout.inputs[0])
        inner = outer
    levels = bpy.data.node_groups
    # "Both" holds Level0 at the top first, then again 17 deep in Level16.
    for name, groups in (("Deep16", ["Level15"]), ("Deep17", ["Level16"]), ("Both", ["Level0", "Level16"])):
        t = Tree(name)
        for group in groups:
            node = t.node("ShaderNodeGroup")
            node.node_tree = levels[group]
        t.surface(node)
        on_plane(t.mat, name)
    scene, log = export()
    results = {name: material_named(scene, name).base_color for name in ("Deep16", "Deep17", "Both")}
    assert results == {"Deep16": rgb(RED), "Deep17": (0.0, 0.0, 0.0), "Both": (0.0, 0.0, 0.0)}
    assert "node groups nested more than 16 deep (the links through the deeper ones left out) (Deep17, Both)" \
        in log.warning_text()


# -- renders: Cycles' image -----------------------------------------------------------------------------------------

def muted_mix(t):
    """The issue's case: a muted Mix Shader of factor 1 between a grey and a red Diffuse (Cycles: grey)."""
    mix = mixed(t, 1.0, diffuse(t, GREY), diffuse(t, RED))
    t.surface(mix)
    mix.mute = True


def shared_glossy(t):
    glossy = t.node("ShaderNodeBsdfGlossy")
    glossy.inputs["Roughness"].default_value = 0.3
    t.surface(mixed(t, 0.3, mixed(t, None, glossy, diffuse(t, RED), "ShaderNodeAddShader"), glossy))


RENDERED = {"muted_mix": muted_mix, "shared_glossy": shared_glossy, "mix_cycle": None}


@pytest.mark.slow
@pytest.mark.parametrize("case", sorted(RENDERED))
def test_graph_renders_as_cycles_renders_it(empty_scene, case, tmp_path):
    """The muted Mix Shader of the issue (Cycles grey, the code before red), a shader reached on two paths, and
    the Mix Shader cycle (the code before: a RecursionError failing the render)."""
    if RENDERED[case] is None:
        t = mix_cycle()[0]
    else:
        t = Tree(case)
        RENDERED[case](t)
    scene = sphere_scene(empty_scene, t.mat)
    difference, ours, cycles = difference_to_cycles(scene, f"graph {case}", tmp_path)
    # The image's colour balance: the plane, grey, dilutes a wrong sphere's colour in the mean difference.
    balance = lambda image: image[..., :3].sum(axis=(0, 1)) / image[..., :3].sum()
    print(f"graph {case}: colour balance ours {balance(ours)}, Cycles {balance(cycles)}")
    assert difference <= TOLERANCE
    assert abs(balance(ours) - balance(cycles)).max() <= BALANCE_TOLERANCE
