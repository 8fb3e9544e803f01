"""Volume-only materials (Volume linked, Surface not): Cycles shows their surface as transparent, so the
exporter leaves those triangles out -- they neither shade nor occlude -- and warns, naming the object, that
the volume itself is not simulated. Exporter, F12 render and Cycles parity (with a near-zero density, so
Cycles' volume does not change the image)."""
import bpy
import numpy as np
import pytest

from conftest import builders, export, lit_test_scene, render, set_resolution
from test_cycles_parity import HEIGHT, WIDTH, difference_to_cycles

WARNING = "volume-only materials (surface transparent, volume not simulated)"


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


def test_volume_only_object_is_left_out_with_a_warning(empty_scene):
    lit_test_scene(empty_scene)
    scene_without, _ = export()
    fog_box()
    bpy.context.view_layer.update()
    scene, log = export()
    assert [m.name for m in scene.meshes] == [m.name for m in scene_without.meshes]  # no FogBox mesh
    assert "FogBox" in log.unsupported[WARNING]
    assert "without a surface shader" not in log.warning_text()


def test_volume_only_slot_of_a_mixed_object_is_left_out(empty_scene):
    """A cube whose top face has a volume-only material keeps its five other faces."""
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
    assert "Cube" in log.unsupported[WARNING]


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
    assert len(scene.meshes) == 1
    assert WARNING not in log.unsupported


def _render_rectangle(scene):
    s = scene.sphrect
    s.technique, s.samples, s.passes, s.seed = "RECTANGLE", 8, 1, 1
    return render()["images"]["rectangle"]


def test_fog_box_no_longer_hides_the_lit_scene(empty_scene):
    """F12 with the fog box in front of the lit plane gives the image without it (it used to be black)."""
    scene = lit_test_scene(empty_scene)
    without = _render_rectangle(scene)
    box = fog_box()
    bpy.context.view_layer.update()
    with_box = _render_rectangle(scene)
    assert without[..., :3].mean() > 0.01
    assert np.allclose(with_box, without, rtol=1e-5, atol=1e-6)
    # The check can fail: the same box with a diffuse surface darkens the view (its shadowed faces).
    box.data.materials[0] = builders.material("Grey", (0.05, 0.05, 0.05))
    bpy.context.view_layer.update()
    opaque = _render_rectangle(scene)
    assert np.abs(opaque - without)[..., :3].mean() > 0.01


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
