"""Cycles parity of the Diffuse BSDF's Roughness (Cycles 3.4's Oren-Nayar): the smallest test scene with its ground
and box Diffuse BSDFs of Roughness 0.5 and 1, rendered as test_cycles_parity.py does (Cycles 2048 spp, SPHRECT 512,
mean relative difference over lit 4x4 blocks).  The same scene rendered as Lambert differs by far more, so the
comparison would catch the roughness ignored.  Fixed seeds: deterministic."""
import bpy
import pytest

from conftest import builders, lit_test_scene, render, set_resolution
from test_cycles_parity import HEIGHT, WIDTH, difference_to_cycles, mean_relative_difference


@pytest.mark.slow
@pytest.mark.parametrize("roughness", [0.5, 1.0])
def test_oren_nayar_matches_cycles(roughness, empty_scene, tmp_path):
    lit_test_scene(empty_scene)
    bpy.data.objects["Light"].visible_camera = False
    for name in ("Ground", "Box"):
        mat, _ = builders.node_material(f"{name} rough", "ShaderNodeBsdfDiffuse", Color=(0.7, 0.6, 0.5, 1.0),
                                        Roughness=roughness)
        bpy.data.objects[name].data.materials[0] = mat
    set_resolution(empty_scene, WIDTH, HEIGHT)
    empty_scene.sphrect.technique = "RECTANGLE"
    difference, _, cycles = difference_to_cycles(empty_scene, f"Oren-Nayar {roughness}", tmp_path, light_samples=4)
    assert difference <= 0.01
    for name in ("Ground", "Box"):
        bpy.data.materials[f"{name} rough"].node_tree.nodes["Diffuse BSDF"].inputs["Roughness"].default_value = 0.0
    empty_scene.sphrect.samples = 512
    lambert = render()["images"]["rectangle"]
    ignored = mean_relative_difference(lambert, cycles)
    print(f"Oren-Nayar {roughness}: as Lambert {ignored:.4f}")
    assert ignored > 0.03
