"""Emissive meshes: the exporter reads Cycles 3.4's emission (Emission shader colour x strength, the
Principled BSDF's Emission x Emission Strength, a Mix Shader of an emission and a BSDF with an unlinked
factor) on evaluated meshes (modifiers, instances), and the renders match Cycles 3.4 (direct light only)
on an emissive plane, an emissive UV sphere of a few hundred triangles and a ceiling of 100 small quads.
Parity as in test_cycles_parity.py: mean relative difference of 4x4-pixel blocks, fixed seeds."""
import bpy
import numpy as np
import pytest

from conftest import builders, export, set_resolution
from test_cycles_parity import HEIGHT, WIDTH, difference_to_cycles

pytestmark = pytest.mark.slow


def emission_material(name, color=(1.0, 0.9, 0.8), strength=5.0):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    e = tree.nodes.new("ShaderNodeEmission")
    e.inputs["Color"].default_value = (*color, 1)
    e.inputs["Strength"].default_value = strength
    tree.links.new(e.outputs[0], out.inputs["Surface"])
    return mat


def mix_material(name, fac, emission_first=False, link_fac=False):
    mat = emission_material(name, (0.5, 1.0, 0.25), 4.0)
    tree = mat.node_tree
    e = tree.nodes["Emission"]
    d = tree.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (0.8, 0.6, 0.4, 1)
    mix = tree.nodes.new("ShaderNodeMixShader")
    mix.inputs[0].default_value = fac
    tree.links.new(e.outputs[0], mix.inputs[1 if emission_first else 2])
    tree.links.new(d.outputs[0], mix.inputs[2 if emission_first else 1])
    tree.links.new(mix.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    if link_fac:
        tree.links.new(tree.nodes.new("ShaderNodeValue").outputs[0], mix.inputs[0])
    return mat


def exported_material(scene, name):
    (m,) = [m for m in scene.materials if m.name == name]
    return m


def test_emission_conventions(empty_scene):
    builders.mesh_object("Panel", "plane", emission_material("Panel", strength=5.0))
    principled = builders.material("Glow", (0.2, 0.3, 0.4), kind="principled")
    bsdf = principled.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Emission"].default_value = (1.0, 0.5, 0.25, 1)
    bsdf.inputs["Emission Strength"].default_value = 3.0
    builders.mesh_object("Glow", "cube", principled, location=(3, 0, 0))
    builders.mesh_object("Mix", "cube", mix_material("Mix", 0.25), location=(6, 0, 0))
    builders.mesh_object("MixFirst", "cube", mix_material("MixFirst", 0.25, emission_first=True), location=(9, 0, 0))
    builders.mesh_object("Linked", "cube", mix_material("Linked", 0.25, link_fac=True), location=(12, 0, 0))
    builders.mesh_object("Negative", "cube", emission_material("Negative", strength=-2.0), location=(15, 0, 0))
    scene, log = export()
    assert exported_material(scene, "Panel").emission == pytest.approx((5.0, 4.5, 4.0))
    glow = exported_material(scene, "Glow")
    assert glow.emission == pytest.approx((3.0, 1.5, 0.75)) and glow.base_color == pytest.approx((0.2, 0.3, 0.4))
    mix = exported_material(scene, "Mix")  # fac 0.25 on the second input (emission): 0.25 emission, 0.75 BSDF
    assert mix.emission == pytest.approx((0.5, 1.0, 0.25)) and mix.base_color == pytest.approx((0.6, 0.45, 0.3))
    first = exported_material(scene, "MixFirst")  # emission on the first input: weight 1 - fac
    assert first.emission == pytest.approx((1.5, 3.0, 0.75)) and first.base_color == pytest.approx((0.2, 0.15, 0.1))
    assert exported_material(scene, "Negative").emission == pytest.approx((0.0, 0.0, 0.0))
    text = log.warning_text()
    # A Value node on the factor folds to its constant, 0 (node_program.py), as Cycles folds it: the diffuse alone.
    linked = exported_material(scene, "Linked")
    assert linked.emission == pytest.approx((0.0, 0.0, 0.0)) and linked.base_color == pytest.approx((0.8, 0.6, 0.4))
    assert "(Linked)" not in text
    assert "negative emission strength (0 used) (Negative)" in text
    for name in ("Panel", "Glow", "Mix (", "MixFirst"):
        assert name not in text
    assert "no lights" not in text  # emissive meshes light the scene


def test_emissive_modifiers_and_instances(empty_scene):
    """An emissive plane with a 10 x 10 array: 100 quads, each recognised as one rectangle light; a linked
    duplicate adds its own 100."""
    panel = builders.mesh_object("Tiles", "plane", emission_material("Tiles"), size=0.2)
    for axis in (0, 1):
        mod = panel.modifiers.new(f"Array{axis}", "ARRAY")
        mod.count = 10
        mod.relative_offset_displace = (1.5, 0, 0) if axis == 0 else (0, 1.5, 0)
    copy = panel.copy()
    copy.location = (0, 0, 2)
    bpy.context.scene.collection.objects.link(copy)
    scene, _ = export()
    from sphrect.render import build_native_scene
    native, warnings = build_native_scene(scene)
    assert native.num_area_lights == 200 and not warnings


def lit_by_meshes(scene):
    builders.mesh_object("Ground", "plane", builders.material("Ground", (0.8, 0.8, 0.8)), size=8)
    builders.mesh_object("Box", "cube", builders.material("Box", (0.7, 0.4, 0.2)), location=(0.3, 0.5, 0.5),
                         size=1.0, rotation=(0, 0, 0.4))
    set_resolution(scene, WIDTH, HEIGHT)
    scene.sphrect.technique = "RECTANGLE"
    return scene


def emissive_plane(scene):
    builders.mesh_object("Panel", "plane", emission_material("Panel", strength=20.0), location=(-0.5, 0.0, 2.0),
                         rotation=(0.2, -0.3, 0.0), scale=(0.75, 0.4, 1.0), size=2.0)


def emissive_sphere(scene):
    sphere = builders.mesh_object("Bulb", "uv_sphere", emission_material("Bulb", strength=8.0),
                                  location=(-0.8, -0.6, 1.6), radius=0.35, segments=24, ring_count=12)
    assert len(sphere.data.polygons) == 288  # 528 triangles


def emissive_ceiling(scene):
    tiles = builders.mesh_object("Tiles", "plane", emission_material("Tiles", strength=40.0),
                                 location=(-1.35, -1.35, 2.5), rotation=(np.pi, 0, 0), size=0.12)
    for axis in (0, 1):
        mod = tiles.modifiers.new(f"Array{axis}", "ARRAY")
        mod.count = 10
        mod.relative_offset_displace = (2.5, 0, 0) if axis == 0 else (0, -2.5, 0)


@pytest.mark.parametrize("build", [emissive_plane, emissive_sphere, emissive_ceiling], ids=lambda f: f.__name__)
def test_emissive_meshes_match_cycles(empty_scene, build, tmp_path):
    scene = lit_by_meshes(empty_scene)
    build(scene)
    difference, ours, cycles = difference_to_cycles(scene, build.__name__, tmp_path, light_samples=4)
    assert np.isfinite(ours).all() and cycles[..., :3].max() > 0
    assert difference <= 0.02
