"""Material kinds 'glossy_bsdf' (Cycles 3.4's Glossy BSDF: colour x microfacet reflection, no Fresnel) and 'mix'
(Mix / Add Shader: the layers' closures scaled by their weights) through sphrect.Scene: a sun-lit plane seen by a
tilted orthographic camera has one exact radiance, f(wo, wi) E cos, compared with NumPy transcriptions of
Cycles' closures (the Principled and Glass ones of the neighbouring tests); what a mix cannot hold is refused
with a message; the fields round-trip through scene files and version-4 files load unchanged."""
import dataclasses
import json
import math

import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh
from test_materials_glass import cycles_glass_reflection
from test_materials_glass import cycles_microfacet_reflection as cycles_glossy  # the Glossy BSDF
from test_materials_principled import (E_SUN, TILT, cycles_principled_brdf, fresnel_dielectric, plain,
                                      tilted_camera)

WO = np.array([0.0, -math.sin(TILT), math.cos(TILT)])
SUNS = [(0.0, 1.2), (0.6, -0.4), (0.0, 3.0)]  # (x, y) of wi before normalising, z = 1


def reference(m, wo, wi):
    if m.kind == "diffuse":
        return np.asarray(m.base_color) / math.pi
    if m.kind == "principled":
        return cycles_principled_brdf(m, wo, wi)
    if m.kind == "glass":
        return cycles_glass_reflection(m, wo, wi)
    if m.kind == "glossy_bsdf":
        return cycles_glossy(m, wo, wi)
    assert m.kind == "mix"
    return sum(layer.weight * reference(layer.material, wo, wi) for layer in m.layers)


def sunlit_image(mat, wi):
    scene = sphrect.Scene(camera=tilted_camera(), meshes=[plane_mesh()], materials=[mat],
                          lights=[sphrect.SunLight(direction=tuple(-wi), irradiance=(E_SUN,) * 3)])
    return sphrect.render(scene, samples=2)["rectangle"][..., :3]


def check_sunlit_plane(mat):
    for sun in SUNS:
        wi = np.array([sun[0], sun[1], 1.0])
        wi /= np.linalg.norm(wi)
        image = sunlit_image(mat, wi)
        expected = reference(mat, WO, wi) * E_SUN * wi[2]
        np.testing.assert_allclose(image, np.broadcast_to(expected, image.shape), rtol=2e-4, atol=1e-9)


def deep_plain(material):
    """The material as its scene file stores it (tuples as lists, at every depth)."""
    return json.loads(json.dumps(dataclasses.asdict(material)))


def layer(weight, **kw):
    return sphrect.MaterialLayer(weight=weight, material=sphrect.Material(**kw))


GLOSSY = dict(kind="glossy_bsdf", base_color=(0.9, 0.6, 0.3), roughness=0.3)
PRINCIPLED = dict(kind="principled", base_color=(0.7, 0.45, 0.2), roughness=0.45, specular=0.7, sheen=0.5,
                  clearcoat=0.5, clearcoat_roughness=0.2)
MIXES = {
    "diffuse + glossy": [layer(0.6, kind="diffuse", base_color=(0.8, 0.3, 0.2)), layer(0.4, **GLOSSY)],
    "principled + glossy": [layer(0.7, **PRINCIPLED), layer(0.3, **GLOSSY)],
    "add glossy + glossy": [layer(1.0, **GLOSSY), layer(1.0, kind="glossy_bsdf", base_color=(0.2, 0.4, 0.6),
                                                        roughness=0.7, distribution="beckmann")],
    "diffuse + glass + principled": [layer(0.2, kind="diffuse"), layer(0.5, kind="glass", roughness=0.25, ior=1.6),
                                     layer(0.3, **PRINCIPLED)],
    "nested": [layer(0.5, kind="mix", layers=[layer(0.5, kind="diffuse"), layer(0.5, **GLOSSY)]),
               layer(0.5, **GLOSSY)],
}


@pytest.mark.parametrize("distribution", sphrect.scene.GLASS_DISTRIBUTIONS)
@pytest.mark.parametrize("roughness", [0.2, 0.5, 0.8])
def test_sunlit_plane_has_cycles_glossy_radiance(roughness, distribution):
    mat = sphrect.Material(kind="glossy_bsdf", base_color=(0.9, 0.7, 0.5), roughness=roughness,
                           distribution=distribution)
    check_sunlit_plane(mat)
    # No Fresnel: the same lobe as a glass of any IOR differs (the comparison could fail).
    wi = np.array([0.0, 1.2, 1.0]) / math.hypot(1.2, 1.0)
    glass = sphrect.Material(kind="glass", base_color=mat.base_color, roughness=roughness, ior=1.45,
                             distribution=distribution)
    assert np.all(cycles_glass_reflection(glass, WO, wi) < 0.2 * cycles_glossy(mat, WO, wi))


def test_sharp_glossy_is_black_at_zero_bounces():
    wi = np.array([0.0, math.sin(TILT), math.cos(TILT)])  # the mirror direction
    assert sunlit_image(sphrect.Material(kind="glossy_bsdf", roughness=0.0), wi).max() == 0


@pytest.mark.parametrize("name", sorted(MIXES))
def test_sunlit_plane_has_the_weighted_sum_of_the_layers(name):
    mat = sphrect.Material(kind="mix", layers=MIXES[name])
    check_sunlit_plane(mat)
    # The weights matter: the first layer's doubled changes the reference well beyond the tolerance.
    wi = np.array([0.6, -0.4, 1.0]) / np.linalg.norm([0.6, -0.4, 1.0])
    heavier = sphrect.Material(kind="mix", layers=[sphrect.MaterialLayer(2 * MIXES[name][0].weight,
                                                                         MIXES[name][0].material), *MIXES[name][1:]])
    assert np.max(np.abs(reference(heavier, WO, wi) / reference(mat, WO, wi) - 1)) > 1e-2


def test_mix_emission_adds_the_layers_weighted():
    mat = sphrect.Material(kind="mix", emission=(0.1, 0.0, 0.0),
                           layers=[layer(0.25, kind="diffuse", base_color=(0, 0, 0), emission=(0.0, 2.0, 0.0)),
                                   layer(0.75, kind="diffuse", base_color=(0, 0, 0))])
    wi = np.array([0.0, 0.0, 1.0])
    np.testing.assert_allclose(sunlit_image(mat, wi)[0, 0], (0.1, 0.5, 0.0), rtol=1e-5, atol=1e-7)


def test_what_a_mix_cannot_hold_is_refused():
    two_principled = sphrect.Material(name="pp", kind="mix",
                                      layers=[layer(0.5, **PRINCIPLED), layer(0.5, **PRINCIPLED)])
    with pytest.raises(ValueError, match="'pp'.*at most one Principled"):
        sunlit_image(two_principled, np.array([0.0, 0.0, 1.0]))
    n = sphrect.MAX_MIX_GLOSSY_LOBES
    many = [layer(1.0, kind="glossy_bsdf", roughness=0.2 + 0.1 * i) for i in range(n + 1)]
    sunlit_image(sphrect.Material(kind="mix", layers=many[:n]), np.array([0.0, 0.0, 1.0]))  # n fit
    with pytest.raises(ValueError, match=f"at most {n} distinct"):
        sunlit_image(sphrect.Material(kind="mix", layers=many), np.array([0.0, 0.0, 1.0]))
    with pytest.raises(ValueError, match="'glossy' model cannot be mixed"):
        sunlit_image(sphrect.Material(kind="mix", layers=[layer(1.0, kind="glossy")]), np.array([0.0, 0.0, 1.0]))
    with pytest.raises(ValueError, match="only kind 'mix' has layers"):
        sunlit_image(sphrect.Material(kind="diffuse", layers=[layer(1.0, kind="diffuse")]), np.array([0.0, 0.0, 1.0]))
    with pytest.raises(ValueError, match="weight"):
        sunlit_image(sphrect.Material(kind="mix", layers=[layer(-0.5, kind="diffuse")]), np.array([0.0, 0.0, 1.0]))


def test_mix_fields_round_trip_and_version_4_files_load(tmp_path):
    mats = [sphrect.Material(name="m", kind="mix", layers=MIXES["nested"]),
            sphrect.Material(name="g", kind="glossy_bsdf", roughness=0.3, distribution="beckmann")]
    path = str(tmp_path / "v5.sphrect.npz")
    sphrect.save_scene(sphrect.Scene(materials=mats), path)
    loaded = sphrect.load_scene(path).materials
    assert [deep_plain(m) for m in loaded] == [deep_plain(m) for m in mats]
    assert isinstance(loaded[0].layers[0].material.layers[1], sphrect.MaterialLayer)
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    meta = json.loads(bytes(arrays["scene.json"]).decode("utf-8"))
    meta["version"] = 4
    glass = sphrect.Material(name="v4", kind="glass", roughness=0.3)
    meta["materials"] = [{k: v for k, v in plain(glass).items() if k != "layers"}]
    arrays["scene.json"] = np.frombuffer(json.dumps(meta).encode("utf-8"), dtype=np.uint8)
    old = str(tmp_path / "v4.sphrect.npz")
    np.savez_compressed(old, **arrays)
    assert [plain(m) for m in sphrect.load_scene(old).materials] == [plain(glass)]


def ggx_lobe_albedo(color, roughness, wo, fresnel_ior=None, n_theta=1500, n_phi=720):
    """Midpoint quadrature over the hemisphere of colour [F(wo)] D G1 G1 / (4 cos cos) cos(wi)."""
    theta = (np.arange(n_theta) + 0.5) * (0.5 * math.pi / n_theta)
    phi = (np.arange(n_phi) + 0.5) * (2 * math.pi / n_phi)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    wi = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)
    h = wi + wo
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    alpha = roughness ** 2
    d = alpha ** 2 / (math.pi * (h[..., 2] ** 2 * (alpha ** 2 - 1) + 1) ** 2)
    g1 = lambda c: 2 / (1 + np.sqrt(1 + alpha ** 2 * (1 - c * c) / (c * c)))
    value = d * g1(wo[2]) * g1(wi[..., 2]) / (4 * wo[2])  # f cos(wi)
    fresnel = 1.0 if fresnel_ior is None else fresnel_dielectric(wo[2], fresnel_ior)
    integral = np.sum(value * np.sin(t)) * (0.5 * math.pi / n_theta) * (2 * math.pi / n_phi)
    return np.asarray(color) * fresnel * integral


def test_bsdf_sampling_of_a_mix_matches_its_albedo():
    """Under a uniform white background (no lights) each pixel is the BSDF-sampled estimate of the directional
    albedo, f cos / pdf: it converges to the albedo only if the mix's lobe choice, each lobe's warp and the
    mixture pdf agree.  Reference: quadrature of Cycles' closures.  The mean of 16 pixels x 4096 samples has a
    relative standard error ~0.1% (measured), so the 1% tolerance does not fail by chance."""
    layers = [layer(0.3, kind="diffuse", base_color=(0.8, 0.5, 0.2)),
              layer(0.4, kind="glossy_bsdf", base_color=(0.9, 0.9, 0.6), roughness=0.5),
              layer(0.3, kind="glass", base_color=(1.0, 1.0, 1.0), roughness=0.6, ior=1.5)]
    mat = sphrect.Material(kind="mix", layers=layers)
    scene = sphrect.Scene(camera=tilted_camera(), meshes=[plane_mesh()], materials=[mat],
                          world=sphrect.World(background=(1.0, 1.0, 1.0)))
    image = sphrect.render(scene, samples=4096)["rectangle"][..., :3]
    expected = (0.3 * np.array([0.8, 0.5, 0.2]) + 0.4 * ggx_lobe_albedo((0.9, 0.9, 0.6), 0.5, WO)
                + 0.3 * ggx_lobe_albedo((1.0, 1.0, 1.0), 0.6, WO, fresnel_ior=1.5))
    np.testing.assert_allclose(image.reshape(-1, 3).mean(axis=0), expected, rtol=0.01)
    # The glossy lobes' share is several times the tolerance (the check sees them).
    assert np.all(0.4 * ggx_lobe_albedo((0.9, 0.9, 0.6), 0.5, WO) > 0.1 * expected)


def test_mix_lobe_slots_follow_the_renderers_merging():
    # Equal glossy lobes share a slot (the renderer merges them), another roughness, distribution or IOR takes a new
    # one, a diffuse layer none: what the Blender exporter asks before it drops lobes beyond MAX_MIX_GLOSSY_LOBES.
    glossy = sphrect.Material(kind="glossy_bsdf", roughness=0.3)
    slots = sphrect.mix_lobe_slots([glossy, sphrect.Material(kind="diffuse"), glossy,
                                    sphrect.Material(kind="glossy_bsdf", roughness=0.5),
                                    sphrect.Material(kind="glossy_bsdf", roughness=0.3, distribution="beckmann"),
                                    sphrect.Material(kind="glass", roughness=0.3, ior=1.5),
                                    sphrect.Material(kind="glass", roughness=0.3, ior=1.5, base_color=(1, 0, 0))])
    assert slots == [0, -1, 0, 1, 2, 3, 3]
    n = sphrect.MAX_MIX_GLOSSY_LOBES
    many = [sphrect.Material(kind="glossy_bsdf", roughness=0.2 + 0.1 * i) for i in range(n + 1)]
    assert sphrect.mix_lobe_slots(many) == list(range(n + 1))
