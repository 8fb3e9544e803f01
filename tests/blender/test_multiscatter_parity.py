"""The Principled BSDF's Multiscatter GGX as Cycles 3.4 shows it at max_bounces 0: the specular's multiple
scattering between microfacets (Heitz et al. 2016's random walk, render/bsdf/multiscatter_ggx.h) brightens rough metals
and dielectrics' specular.  The glass test's sphere, against Cycles (test_cycles_parity's renders; the whole image
and ours / Cycles over the highlight's blocks), and the single-scattering GGX rendered instead is measurably off."""
import pytest

from conftest import export
from test_cycles_parity import difference_to_cycles
from test_glass_parity import highlight_ratio, shader_material, sphere_scene

pytestmark = pytest.mark.slow

TOLERANCE = 0.01
HIGHLIGHT_TOLERANCE = 0.05  # the highlight's own blocks, as in test_glass_parity

CASES = {
    "rough_gold": dict(Metallic=1.0, Roughness=0.7, **{"Base Color": (0.95, 0.7, 0.35, 1.0)}),
    "rough_white_metal": dict(Metallic=1.0, Roughness=1.0, **{"Base Color": (0.9, 0.9, 0.9, 1.0)}),
    "dielectric": dict(Roughness=0.5, Specular=1.0, **{"Base Color": (0.2, 0.4, 0.7, 1.0)}),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_multiscatter_sphere_matches_cycles(empty_scene, case, tmp_path):
    mat = shader_material("ShaderNodeBsdfPrincipled", distribution="MULTI_GGX", **CASES[case])
    scene = sphere_scene(empty_scene, mat)
    exported, log = export()
    (m,) = [m for m in exported.materials if m.name == mat.name]
    assert m.distribution == "multiscatter_ggx" and "Multiscatter" not in log.warning_text()
    difference, ours, cycles = difference_to_cycles(scene, f"multiscatter: {case}", tmp_path)
    assert difference <= TOLERANCE
    if case == "rough_white_metal":
        # The comparison can fail: single-scattering GGX (what the renderer drew before) loses the sphere's energy.
        (node,) = [n for n in mat.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled"]
        node.distribution = "GGX"
        single, _, _ = difference_to_cycles(scene, "multiscatter rendered as GGX", tmp_path, cycles=cycles)
        assert single > 2 * max(difference, 0.002)
    ratio = highlight_ratio(scene, ours, cycles, tmp_path)
    print(f"multiscatter {case}: highlight ours / Cycles {ratio:.3f}")
    assert abs(ratio - 1) <= HIGHLIGHT_TOLERANCE


def test_multiscatter_glossy_bsdf_matches_cycles(empty_scene, tmp_path):
    """The Glossy BSDF's Multiscatter GGX: no Fresnel, its Color tinting every bounce (and the whole, as the closure's
    weight)."""
    mat = shader_material("ShaderNodeBsdfGlossy", distribution="MULTI_GGX", Roughness=0.8, Color=(0.9, 0.5, 0.3, 1.0))
    scene = sphere_scene(empty_scene, mat)
    exported, log = export()
    (m,) = [m for m in exported.materials if m.name == mat.name]
    assert (m.kind, m.distribution) == ("glossy_bsdf", "multiscatter_ggx") and "Multiscatter" not in log.warning_text()
    difference, ours, cycles = difference_to_cycles(scene, "multiscatter glossy", tmp_path)
    assert difference <= TOLERANCE
    ratio = highlight_ratio(scene, ours, cycles, tmp_path)
    print(f"multiscatter glossy: highlight ours / Cycles {ratio:.3f}")
    assert abs(ratio - 1) <= HIGHLIGHT_TOLERANCE
