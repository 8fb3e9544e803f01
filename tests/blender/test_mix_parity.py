"""Glossy BSDF, Mix / Add Shader, Transparent BSDF, Holdout and Translucent BSDF as Cycles 3.4 shows them at
max_bounces 0 (test_cycles_parity's renders and mean relative difference over 4x4 blocks; the glass test's
sphere of the material over a diffuse plane, lit by a rectangle). Also the exporter: the kinds and weights it
writes, and the warnings for what is not modelled."""
import bpy
import pytest

from conftest import builders, export, render
from test_cycles_parity import difference_to_cycles, mean_relative_difference
from test_glass_parity import COLOR, highlight_ratio, shader_material, sphere_scene

pytestmark = pytest.mark.slow

TOLERANCE = 0.01
HIGHLIGHT_TOLERANCE = 0.05  # the highlight's own blocks, as in test_glass_parity
GLOSSY_CASES = [("GGX", 0.3), ("GGX", 0.6), ("BECKMANN", 0.4)]


def shader_tree(name, build):
    """A material whose Surface is what build(tree) returns (a node's output socket)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(build(tree), out.inputs["Surface"])
    return mat


def node(tree, node_type, **inputs):
    n = tree.nodes.new(node_type)
    if "distribution" in inputs:
        n.distribution = inputs.pop("distribution")
    for socket, value in inputs.items():
        n.inputs[socket].default_value = value
    return n


def combine(tree, kind, a, b, fac=None):
    """Mix (fac) or Add Shader of two nodes' outputs."""
    m = tree.nodes.new("ShaderNodeMixShader" if kind == "mix" else "ShaderNodeAddShader")
    first = 1 if kind == "mix" else 0
    if fac is not None:
        m.inputs[0].default_value = fac
    tree.links.new(a.outputs[0], m.inputs[first])
    tree.links.new(b.outputs[0], m.inputs[first + 1])
    return m


def glossy(tree, roughness=0.3, color=COLOR, distribution="GGX"):
    return node(tree, "ShaderNodeBsdfGlossy", distribution=distribution, Roughness=roughness, Color=color)


MIXES = {
    "diffuse_glossy_mix0.4": lambda t: combine(t, "mix", node(t, "ShaderNodeBsdfDiffuse", Color=(0.8, 0.3, 0.2, 1)),
                                               glossy(t), 0.4).outputs[0],
    "principled_glossy_add": lambda t: combine(t, "add", node(t, "ShaderNodeBsdfPrincipled", Roughness=0.6),
                                               glossy(t, 0.25, (0.3, 0.3, 0.3, 1))).outputs[0],
    "glossy_glossy_glass_nested": lambda t: combine(
        t, "mix", combine(t, "add", glossy(t, 0.2, (0.4, 0.4, 0.4, 1)), glossy(t, 0.6, (0.3, 0.2, 0.1, 1))),
        node(t, "ShaderNodeBsdfGlass", distribution="GGX", Roughness=0.3, IOR=1.5), 0.5).outputs[0],
    "principled_principled_mix0.3": lambda t: combine(
        t, "mix", node(t, "ShaderNodeBsdfPrincipled", Roughness=0.4, **{"Base Color": (0.8, 0.45, 0.25, 1)}),
        node(t, "ShaderNodeBsdfPrincipled", Roughness=0.4, **{"Base Color": (0.2, 0.5, 0.8, 1)}), 0.3).outputs[0],
}


@pytest.mark.parametrize("distribution, roughness", GLOSSY_CASES)
def test_glossy_matches_cycles(empty_scene, distribution, roughness, tmp_path):
    mat = shader_material("ShaderNodeBsdfGlossy", distribution=distribution, Roughness=roughness, Color=COLOR)
    scene = sphere_scene(empty_scene, mat)
    exported, log = export()
    (m,) = [m for m in exported.materials if m.name == "ShaderNodeBsdfGlossy"]
    assert (m.kind, m.roughness, m.distribution) == ("glossy_bsdf", pytest.approx(roughness), distribution.lower())
    assert "grey diffuse" not in log.warning_text()
    difference, ours, cycles = difference_to_cycles(scene, f"glossy {distribution} r={roughness}", tmp_path)
    assert difference <= TOLERANCE
    ratio = highlight_ratio(scene, ours, cycles, tmp_path)
    print(f"glossy {distribution} r={roughness}: highlight ours / Cycles {ratio:.4f}")
    assert abs(ratio - 1) <= HIGHLIGHT_TOLERANCE


# Cycles' image of a mix's scene, kept for test_the_mix_comparison_can_fail (the same scene).
MIX_CYCLES_IMAGES = {}


@pytest.mark.parametrize("name", sorted(MIXES))
def test_mix_matches_cycles(empty_scene, name, tmp_path):
    scene = sphere_scene(empty_scene, shader_tree(name, MIXES[name]))
    exported, log = export()
    (m,) = [m for m in exported.materials if m.name == name]
    # Two Principled BSDFs differing only in base colour (no tints) merge exactly into one.
    assert m.kind == ("principled" if name == "principled_principled_mix0.3" else "mix")
    assert "grey diffuse" not in log.warning_text() and "Principled BSDFs" not in log.warning_text()
    difference, ours, cycles = difference_to_cycles(scene, f"mix {name}", tmp_path)
    MIX_CYCLES_IMAGES[name] = cycles
    ratio = highlight_ratio(scene, ours, cycles, tmp_path)
    print(f"mix {name}: highlight ours / Cycles {ratio:.4f}")
    assert difference <= TOLERANCE
    assert abs(ratio - 1) <= HIGHLIGHT_TOLERANCE


def test_mix_weights_reach_the_export(empty_scene):
    sphere_scene(empty_scene, shader_tree("m", MIXES["diffuse_glossy_mix0.4"]))
    exported, _ = export()
    (m,) = [m for m in exported.materials if m.name == "m"]
    assert [(l.weight, l.material.kind) for l in m.layers] == [(pytest.approx(0.6), "diffuse"),
                                                              (pytest.approx(0.4), "glossy_bsdf")]


def test_different_principled_bsdfs_in_a_mix_are_averaged_with_a_warning(empty_scene):
    def build(t):
        a = node(t, "ShaderNodeBsdfPrincipled", Roughness=0.2)
        b = node(t, "ShaderNodeBsdfPrincipled", Roughness=0.6, Metallic=1.0)
        return combine(t, "mix", a, combine(t, "add", b, glossy(t)), 0.25).outputs[0]
    sphere_scene(empty_scene, shader_tree("pp", build))
    exported, log = export()
    (m,) = [m for m in exported.materials if m.name == "pp"]
    assert sorted((l.material.kind, round(l.weight, 6)) for l in m.layers) == [("glossy_bsdf", 0.25),
                                                                               ("principled", 1.0)]
    (p,) = [l.material for l in m.layers if l.material.kind == "principled"]
    assert (p.roughness, p.metallic) == (pytest.approx(0.75 * 0.2 + 0.25 * 0.6), pytest.approx(0.25))
    assert "a mix of 2 different Principled BSDFs" in log.warning_text()


def test_a_mix_of_diffuse_bsdfs_exports_as_one_diffuse(empty_scene):
    """Lambert is linear in its colour, so the mix is one 'diffuse' (the renderer's diffuse-only kernel)."""
    def build(t):
        a = node(t, "ShaderNodeBsdfDiffuse", Color=(0.8, 0.2, 0.1, 1))
        b = node(t, "ShaderNodeBsdfDiffuse", Color=(0.1, 0.4, 0.8, 1))
        return combine(t, "add", combine(t, "mix", a, b, 0.25), node(t, "ShaderNodeEmission", Strength=2.0)).outputs[0]
    sphere_scene(empty_scene, shader_tree("dd", build))
    exported, _ = export()
    (m,) = [m for m in exported.materials if m.name == "dd"]
    assert m.kind == "diffuse" and m.base_color == pytest.approx((0.625, 0.25, 0.275))
    assert m.emission == pytest.approx((2.0, 2.0, 2.0))


def test_white_transparent_surface_is_left_out_as_cycles_shows_it(empty_scene, tmp_path):
    mat = shader_material("ShaderNodeBsdfTransparent", Color=(1.0, 1.0, 1.0, 1.0))
    scene = sphere_scene(empty_scene, mat)
    exported, log = export()
    assert "Ball" not in [m.name for m in exported.meshes]
    assert "Transparent BSDF surfaces (left out: transparent)" in log.warning_text()
    difference, ours, cycles = difference_to_cycles(scene, "transparent", tmp_path)
    assert difference <= TOLERANCE


@pytest.mark.parametrize("node_type, kind", [("ShaderNodeHoldout", "holdout"),
                                             ("ShaderNodeBsdfTranslucent", "translucent")])
def test_holdout_and_translucent_spheres_match_cycles(empty_scene, node_type, kind, tmp_path):
    """Cycles shows a holdout's pixels black (alpha 0: test_alpha_parity), and a closed translucent sphere lit from
    outside black but at its rim (light from behind a point crosses the sphere)."""
    scene = sphere_scene(empty_scene, shader_material(node_type))
    exported, log = export()
    (m,) = [m for m in exported.materials if m.name == node_type]
    assert m.kind == kind
    assert "Holdout" not in log.warning_text() and "Translucent" not in log.warning_text()
    difference, ours, cycles = difference_to_cycles(scene, node_type, tmp_path)
    assert difference <= TOLERANCE


def test_the_mix_comparison_can_fail(empty_scene, tmp_path):
    """The diffuse + glossy mix rendered with its glossy side dropped is far from Cycles' mix."""
    name = "diffuse_glossy_mix0.4"
    scene = sphere_scene(empty_scene, shader_tree(name, MIXES[name]))
    _, ours, cycles = difference_to_cycles(scene, "mix reference", tmp_path, cycles=MIX_CYCLES_IMAGES.get(name))
    tree = bpy.data.materials[name].node_tree
    tree.nodes.remove(tree.nodes["Glossy BSDF"])
    dropped = render()["images"]["rectangle"]  # SPHRECT, at difference_to_cycles' settings
    assert mean_relative_difference(dropped, cycles) > 0.03


def test_what_is_not_modelled_is_named_in_warnings(empty_scene):
    """Beckmann anisotropy and the distributions rendered as GGX are warned; a Holdout in a mix is a layer."""
    aniso = shader_material("ShaderNodeBsdfAnisotropic", Roughness=0.4, distribution="BECKMANN")  # anisotropy 0.5
    ashikhmin = shader_material("ShaderNodeBsdfGlossy", distribution="ASHIKHMIN_SHIRLEY", Roughness=0.4)
    holdout_mix = shader_tree("holdout_mix", lambda t: combine(t, "mix", node(t, "ShaderNodeHoldout"),
                                                               glossy(t), 0.25).outputs[0])
    sphere_scene(empty_scene, aniso)
    for i, mat in enumerate((ashikhmin, holdout_mix)):
        builders.mesh_object(f"Extra{i}", "cube", mat, location=(3.0 * (i + 1), 0.0, 0.5))
    exported, log = export()
    text = log.warning_text()
    by_name = {m.name: m for m in exported.materials}
    assert by_name["ShaderNodeBsdfAnisotropic"].kind == "glossy_bsdf"
    assert "anisotropy of a Beckmann Anisotropic BSDF (isotropic used)" in text
    assert "distribution 'Ashikhmin-Shirley' (GGX used)" in text
    # The holdout's share (0.75) is a hole in the film's alpha (test_alpha_parity): a layer of its own, not warned.
    assert "Holdout" not in text
    assert sorted((round(l.weight, 6), l.material.kind) for l in by_name["holdout_mix"].layers) == [
        (0.25, "glossy_bsdf"), (0.75, "holdout")]
