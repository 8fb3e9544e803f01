"""The textured room and the still life (blend_scenes/13_textured_room, 14_still_life) against Cycles 3.4:
image textures (sRGB and Non-Color, a Mapping node, Generated coordinates, closest filtering, a tangent-space
normal map), Glass, Glossy, Principled metal and clearcoat, a Mix Shader, under rectangle and disk lights, at
max_bounces 0 (test_cycles_parity's renders -- Cycles 2048 spp, SPHRECT 512, fixed seeds -- and mean relative
difference over 4x4 blocks, lights hidden from the camera as there)."""
import bpy
import pytest

from conftest import engine_module, open_blend, render
from test_cycles_parity import HEIGHT, WIDTH, difference_to_cycles, mean_relative_difference

pytestmark = pytest.mark.slow

# Measured when written (Cycles' seeds 0 and 1 differ by 0.24% on the room, 0.50% on the still life):
# - still life 0.41%, at the two renders' noise: the other parity tests' bound for models that agree exactly.
# - textured room 1.52%, systematic, all of it on the normal-mapped left wall, a plane of object scale
#   (2.5, 1.5, 1): Cycles applies a tangent-space normal map in object space and transforms the result by the
#   object's normal matrix, the renderer in world space -- the same without a non-uniform object scale (a 2:1
#   plane: 14% apart with the object scaled, 0.06% with the scale applied to its mesh; the room with the wall's
#   scale applied: 0.29%). Its bound is 1.6x the figure; 1% once normal maps follow the object's scale.
BOUND = {"13_textured_room": 0.025, "14_still_life": 0.01}
# The images each scene's parity depends on: without them the comparison is far off (it sees the textures).
FAR_WITHOUT = {"13_textured_room": ("Wood Floor", "Base Color"), "14_still_life": ("Table Top", "Base Color")}


@pytest.mark.parametrize("name", sorted(BOUND))
def test_textured_scenes_match_cycles(name, tmp_path):
    scene = open_blend(name, WIDTH, HEIGHT)
    for obj in bpy.data.objects:
        if obj.type == "LIGHT":
            obj.visible_camera = False
    difference, ours, cycles = difference_to_cycles(scene, name, tmp_path)
    assert "textures" in engine_module().last_render["features"]
    assert cycles[..., :3].max() > 0
    assert difference <= BOUND[name]
    material, socket = FAR_WITHOUT[name]
    tree = bpy.data.materials[material].node_tree
    tree.links.remove(tree.nodes["Principled BSDF"].inputs[socket].links[0])
    untextured = mean_relative_difference(render()["images"]["rectangle"], cycles)
    print(f"{name} without '{material}' {socket} texture: {untextured:.4f}")
    assert untextured > 2 * BOUND[name]
