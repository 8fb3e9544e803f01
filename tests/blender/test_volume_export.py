"""Object volumes: a mesh whose material has a Volume output exports a sphrect.Volume per object instance and material
slot -- that slot's triangles in world space, facing out -- with the homogeneous medium Cycles 3.4 sums from the
volume shaders (Volume Scatter, Volume Absorption, Principled Volume, Add and Mix Shader, node groups).  What is not
simulated is warned naming the object: heterogeneous inputs (read at the volume's centre, or their own value),
volume emission, open meshes.  No rendering here (test_volume_parity.py renders)."""
import bpy
import numpy as np
import pytest

from conftest import builders, export
from test_texture_export import Tree as MaterialTree

HETEROGENEOUS = "heterogeneous volume density"


class Tree(MaterialTree):
    """A material's node tree (test_texture_export.Tree) whose node(...) sets input values:
    Tree('Fog').volume(node) links `node` to the Material Output's Volume."""

    def node(self, node_type, **inputs):
        n = self.nodes.new(node_type)
        for k, v in inputs.items():
            n.inputs[k].default_value = v
        return n

    def volume(self, node):
        self.link(node.outputs[0], self.out.inputs["Volume"])
        return self.mat


def scatter(t, density=0.5, color=(0.8, 0.6, 0.4, 1.0), anisotropy=0.3):
    return t.node("ShaderNodeVolumeScatter", Density=density, Color=color, Anisotropy=anisotropy)


def absorption(t, density=2.0, color=(0.25, 0.5, 0.75, 1.0)):
    return t.node("ShaderNodeVolumeAbsorption", Density=density, Color=color)


def box(mat, name="Fog", location=(1.0, 2.0, 0.5), scale=(1.0, 1.0, 1.0), rotation=(0.0, 0.0, 0.0)):
    """A cube of side 2 (before scale)."""
    obj = builders.mesh_object(name, "cube", mat, location=location, rotation=rotation, scale=scale)
    bpy.context.view_layer.update()
    return obj


def outward(volume):
    """Whether every triangle's normal (its winding's) points away from the volume's centre."""
    p = np.asarray(volume.vertices, dtype=np.float64)[np.asarray(volume.triangles)]
    normals = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    centre = 0.5 * (np.asarray(volume.vertices).min(axis=0) + np.asarray(volume.vertices).max(axis=0))
    return bool((np.einsum("ij,ij->i", normals, p.mean(axis=1) - centre) > 0).all())


def volume_warnings(log):
    return [w for w in log.unsupported if "volume" in w]


def test_volume_scatter_box(empty_scene):
    t = Tree("Fog")
    mat = t.volume(scatter(t, density=0.5, color=(0.8, 0.6, 0.4, 1.0), anisotropy=0.3))
    box(mat, location=(1.0, 2.0, 0.5), scale=(1.0, 2.0, 0.5))
    scene, log = export()
    assert scene.meshes == []  # the volume-only surface is left out
    (volume,) = scene.volumes
    assert volume.name == "Fog"
    assert volume.medium.sigma_s == pytest.approx((0.4, 0.3, 0.2))
    assert volume.medium.sigma_a == pytest.approx((0.0, 0.0, 0.0))
    assert volume.medium.g == pytest.approx(0.3)
    assert np.asarray(volume.triangles).shape == (12, 3)
    assert np.asarray(volume.vertices).shape == (8, 3)
    np.testing.assert_allclose(np.asarray(volume.vertices).min(axis=0), (0.0, 0.0, 0.0), atol=1e-6)
    np.testing.assert_allclose(np.asarray(volume.vertices).max(axis=0), (2.0, 4.0, 1.0), atol=1e-6)
    assert outward(volume)
    assert volume_warnings(log) == []
    assert "volume not simulated" not in log.warning_text()


def test_principled_volume(empty_scene):
    t = Tree("Smoke")
    pv = t.node("ShaderNodeVolumePrincipled", Density=2.0, Color=(0.5, 0.6, 0.7, 1.0),
                **{"Absorption Color": (0.25, 0.25, 0.25, 1.0), "Anisotropy": -0.2})
    box(t.volume(pv))
    scene, log = export()
    (volume,) = scene.volumes
    assert volume.medium.sigma_s == pytest.approx((1.0, 1.2, 1.4))
    # Cycles: density * max(1 - colour, 0) * max(1 - sqrt(absorption colour), 0)
    assert volume.medium.sigma_a == pytest.approx((0.5, 0.4, 0.3))
    assert volume.medium.g == pytest.approx(-0.2)
    assert volume_warnings(log) == []


def test_principled_volume_emission_is_warned(empty_scene):
    t = Tree("Glow")
    pv = t.node("ShaderNodeVolumePrincipled", Density=1.0, **{"Emission Strength": 2.0})
    box(t.volume(pv))
    scene, log = export()
    assert len(scene.volumes) == 1
    assert log.unsupported["volume emission not simulated"] == ["Fog"]


def test_scatter_plus_absorption_through_add_shader(empty_scene):
    t = Tree("Murk")
    add = t.node("ShaderNodeAddShader")
    t.link(scatter(t).outputs[0], add.inputs[0])
    t.link(absorption(t).outputs[0], add.inputs[1])
    box(t.volume(add))
    scene, log = export()
    (volume,) = scene.volumes
    assert volume.medium.sigma_s == pytest.approx((0.4, 0.3, 0.2))
    assert volume.medium.sigma_a == pytest.approx((1.5, 1.0, 0.5))
    assert volume.medium.g == pytest.approx(0.3)
    assert volume_warnings(log) == []


def test_mix_shader_scales_each_side_and_averages_anisotropy(empty_scene):
    """Fac 0.25: the first side weighs 0.75, the second 0.25; the anisotropy is the sigma_s-weighted mean, warned."""
    t = Tree("Mixed")
    mix = t.node("ShaderNodeMixShader", Fac=0.25)
    t.link(scatter(t, density=1.0, color=(1.0, 1.0, 1.0, 1.0), anisotropy=0.6).outputs[0], mix.inputs[1])
    t.link(scatter(t, density=3.0, color=(1.0, 1.0, 1.0, 1.0), anisotropy=-0.2).outputs[0], mix.inputs[2])
    box(t.volume(mix))
    scene, log = export()
    (volume,) = scene.volumes
    assert volume.medium.sigma_s == pytest.approx((1.5, 1.5, 1.5))  # 0.75 * 1 + 0.25 * 3
    assert volume.medium.g == pytest.approx((0.75 * 0.6 - 0.75 * 0.2) / 1.5)
    (warning,) = [w for w in log.unsupported if "different anisotropies" in w]
    assert log.unsupported[warning] == ["Fog"]


def test_volume_inside_a_node_group(empty_scene):
    group = bpy.data.node_groups.new("FogGroup", "ShaderNodeTree")
    group.outputs.new("NodeSocketShader", "Volume")
    out = group.nodes.new("NodeGroupOutput")
    inner = group.nodes.new("ShaderNodeVolumeScatter")
    inner.inputs["Density"].default_value = 0.7
    inner.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    group.links.new(inner.outputs[0], out.inputs[0])
    t = Tree("Grouped")
    node = t.nodes.new("ShaderNodeGroup")
    node.node_tree = group
    box(t.volume(node))
    (volume,) = export()[0].volumes
    assert volume.medium.sigma_s == pytest.approx((0.7, 0.7, 0.7))


def test_surface_and_volume_keep_both(empty_scene):
    t = Tree("Glassy")
    diffuse = t.node("ShaderNodeBsdfDiffuse", Color=(0.2, 0.4, 0.6, 1.0))
    t.link(diffuse.outputs[0], t.out.inputs["Surface"])
    box(t.volume(scatter(t)))
    scene, log = export()
    (mesh,) = scene.meshes
    assert len(mesh.triangles) == 12
    assert scene.materials[int(mesh.material_ids[0])].base_color == pytest.approx((0.2, 0.4, 0.6))
    (volume,) = scene.volumes
    assert volume.medium.sigma_s == pytest.approx((0.4, 0.3, 0.2))
    assert "material volumes" not in log.warning_text()


def test_linked_duplicates_and_collection_instances_each_get_a_volume(empty_scene):
    t = Tree("Fog")
    original = box(t.volume(scatter(t)), location=(0.0, 0.0, 0.0))
    duplicate = original.copy()  # shares the mesh data
    duplicate.location = (5.0, 0.0, 0.0)
    bpy.context.scene.collection.objects.link(duplicate)
    collection = bpy.data.collections.new("FogSet")
    collection.objects.link(bpy.data.objects.new("Inner", original.data))
    instancer = bpy.data.objects.new("Instancer", None)
    instancer.instance_type, instancer.instance_collection = "COLLECTION", collection
    instancer.location = (0.0, 0.0, 7.0)
    bpy.context.scene.collection.objects.link(instancer)
    bpy.context.view_layer.update()
    scene, _ = export()
    centres = sorted(tuple(np.round(np.asarray(v.vertices).mean(axis=0), 5)) for v in scene.volumes)
    assert centres == [(0.0, 0.0, 0.0), (0.0, 0.0, 7.0), (5.0, 0.0, 0.0)]
    assert all(outward(v) for v in scene.volumes)
    assert len({v.name for v in scene.volumes}) == 3


def test_negative_scale_keeps_the_normals_outward(empty_scene):
    t = Tree("Fog")
    box(t.volume(scatter(t)), scale=(-1.0, 0.5, 2.0), rotation=(0.3, 0.2, 0.1))
    (volume,) = export()[0].volumes
    assert outward(volume)
    # The check can fail: the same triangles with Blender's winding under the mirror face in.
    flipped = volume.__class__(vertices=volume.vertices, triangles=np.asarray(volume.triangles)[:, ::-1],
                               medium=volume.medium)
    assert not outward(flipped)


def test_two_volume_slots_of_one_object(empty_scene):
    thin, thick = Tree("Thin"), Tree("Thick")
    cube = box(thin.volume(scatter(thin, density=0.1)))
    cube.data.materials.append(thick.volume(scatter(thick, density=2.0)))
    top = max(cube.data.polygons, key=lambda p: p.center.z)
    top.material_index = 1
    bpy.context.view_layer.update()
    scene, log = export()
    by_name = {v.name: v for v in scene.volumes}
    assert sorted(by_name) == ["Fog/Thick", "Fog/Thin"]
    assert len(by_name["Fog/Thin"].triangles) == 10 and len(by_name["Fog/Thick"].triangles) == 2
    assert "Fog" in log.unsupported[next(w for w in log.unsupported if "not closed" in w)]


def test_open_volume_mesh_is_warned_but_exported(empty_scene):
    t = Tree("Fog")
    builders.mesh_object("Sheet", "plane", t.volume(scatter(t)))
    bpy.context.view_layer.update()
    scene, log = export()
    assert len(scene.volumes) == 1
    (warning,) = [w for w in log.unsupported if "not closed" in w]
    assert log.unsupported[warning] == ["Sheet"]


def test_heterogeneous_density_is_read_at_the_centre_and_warned(empty_scene):
    t = Tree("Cloud")
    node = scatter(t, density=1.0, color=(1.0, 1.0, 1.0, 1.0))
    noise = t.node("ShaderNodeTexNoise", Scale=3.0)
    t.link(noise.outputs["Fac"], node.inputs["Density"])
    box(t.volume(node), name="Cloud")
    scene, log = export()
    (volume,) = scene.volumes
    (warning,) = [w for w in log.unsupported if w.startswith(HETEROGENEOUS)]
    assert "a Noise Texture drives it" in warning and "the value at the volume's centre" in warning
    assert log.unsupported[warning] == ["Cloud"]
    density = volume.medium.sigma_s[0]
    assert 0.0 < density < 1.0 and density != pytest.approx(0.5, abs=1e-6)  # not the own value 1, nor a default
    assert f"{density:.3g}" in warning


def test_heterogeneous_density_that_cannot_be_evaluated_uses_its_own_value(empty_scene):
    """An Attribute node (a smoke domain's 'density') is not read here: the Density's own value, said."""
    t = Tree("Smoke")
    node = scatter(t, density=0.25, color=(1.0, 1.0, 1.0, 1.0))
    attribute = t.nodes.new("ShaderNodeAttribute")
    attribute.attribute_name = "density"
    t.link(attribute.outputs["Fac"], node.inputs["Density"])
    box(t.volume(node), name="Smoke")
    scene, log = export()
    (volume,) = scene.volumes
    assert volume.medium.sigma_s == pytest.approx((0.25, 0.25, 0.25))
    (warning,) = [w for w in log.unsupported if w.startswith(HETEROGENEOUS)]
    assert "the input's own value, 0.25" in warning and log.unsupported[warning] == ["Smoke"]


def test_constant_graph_on_density_folds_unwarned(empty_scene):
    t = Tree("Folded")
    node = scatter(t, density=9.0, color=(1.0, 1.0, 1.0, 1.0))
    math = t.node("ShaderNodeMath")
    math.operation = "MULTIPLY"
    math.inputs[0].default_value, math.inputs[1].default_value = 0.5, 0.6
    t.link(math.outputs[0], node.inputs["Density"])
    box(t.volume(node))
    scene, log = export()
    assert scene.volumes[0].medium.sigma_s == pytest.approx((0.3, 0.3, 0.3))
    assert volume_warnings(log) == []


def test_homogeneous_volume_only_material_is_no_longer_warned(empty_scene):
    """The warning before object volumes ('volume not simulated') is gone; the surface stays left out."""
    builders.area_light("Light", "RECTANGLE", size=1.0, power=100.0, location=(0, 0, 4))
    floor = builders.mesh_object("Floor", "plane", builders.material("Grey", (0.5, 0.5, 0.5)), size=10.0)
    t = Tree("Fog")
    box(t.volume(t.node("ShaderNodeVolumePrincipled", Density=0.3)))
    scene, log = export()
    assert [m.name for m in scene.meshes] == [floor.name]
    assert len(scene.volumes) == 1
    assert "volume" not in log.warning_text()


def test_world_volume_reads_the_same_graphs(empty_scene):
    """The world's medium comes from the same reader: an Add Shader of Scatter and Absorption."""
    tree = empty_scene.world.node_tree
    t = Tree.__new__(Tree)
    t.nodes, t.links = tree.nodes, tree.links
    add = t.node("ShaderNodeAddShader")
    t.link(scatter(t).outputs[0], add.inputs[0])
    t.link(absorption(t).outputs[0], add.inputs[1])
    t.link(add.outputs[0], tree.nodes["World Output"].inputs["Volume"])
    medium = export()[0].world.medium
    assert medium.sigma_s == pytest.approx((0.4, 0.3, 0.2))
    assert medium.sigma_a == pytest.approx((1.5, 1.0, 0.5))


def test_an_empty_smoke_domain_is_no_volume(empty_scene):
    """A gas domain with nothing simulated or cached at this frame: Cycles 3.4 multiplies Principled Volume's Density
    by the (all-zero) density grid and shows nothing; so is it left out.  A Volume Scatter in it reads no grid."""
    t = Tree("Smoke")
    domain = box(t.volume(t.node("ShaderNodeVolumePrincipled", Density=5.0)), name="Domain")
    modifier = domain.modifiers.new("Fluid", "FLUID")
    modifier.fluid_type = "DOMAIN"
    modifier.domain_settings.domain_type = "GAS"
    bpy.context.view_layer.update()
    scene, log = export()
    assert scene.volumes == [] and scene.meshes == []
    assert not [w for w in log.unsupported if w.startswith(HETEROGENEOUS)]
    t2 = Tree("Haze")
    domain.material_slots[0].material = t2.volume(scatter(t2, density=0.5))
    scene, log = export()
    (volume,) = scene.volumes
    assert volume.medium.sigma_s[0] == pytest.approx(0.4)
