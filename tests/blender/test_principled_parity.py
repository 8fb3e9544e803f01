"""Principled BSDF parity with Cycles 3.4 (max_bounces = 0, no denoising, fixed seeds; test_cycles_parity's
renders and mean relative difference over 4x4 blocks): each lobe alone and all together over roughness,
specular, specular tint, metallic, sheen and clearcoat values, on a smooth sphere over a plane of the same
material, back-lit by a rectangle so grazing angles (sheen, retro-reflection, Fresnel) are in view. Also the
exporter: every modelled input reaches sphrect.Material, and what is not modelled is named in a warning."""

import bpy
import pytest

from conftest import builders, export, set_resolution
from test_cycles_parity import HEIGHT, WIDTH, difference_to_cycles

pytestmark = pytest.mark.slow

BASE = (0.8, 0.45, 0.25)
# Inputs per case (the rest at Blender's defaults: specular 0.5, roughness 0.5, sheen tint 0.5, ...).
CASES = {
    "burley_r1": {"Specular": 0.0, "Roughness": 1.0},
    "default": {},
    "issue_r1_spec0.5": {"Roughness": 1.0, "Specular": 0.5},
    "specular_r0.3": {"Roughness": 0.3, "Specular": 1.0},
    "specular_tint": {"Roughness": 0.4, "Specular": 1.0, "Specular Tint": 1.0},
    "metal_r0.3": {"Metallic": 1.0, "Roughness": 0.3},
    "half_metal": {"Metallic": 0.5, "Roughness": 0.45},
    "sheen": {"Specular": 0.0, "Sheen": 1.0, "Sheen Tint": 0.5},
    "clearcoat_r0.1": {"Clearcoat": 1.0, "Clearcoat Roughness": 0.1, "Roughness": 0.6},
    "clearcoat_r0.3_on_metal": {"Clearcoat": 0.6, "Clearcoat Roughness": 0.3, "Metallic": 1.0, "Roughness": 0.5},
    "all": {"Metallic": 0.3, "Specular": 0.7, "Specular Tint": 0.4, "Roughness": 0.45, "Sheen": 0.6,
            "Clearcoat": 0.7, "Clearcoat Roughness": 0.2},
}
TOLERANCE = 0.01
# Cycles 3.4 samples its clearcoat closure from GGX visible normals of alpha = roughness^2 but weights the
# samples with the GTR1 pdf it evaluates (bsdf_microfacet_ggx_sample), so its BSDF-sampled (MIS) share of an
# area light's highlight is biased bright, the more so the sharper the coat (GTR1's peak is ln(1/alpha^2)
# times lower than GGX's). Measured when written: Cycles' mean 3.4% above ours at clearcoat roughness 0.1 (mean
# relative difference 2.9%), 0.5% at 0.3; under a point light (no BSDF sample in Cycles) the same materials
# agree within 0.2% (test below): the model matches, Cycles' estimator does not converge to it.
CYCLES_CLEARCOAT_BIAS = {"clearcoat_r0.1": 0.035}


def principled(name, inputs):
    mat = builders.material(name, BASE, kind="principled")
    node = mat.node_tree.nodes["Principled BSDF"]
    for socket, value in inputs.items():
        node.inputs[socket].default_value = value
    return mat


def principled_scene(scene, inputs, light="area"):
    mat = principled("Principled", inputs)
    builders.mesh_object("Ground", "plane", mat, size=8)
    sphere = builders.mesh_object("Ball", "uv_sphere", mat, location=(0.0, 0.0, 1.0), segments=48, ring_count=24)
    builders.smooth(sphere)
    if light == "area":
        lamp = builders.area_light("Light", "RECTANGLE", size=2.0, size_y=1.2, power=400.0,
                                   location=(1.2, 2.6, 3.0), visible=False)
        builders.aim(lamp, (0.0, 0.0, 0.6))
    else:  # a point light: Cycles samples only the light, no BSDF sample, no MIS
        builders.other_light("Light", "POINT", 400.0, location=(1.2, 2.6, 3.0))
    set_resolution(scene, WIDTH, HEIGHT)
    scene.sphrect.technique = "RECTANGLE"
    bpy.context.view_layer.update()
    return scene


@pytest.mark.parametrize("case", sorted(CASES))
def test_principled_matches_cycles(empty_scene, case, tmp_path):
    scene = principled_scene(empty_scene, CASES[case])
    difference, ours, cycles = difference_to_cycles(scene, f"principled {case}", tmp_path, light_samples=2)
    print(f"principled {case}: mean ours / Cycles {ours[..., :3].mean() / cycles[..., :3].mean():.4f}")
    assert cycles[..., :3].max() > 0
    assert difference <= CYCLES_CLEARCOAT_BIAS.get(case, TOLERANCE)


@pytest.mark.parametrize("case", ["clearcoat_r0.1", "all"])
def test_principled_clearcoat_under_a_point_light_matches_cycles(empty_scene, case, tmp_path):
    scene = principled_scene(empty_scene, CASES[case], light="point")
    difference, ours, cycles = difference_to_cycles(scene, f"principled {case} (point light)", tmp_path)
    print(f"principled {case} (point light): mean ours / Cycles {ours[..., :3].mean() / cycles[..., :3].mean():.4f}")
    assert difference <= TOLERANCE


def test_exporter_reads_principled_inputs_and_names_the_rest(empty_scene):
    inputs = {"Metallic": 0.25, "Specular": 0.6, "Specular Tint": 0.3, "Roughness": 0.4, "Sheen": 0.7,
              "Sheen Tint": 0.2, "Clearcoat": 0.5, "Clearcoat Roughness": 0.15}
    mat = principled("P", inputs)
    node = mat.node_tree.nodes["Principled BSDF"]
    node.inputs["Subsurface"].default_value = 0.1
    node.inputs["Anisotropic"].default_value = 0.5
    node.distribution = "MULTI_GGX"
    builders.mesh_object("Ball", "uv_sphere", mat)
    plain = principled("Plain", {})
    builders.mesh_object("Other", "cube", plain, location=(3, 0, 0))
    scene, log = export()
    m = {m.name: m for m in scene.materials}["P"]
    assert m.kind == "principled" and m.base_color == pytest.approx(BASE)
    got = (m.metallic, m.specular, m.specular_tint, m.roughness, m.sheen, m.sheen_tint, m.clearcoat,
           m.clearcoat_roughness)
    assert got == pytest.approx(tuple(inputs.values()))
    text = log.warning_text()
    assert "subsurface scattering (Burley diffuse used) (P)" in text
    # Anisotropy and Multiscatter GGX are modelled (test_anisotropic_parity, test_multiscatter_parity).
    assert (m.anisotropic, m.distribution) == (pytest.approx(0.5), "multiscatter_ggx")
    assert "anisotropy" not in text and "Multiscatter GGX" not in text
    assert "Plain" not in text  # Blender's default Principled BSDF is modelled in full
