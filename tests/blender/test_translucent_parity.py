"""Translucent BSDF as Cycles 3.4 shows it at max_bounces 0: a thin screen lit from behind (a lampshade, a
paper window) seen from the front, against Cycles (test_cycles_parity's renders and mean relative difference
over 4x4 blocks)."""
import bpy

from conftest import builders, export, render
from test_cycles_parity import WIDTH, HEIGHT, difference_to_cycles, mean_relative_difference
from test_glass_parity import shader_material
from conftest import set_resolution

TOLERANCE = 0.01


def screen_scene(scene, mat):
    """The screen stands at y = 0 facing the camera (at y = -6), a 400 W rectangle 1.5 m behind it aimed at it,
    a diffuse ground lit by the light around the screen."""
    builders.mesh_object("Ground", "plane", builders.material("Ground", (0.8, 0.8, 0.8)), size=8)
    builders.mesh_object("Screen", "plane", mat, location=(0.0, 0.0, 1.2), rotation=(1.5708, 0.0, 0.0), size=1.6)
    lamp = builders.area_light("Light", "RECTANGLE", size=1.0, size_y=0.8, power=400.0, location=(0.3, 1.5, 1.6),
                               visible=False)
    builders.aim(lamp, (0.0, 0.0, 1.2))
    set_resolution(scene, WIDTH, HEIGHT)
    scene.sphrect.technique = "RECTANGLE"
    bpy.context.view_layer.update()
    return scene


def test_translucent_screen_lit_from_behind_matches_cycles(empty_scene, tmp_path):
    scene = screen_scene(empty_scene, shader_material("ShaderNodeBsdfTranslucent", Color=(0.8, 0.6, 0.4, 1.0)))
    exported, log = export()
    (m,) = [m for m in exported.materials if m.name == "ShaderNodeBsdfTranslucent"]
    assert m.kind == "translucent" and "Translucent" not in log.warning_text()
    difference, ours, cycles = difference_to_cycles(scene, "translucent screen", tmp_path)
    assert difference <= TOLERANCE
    # The comparison can fail: the screen black (as it was rendered before the translucent kind) is far off.
    bpy.data.objects["Screen"].data.materials[0] = builders.material("Black", (0.0, 0.0, 0.0))
    black = render()["images"]["rectangle"]
    assert mean_relative_difference(black, cycles) > 0.05
