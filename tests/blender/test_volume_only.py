"""Volume-only materials (Volume linked, Surface not): Cycles shows their surface as transparent, so the
exporter leaves those triangles out of the meshes -- they neither shade nor occlude -- and exports their volume
as an object volume (test_volume_export.py), unwarned.  Exporter and Cycles parity (with a near-zero density:
the box shows nothing)."""
import bpy
import numpy as np
import pytest

from conftest import builders, export, lit_test_scene, set_resolution
from test_cycles_parity import HEIGHT, WIDTH, difference_to_cycles


def fog_material(name="Fog", density=0.5):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    volume = nodes.new("ShaderNodeVolumePrincipled")
    volume.inputs["Density"].default_value = density
    mat.node_tree.links.new(volume.outputs[0], out.inputs["Volume"])
    return mat


def fog_box(density=0.5):
    """A 1.6 m fog box between the camera and the lit scene, covering the middle of the view."""
    return builders.mesh_object("FogBox", "cube", fog_material(density=density), location=(0.0, -2.5, 0.9),
                                size=1.6)


def test_volume_only_object_is_a_volume_and_no_mesh(empty_scene):
    lit_test_scene(empty_scene)
    scene_without, _ = export()
    fog_box()
    bpy.context.view_layer.update()
    scene, log = export()
    assert [m.name for m in scene.meshes] == [m.name for m in scene_without.meshes]  # no FogBox mesh
    assert [v.name for v in scene.volumes] == ["FogBox"]
    assert "volume" not in log.warning_text()
    assert "without a surface shader" not in log.warning_text()


def test_volume_only_slot_of_a_mixed_object_is_left_out(empty_scene):
    """A cube whose top face has a volume-only material keeps its five other faces; the top face is a volume of its
    own (open: warned)."""
    builders.area_light("Light", "RECTANGLE", size=1.0, power=100.0, location=(0, 0, 3))
    cube = builders.mesh_object("Cube", "cube", builders.material("Solid", (0.5, 0.5, 0.5)))
    cube.data.materials.append(fog_material())
    top = max(cube.data.polygons, key=lambda p: p.center.z)
    top.material_index = 1
    bpy.context.view_layer.update()
    scene, log = export()
    (mesh,) = scene.meshes
    assert len(mesh.triangles) == 10
    assert all(scene.materials[i].name == "Solid" for i in np.unique(mesh.material_ids))
    vertices = np.asarray(mesh.vertices)[np.asarray(mesh.triangles)]
    assert not np.all(vertices[..., 2] > 0.99, axis=1).any()  # no triangle of the top face is left
    (volume,) = scene.volumes
    assert len(volume.triangles) == 2
    assert log.unsupported[next(w for w in log.unsupported if "not closed" in w)] == ["Cube"]


def test_material_with_neither_surface_nor_volume_stays_black(empty_scene):
    """Only a Volume link makes a surface transparent; an empty output is black in Cycles, and stays opaque."""
    mat = bpy.data.materials.new("Empty")
    mat.use_nodes = True
    mat.node_tree.nodes.clear()
    mat.node_tree.nodes.new("ShaderNodeOutputMaterial")
    builders.area_light("Light", "RECTANGLE", size=1.0, power=100.0, location=(0, 0, 3))
    builders.mesh_object("Cube", "cube", mat)
    bpy.context.view_layer.update()
    scene, log = export()
    assert len(scene.meshes) == 1 and scene.volumes == []
    assert "volume" not in log.warning_text()


@pytest.mark.parametrize("density", [1e-6])
def test_fog_box_of_zero_density_matches_cycles(empty_scene, density, tmp_path):
    """Cycles renders the near-empty volume's box as nothing: the lit scene behind it shows unchanged."""
    scene = lit_test_scene(empty_scene)
    bpy.data.objects["Light"].visible_camera = False
    fog_box(density)
    set_resolution(scene, WIDTH, HEIGHT)
    scene.sphrect.technique = "RECTANGLE"
    bpy.context.view_layer.update()
    difference, ours, cycles = difference_to_cycles(scene, "fog box (density ~0)", tmp_path, light_samples=4)
    assert cycles[..., :3].max() > 0
    assert difference <= 0.02  # test_diffuse_scene_matches_cycles' bound, on the same scene
