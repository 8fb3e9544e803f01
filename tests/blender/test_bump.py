"""The Bump node (render/svm shading_nodes.h BumpNormal, the compiler's triple Height, the renderer's camera ray
differentials) against Cycles 3.4.

Per node (as test_node_programs.py): a grid of planes under an orthographic camera, each an Emission whose Color is
0.5 + 0.5 N of a case's Bump normal (or a Layer Weight reading it), Cycles at 1 sample through the pixel centres.
The exported program is evaluated at each pixel's exact hit (read from a render of the Generated coordinates) with
Cycles' compact ray differential there: an orthographic camera's dP is one pixel's width in the world, the Height's
copies read the position-dependent inputs at P + dP a and P + dP b, (a, b) = make_orthonormals(+z).  Max abs
difference <= 1e-3.  The same grid rendered by SPHRECT itself (its dP and shifted inputs from the hit) is compared
too.  Then a parity render: a perspective view of a noise-bumped Principled floor and sphere under an area light,
blurred relative L1 <= 1% against Cycles, where the unbumped render is clearly further."""
import dataclasses

import bpy
import numpy as np
import pytest

from conftest import export, render
from test_node_programs import (CELL, COLUMNS, Case, cell_hits, cycles_grid, parity_view, render_cycles,
                                sphrect_module)
from test_texture_export import Tree, material_named

pytestmark = pytest.mark.slow

TOLERANCE = 1e-3
# Cycles' make_orthonormals of the planes' true normal +z: the directions of the Height's dx and dy copies.
DX, DY = np.array([1.0, -1.0, 0.0]) / np.sqrt(2.0), np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0)


def shown(t, normal):
    """0.5 + 0.5 normal (Vector Math Multiply Add): a colour an Emission shows as it is."""
    m = t.node("ShaderNodeVectorMath", operation="MULTIPLY_ADD")
    t.link(normal, m.inputs[0])
    m.inputs[1].default_value, m.inputs[2].default_value = (0.5, 0.5, 0.5), (0.5, 0.5, 0.5)
    return m.outputs[0]


def bump(t, height, strength=1.0, distance=1.0, invert=False, normal=None):
    b = t.node("ShaderNodeBump", invert=invert)
    t.link(height, b.inputs["Height"])
    b.inputs["Strength"].default_value, b.inputs["Distance"].default_value = strength, distance
    if normal is not None:
        t.link(normal, b.inputs["Normal"])
    return b


def texture(t, kind, vector=None, **inputs):
    n = t.node(kind)
    if vector is not None:
        t.link(vector, n.inputs["Vector"])
    for k, v in inputs.items():
        n.inputs[k].default_value = v
    return n


def bump_cases():
    def noise_generated(t, a, b, gx, gy):
        return shown(t, bump(t, texture(t, "ShaderNodeTexNoise", Scale=3.0).outputs["Fac"]).outputs[0])

    def voronoi_object(t, a, b, gx, gy):
        coords = t.node("ShaderNodeTexCoord")
        cells = texture(t, "ShaderNodeTexVoronoi", coords.outputs["Object"], Scale=1.5)
        return shown(t, bump(t, cells.outputs["Distance"], strength=0.7, distance=0.4, invert=True).outputs[0])

    def position(t, a, b, gx, gy):
        sep = t.node("ShaderNodeSeparateXYZ")
        t.link(t.node("ShaderNodeNewGeometry").outputs["Position"], sep.inputs[0])
        s = t.node("ShaderNodeMath", operation="SINE")
        m = t.node("ShaderNodeMath", operation="MULTIPLY")
        t.link(sep.outputs["X"], m.inputs[0])
        t.link(sep.outputs["Y"], m.inputs[1])
        t.link(m.outputs[0], s.inputs[0])
        return shown(t, bump(t, s.outputs[0], distance=0.5).outputs[0])

    def uv_wave(t, a, b, gx, gy):
        coords = t.node("ShaderNodeTexCoord")
        wave = texture(t, "ShaderNodeTexWave", coords.outputs["UV"], Scale=2.0)
        return shown(t, bump(t, wave.outputs["Fac"], distance=0.2).outputs[0])

    def camera(t, a, b, gx, gy):
        coords = t.node("ShaderNodeTexCoord")
        noise = texture(t, "ShaderNodeTexNoise", coords.outputs["Camera"], Scale=0.7)
        return shown(t, bump(t, noise.outputs["Fac"], strength=0.5).outputs[0])

    def bump_of_bump(t, a, b, gx, gy):
        inner = bump(t, texture(t, "ShaderNodeTexNoise", Scale=3.0).outputs["Fac"], distance=0.3)
        gradient = texture(t, "ShaderNodeTexGradient")
        return shown(t, bump(t, gradient.outputs["Fac"], normal=inner.outputs[0], distance=2.0).outputs[0])

    def varying_strength(t, a, b, gx, gy):
        magic = texture(t, "ShaderNodeTexMagic", Scale=2.0)
        out = bump(t, magic.outputs["Fac"], distance=0.3)
        t.link(gx, out.inputs["Strength"])
        return shown(t, out.outputs[0])

    def layer_weight(t, a, b, gx, gy):
        lw = t.node("ShaderNodeLayerWeight")
        lw.inputs["Blend"].default_value = 0.3
        t.link(bump(t, texture(t, "ShaderNodeTexNoise", Scale=4.0).outputs["Fac"]).outputs[0], lw.inputs["Normal"])
        return lw.outputs["Facing"]

    return [Case("Bump Noise Generated", noise_generated), Case("Bump Voronoi Object", voronoi_object),
            Case("Bump Position", position), Case("Bump UV Wave", uv_wave), Case("Bump Camera", camera),
            Case("Bump of Bump", bump_of_bump), Case("Bump Strength", varying_strength),
            Case("Layer Weight of Bump", layer_weight)]


def test_bump_matches_cycles(empty_scene, tmp_path):
    scene = empty_scene
    sphrect = sphrect_module()
    cases = bump_cases()
    planes, rows, coordinates, theirs = cycles_grid(scene, cases, tmp_path, "bump")
    exported, log = export()
    assert "Bump" not in log.warning_text()
    ray_length = scene.camera.location.z - scene.camera.data.clip_start
    dP = scene.camera.data.ortho_scale / scene.render.resolution_x  # Cycles' orthographic |cam.dx|
    errors, others = {}, {}
    for k, case in enumerate(cases):
        program = material_named(exported, case.label).programs["emission"]
        assert sum(i.op == "bump" for i in program.instructions) == (2 if case.label == "Bump of Bump" else 1)
        fields = dataclasses.asdict(program)
        row, col = k // COLUMNS, k % COLUMNS
        worst = 0.0
        for y, x, g, local, world in cell_hits(k, coordinates):
            # The plane's Generated and UV coordinates are (local + 1) / 2: they move by half the offset.
            shifts = [(tuple(world + o), tuple((g + o / 2) * [1, 1, 0]), tuple(g + o / 2), tuple(local + o))
                      for o in (dP * DX, dP * DY)]
            ours = np.array(sphrect._native._eval_node_program(fields, tuple(world), (g[0], g[1], 0.0), tuple(g),
                                                               tuple(local), [], ray_length, dP, shifts))
            cycles = theirs[y, x, :3].astype(np.float64)
            worst = max(worst, float(np.max(np.abs(ours - cycles))))
        errors[case.label] = worst
        cell = theirs[row * CELL:(row + 1) * CELL, col * CELL:(col + 1) * CELL, :3]
        assert np.ptp(cell) > 0.05, f"{case.label}: Cycles' image is not bumped"
    for label, e in sorted(errors.items(), key=lambda kv: -kv[1]):
        print(f"{label}: max abs difference {e:.2e}")
    assert all(e <= TOLERANCE for e in errors.values()), errors
    # SPHRECT's own render of the grid (1 sample near each pixel centre, its dP and shifted inputs from its hits).
    # Each renderer's ray lands within 0.005 px of the centre (filter width 0.01), not on it: where the image is
    # steep the two differ by up to ~1% of the step to a neighbouring pixel, so the bound is 1e-3 + 5% of it.
    scene.sphrect.samples, scene.sphrect.passes, scene.sphrect.light_samples = 1, 1, 1
    scene.sphrect.pixel_filter, scene.sphrect.filter_width = "BLACKMAN_HARRIS", 0.01
    ours = render()["images"]["rectangle"][..., :3]
    theirs = theirs[..., :3]
    padded = np.pad(theirs, ((1, 1), (1, 1), (0, 0)), mode="edge")
    height, width = theirs.shape[:2]
    step = np.max([np.abs(padded[1 + dy:1 + dy + height, 1 + dx:1 + dx + width] - theirs).max(-1)
                   for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0))], axis=0)
    excess = np.abs(ours - theirs).max(-1) - (TOLERANCE + 0.05 * step)
    for k, case in enumerate(cases):
        row, col = k // COLUMNS, k % COLUMNS
        window = (slice(row * CELL, (row + 1) * CELL), slice(col * CELL, (col + 1) * CELL))
        others[case.label] = float(np.max(excess[window]))
        print(f"{case.label}: SPHRECT's render, max abs difference {np.abs(ours - theirs)[window].max():.2e}")
    assert all(e <= 0 for e in others.values()), others
    # Unbumped (the shading normal), the image is far from Cycles': the check can fail.
    assert np.abs(theirs[:CELL, :CELL] - 0.5 * (np.array([0.0, 0.0, 1.0]) + 1)).max() > 0.05


def principled_tree(name):
    """A Tree of a Principled BSDF of the bump tests' constant base colour and roughness: (tree, the node)."""
    t = Tree(name)
    p = t.node("ShaderNodeBsdfPrincipled")
    p.inputs["Base Color"].default_value = (0.7, 0.45, 0.3, 1.0)
    p.inputs["Roughness"].default_value = 0.35
    return t, p


def object_noise(t, scale, detail):
    """A Noise Texture of the Object coordinates in tree t."""
    return texture(t, "ShaderNodeTexNoise", t.node("ShaderNodeTexCoord").outputs["Object"], Scale=scale, Detail=detail)


def bumped_material(name="Bumped"):
    """A Principled BSDF (base colour and roughness constant, some specular) whose Normal a Bump node drives: the
    Height a Noise Texture of the Object coordinates (scale 4), strength 1, distance 0.4."""
    t, p = principled_tree(name)
    noise = object_noise(t, scale=4.0, detail=3.0)
    b = bump(t, noise.outputs["Fac"], strength=1.0, distance=0.4)
    t.link(b.outputs[0], p.inputs["Normal"])
    return t.surface(p), b


@pytest.mark.slow
def test_bumped_principled_matches_cycles(empty_scene, tmp_path):
    """A noise-bumped Principled floor and smooth sphere under a rectangle light, seen in perspective: mean relative
    difference to Cycles over 4x4 blocks (test_cycles_parity's measure) <= 1%; the same scene unbumped is clearly
    further from Cycles' (the bump shows, so the test can fail)."""
    from test_cycles_parity import difference_to_cycles, mean_relative_difference
    scene = empty_scene
    material, b = bumped_material()
    bpy.ops.mesh.primitive_plane_add(size=4.0)
    bpy.context.active_object.data.materials.append(material)
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(-0.4, 0.3, 0.5), segments=48, ring_count=24)
    bpy.ops.object.shade_smooth()
    bpy.context.active_object.data.materials.append(material)
    parity_view(scene, light=True, target=(0.0, 0.0, 0.3))
    exported, log = export()
    assert material_named(exported, "Bumped").normal_program is not None
    assert "Bump" not in log.warning_text() and "Normal" not in log.warning_text()
    difference, ours, cycles = difference_to_cycles(scene, "bumped Principled", tmp_path)
    assert difference <= 0.01
    material.node_tree.links.remove(b.outputs[0].links[0])
    scene.render.engine = "SPHRECT"
    unbumped = render()["images"]["rectangle"]
    far = mean_relative_difference(unbumped, cycles)
    print(f"unbumped: mean relative difference to Cycles' bumped render {far:.4f}")
    assert far > 5 * difference and far > 0.05


@pytest.mark.slow
def test_bumped_mix_and_glass_match_cycles(empty_scene, tmp_path):
    """A floor of a Mix Shader (0.4) of a Diffuse and a Glossy BSDF both bumped by one Voronoi Bump node, and a Glass
    sphere bumped by a Noise Bump, under a rectangle light: mean relative difference to Cycles <= 1%, nothing warned
    of the bumps."""
    from test_cycles_parity import difference_to_cycles
    scene = empty_scene
    t = Tree("Mixed")
    diffuse, glossy = t.node("ShaderNodeBsdfDiffuse"), t.node("ShaderNodeBsdfGlossy")
    diffuse.inputs["Color"].default_value = (0.3, 0.6, 0.4, 1.0)
    glossy.inputs["Roughness"].default_value = 0.3
    cells = texture(t, "ShaderNodeTexVoronoi", t.node("ShaderNodeTexCoord").outputs["Object"], Scale=3.0)
    b = bump(t, cells.outputs["Distance"], strength=0.6, distance=0.3)
    t.link(b.outputs[0], diffuse.inputs["Normal"])
    t.link(b.outputs[0], glossy.inputs["Normal"])
    mix = t.node("ShaderNodeMixShader")
    mix.inputs["Fac"].default_value = 0.4
    t.link(diffuse.outputs[0], mix.inputs[1])
    t.link(glossy.outputs[0], mix.inputs[2])
    bpy.ops.mesh.primitive_plane_add(size=4.0)
    bpy.context.active_object.data.materials.append(t.surface(mix))
    g = Tree("Glass")
    glass = g.node("ShaderNodeBsdfGlass")
    glass.inputs["Roughness"].default_value = 0.2
    noise = texture(g, "ShaderNodeTexNoise", Scale=6.0)
    g.link(bump(g, noise.outputs["Fac"], distance=0.2).outputs[0], glass.inputs["Normal"])
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(-0.4, 0.3, 0.5), segments=48, ring_count=24)
    bpy.ops.object.shade_smooth()
    bpy.context.active_object.data.materials.append(g.surface(glass))
    parity_view(scene, light=True, target=(0.0, 0.0, 0.3))
    exported, log = export()
    assert material_named(exported, "Mixed").normal_program is not None
    assert material_named(exported, "Glass").normal_program is not None
    assert "Bump" not in log.warning_text() and "normal" not in log.warning_text().lower()
    difference, ours, cycles = difference_to_cycles(scene, "bumped mix and glass", tmp_path)
    assert difference <= 0.01


# -- the compiler ------------------------------------------------------------------------------------------------

def normal_program_of(t, shader, name):
    bpy.ops.mesh.primitive_plane_add()
    bpy.context.active_object.data.materials.append(t.surface(shader))
    exported, log = export()
    return material_named(exported, name).normal_program, log


def test_the_height_is_compiled_three_times_and_the_rest_once(empty_scene):
    """The Height's position-dependent nodes (a Noise of Generated, a Math of it) appear at the point and at P + dx,
    P + dy (their 'global' read with flags 0, 1, 2); what does not depend on the position -- a Math of Geometry
    Normal, the Strength reading the same Noise at the point -- once; the shader's other inputs keep their own
    programs."""
    sphrect = sphrect_module()
    t = Tree("Triple")
    p = t.node("ShaderNodeBsdfPrincipled")
    noise = texture(t, "ShaderNodeTexNoise", Scale=2.0)
    sep = t.node("ShaderNodeSeparateXYZ")
    t.link(t.node("ShaderNodeNewGeometry").outputs["Normal"], sep.inputs[0])
    add = t.node("ShaderNodeMath", operation="ADD")
    t.link(noise.outputs["Fac"], add.inputs[0])
    t.link(sep.outputs["Z"], add.inputs[1])
    b = bump(t, add.outputs[0])
    t.link(noise.outputs["Fac"], b.inputs["Strength"])
    t.link(b.outputs[0], p.inputs["Normal"])
    t.link(noise.outputs["Color"], p.inputs["Base Color"])
    program, log = normal_program_of(t, p, "Triple")
    code = program.instructions
    assert sum(i.op == "noise_texture" for i in code) == 3
    assert sum(i.op == "math" for i in code) == 3
    assert sum(i.op == "separate" for i in code) == 1  # of the normal: the same at P + dx, P + dy
    generated = sphrect.scene.NODE_GLOBALS.index("generated")
    assert sorted(i.flags for i in code if i.op == "global" and i.mode == generated) == [0, 1, 2]
    assert all(i.flags == 0 for i in code if i.op == "global" and i.mode != generated)
    assert sum(i.op == "bump" for i in code) == 1
    bumped = material_named(export()[0], "Triple")
    assert not any(i.op == "bump" for i in bumped.programs["base_color"].instructions)
    assert "Triple" not in log.warning_text()


def test_a_bump_without_height_leaves_the_normal_and_unknown_inputs_are_warned(empty_scene):
    """An unlinked Height passes the normal through (Cycles' constant folding): no program.  A Normal Map on a Bump's
    Normal input is warned (the shading normal used), and so is a Bump inside another Bump's Height."""
    t = Tree("Flat")
    p = t.node("ShaderNodeBsdfDiffuse")
    t.link(t.node("ShaderNodeBump").outputs[0], p.inputs["Normal"])
    program, log = normal_program_of(t, p, "Flat")
    assert program is None and "Flat" not in log.warning_text()
    t = Tree("Inner")
    p = t.node("ShaderNodeBsdfDiffuse")
    inner = bump(t, texture(t, "ShaderNodeTexNoise").outputs["Fac"], normal=t.node("ShaderNodeNormalMap").outputs[0])
    dot = t.node("ShaderNodeVectorMath", operation="DOT_PRODUCT")
    t.link(inner.outputs[0], dot.inputs[0])
    outer = bump(t, dot.outputs["Value"])
    t.link(outer.outputs[0], p.inputs["Normal"])
    program, log = normal_program_of(t, p, "Inner")
    text = log.warning_text()
    assert "Normal Map' node on a Bump node's Normal input" in text
    assert "Bump node inside another Bump node's Height" in text
    assert program is not None


def test_a_bump_in_a_group_through_a_reroute_is_the_ungrouped_one(empty_scene):
    """A group holding the Bump (its Height a group input fed by a Noise outside), its Normal output reaching the
    Principled Normal through a reroute: the same program as the Bump and Noise in the material itself."""
    group = bpy.data.node_groups.new("Bumper", "ShaderNodeTree")
    group.inputs.new("NodeSocketFloat", "Height")
    group.outputs.new("NodeSocketVector", "Normal")
    inside_in, inside_out = group.nodes.new("NodeGroupInput"), group.nodes.new("NodeGroupOutput")
    inner = group.nodes.new("ShaderNodeBump")
    inner.inputs["Distance"].default_value = 0.3
    group.links.new(inside_in.outputs["Height"], inner.inputs["Height"])
    group.links.new(inner.outputs["Normal"], inside_out.inputs["Normal"])
    t = Tree("Grouped")
    p = t.node("ShaderNodeBsdfPrincipled")
    node = t.node("ShaderNodeGroup")
    node.node_tree = group
    t.link(texture(t, "ShaderNodeTexNoise").outputs["Fac"], node.inputs["Height"])
    reroute = t.node("NodeReroute")
    t.link(node.outputs["Normal"], reroute.inputs[0])
    t.link(reroute.outputs[0], p.inputs["Normal"])
    grouped, log = normal_program_of(t, p, "Grouped")
    t = Tree("Flat")
    p = t.node("ShaderNodeBsdfPrincipled")
    t.link(bump(t, texture(t, "ShaderNodeTexNoise").outputs["Fac"], distance=0.3).outputs[0], p.inputs["Normal"])
    flat, log = normal_program_of(t, p, "Flat")
    assert grouped is not None and grouped == flat
    assert "Grouped" not in log.warning_text()


def test_bump_through_a_perspective_camera_matches_cycles(empty_scene, tmp_path):
    """A floor seen obliquely through a perspective camera, its Emission colour 0.5 + 0.5 N of a Bump of a fine
    Noise (features a few pixels wide, so the finite differences depend on the footprint dP = t dD): SPHRECT's render
    at 1 sample through the pixel centres against Cycles', within 1e-3 + 5% of the step to a neighbouring pixel (the
    rays' jitter, as in test_bump_matches_cycles) in 98% of the pixels (the rest: where the far floor's noise
    changes within a pixel), and the median difference <= 1e-3: 3.7e-4, where a footprint dP 20% too large gives
    1.2e-2."""
    scene = empty_scene
    t = Tree("Fine")
    emission = t.node("ShaderNodeEmission")
    noise = texture(t, "ShaderNodeTexNoise", t.node("ShaderNodeTexCoord").outputs["Object"], Scale=12.0)
    t.link(shown(t, bump(t, noise.outputs["Fac"], distance=0.05).outputs[0]), emission.inputs["Color"])
    bpy.ops.mesh.primitive_plane_add(size=6.0)
    bpy.context.active_object.data.materials.append(t.surface(emission))
    parity_view(scene, light=False, target=(0.0, 0.5, 0.0))
    theirs = render_cycles(scene, str(tmp_path / "fine.exr"))[..., :3]
    scene.render.engine = "SPHRECT"
    scene.sphrect.samples, scene.sphrect.passes, scene.sphrect.light_samples = 1, 1, 1
    scene.sphrect.pixel_filter, scene.sphrect.filter_width = "BLACKMAN_HARRIS", 0.01
    ours = render()["images"]["rectangle"][..., :3]
    padded = np.pad(theirs, ((1, 1), (1, 1), (0, 0)), mode="edge")
    height, width = theirs.shape[:2]
    step = np.max([np.abs(padded[1 + dy:1 + dy + height, 1 + dx:1 + dx + width] - theirs).max(-1)
                   for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0))], axis=0)
    difference = np.abs(ours - theirs).max(-1)
    print(f"perspective bump: max abs difference {difference.max():.2e}, median {np.median(difference):.2e}, "
          f"median step {np.median(step):.2e}")
    assert np.ptp(theirs) > 0.2  # the floor is bumped
    assert np.median(difference) <= TOLERANCE  # a footprint 20% too large: 1.16e-2
    assert np.mean(difference > TOLERANCE + 0.05 * step) <= 0.02  # 0.8%: where the noise changes within a pixel


def displaced_material(name, space, layer_weight=False):
    """A Principled BSDF whose Material Output's Displacement is a Displacement node (`space`, scale 0.15) of a
    Noise's Fac of the Object coordinates; with `layer_weight`, its Base Color a Layer Weight's Facing (a graph
    reading the displaced normal)."""
    t, p = principled_tree(name)
    noise = object_noise(t, scale=5.0, detail=2.0)
    d = t.node("ShaderNodeDisplacement", space=space)
    d.inputs["Scale"].default_value = 0.15
    t.link(noise.outputs["Fac"], d.inputs["Height"])
    t.link(d.outputs[0], t.out.inputs["Displacement"])
    if layer_weight:
        t.link(t.node("ShaderNodeLayerWeight").outputs["Facing"], p.inputs["Base Color"])
    return t.surface(p)


@pytest.mark.slow
def test_displacement_bumps_the_normal_as_in_cycles(empty_scene, tmp_path):
    """Cycles 3.4's default displacement method (Bump Only) bumps every closure's normal and every graph reading
    it: a floor displaced in Object space (its object scaled 1.5: the offset grows with it) and a smooth sphere in
    World space whose Base Color reads the normal (Layer Weight), under a rectangle light: mean relative difference
    to Cycles <= 1%, unwarned; undisplaced (the Displacement unlinked) clearly further."""
    from test_cycles_parity import difference_to_cycles, mean_relative_difference
    scene = empty_scene
    floor = displaced_material("Floor", "OBJECT")
    bpy.ops.mesh.primitive_plane_add(size=4.0 / 1.5, scale=(1.5, 1.5, 1.5))
    bpy.context.active_object.data.materials.append(floor)
    ball = displaced_material("Ball", "WORLD", layer_weight=True)
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(-0.4, 0.3, 0.5), segments=48, ring_count=24)
    bpy.ops.object.shade_smooth()
    bpy.context.active_object.data.materials.append(ball)
    parity_view(scene, light=True, target=(0.0, 0.0, 0.3))
    exported, log = export()
    assert material_named(exported, "Floor").normal_program is not None
    assert "isplacement" not in log.warning_text()
    difference, ours, cycles = difference_to_cycles(scene, "displacement as bump", tmp_path)
    assert difference <= 0.01
    for mat in (floor, ball):
        out = mat.node_tree.nodes["Material Output"]
        mat.node_tree.links.remove(out.inputs["Displacement"].links[0])
    scene.render.engine = "SPHRECT"
    far = mean_relative_difference(render()["images"]["rectangle"], cycles)
    print(f"undisplaced: mean relative difference to Cycles' displaced render {far:.4f}")
    assert far > 3 * difference and far > 0.03
