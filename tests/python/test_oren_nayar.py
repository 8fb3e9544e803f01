"""The Diffuse BSDF's Roughness: Cycles 3.4's Oren-Nayar (bsdf_oren_nayar.h), f cos = cos_i (a + b t), a = 1 / (pi +
(3 pi - 4) / 6 sigma), b = sigma a, t = (wi.wo - cos_i cos_o) / max(cos_i, cos_o) where positive.  Checked exactly
(deterministic: a sharp sun and an orthographic camera make every pixel the same closed form), against Lambert at
roughness 0 bit for bit, and inside a mix."""
import math

import numpy as np
import pytest

import sphrect

BASE = (0.7, 0.5, 0.3)
E = 2.0


def plane():
    v = np.array([[-50, -50, 0], [50, -50, 0], [50, 50, 0], [-50, 50, 0]], np.float32)
    return sphrect.Mesh(vertices=v, triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32),
                        material_ids=np.zeros(2, np.int32))


def ortho_camera(wo):
    """Looking along -wo at the origin (wo towards the camera, in the x = 0 plane), 4 x 4 pixels."""
    z = np.asarray(wo, float) / np.linalg.norm(wo)
    x = np.array([1.0, 0, 0])
    y = np.cross(z, x)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = x, y, z, 5 * z
    return sphrect.Camera(width=4, height=4, type="orthographic", ortho_scale=0.5, to_world=m.tolist())


def unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def oren_nayar(sigma, wo, wi):
    """Cycles' f cos / cos (the BRDF) for unit wo, wi about n = +z."""
    s = min(max(sigma, 0.0), 1.0)
    a = 1 / (math.pi + (3 * math.pi - 4) / 6 * s)
    b = s * a
    nl, nv = max(wi[2], 0.0), max(wo[2], 0.0)
    t = float(np.dot(wi, wo)) - nl * nv
    if t > 0:
        t /= max(nl, nv)
    return a + b * t


def render(material, wo, wi, samples=2, **kw):
    sun = sphrect.SunLight(direction=tuple(-unit(wi)), irradiance=(E, E, E))
    scene = sphrect.Scene(camera=ortho_camera(wo), meshes=[plane()], materials=[material], lights=[sun])
    r = sphrect.Renderer(scene, techniques=["rectangle"], seed=2, **kw)
    assert r.render(samples)
    return r.image("rectangle")[..., :3].astype(np.float64)


# (view, light) pairs: t > 0 (same azimuth side), t < 0 (opposite), grazing view, the view along the normal.
GEOMETRIES = [((0, 0.5, 1), (0, 1, 1)), ((0, 0.5, 1), (0, -1, 0.7)), ((0, 3, 0.4), (0.3, 0.8, 1)),
              ((0, 0, 1), (1, 0.2, 0.5)), ((0, -2, 1), (0.5, -1, 0.3))]


@pytest.mark.parametrize("sigma", [0.2, 0.6, 1.0, 1.7])
@pytest.mark.parametrize("view, light", GEOMETRIES)
def test_oren_nayar_closed_form(sigma, view, light):
    wo, wi = unit(view), unit(light)
    image = render(sphrect.Material(kind="diffuse", base_color=BASE, diffuse_roughness=sigma), wo, wi)
    expected = np.array(BASE) * oren_nayar(sigma, wo, wi) * E * wi[2]
    np.testing.assert_allclose(image, np.broadcast_to(expected, image.shape), rtol=2e-5)
    # It is not Lambert (the test can fail): Lambert differs by more than 1% here.
    assert abs(oren_nayar(sigma, wo, wi) * math.pi - 1) > 0.01


def test_roughness_zero_is_lambert_bit_for_bit():
    wo, wi = unit((0, 0.5, 1)), unit((0, 1, 1))
    lambert = render(sphrect.Material(kind="diffuse", base_color=BASE), wo, wi)
    np.testing.assert_array_equal(render(sphrect.Material(kind="diffuse", base_color=BASE, diffuse_roughness=0.0),
                                         wo, wi), lambert)
    np.testing.assert_allclose(lambert, np.broadcast_to(np.array(BASE) / math.pi * E * wi[2], lambert.shape),
                               rtol=2e-5)


def test_in_a_mix_each_layer_keeps_its_lobe():
    """Half Oren-Nayar, half Lambert: the mean of the two closed forms."""
    wo, wi = unit((0, 0.5, 1)), unit((0, -1, 0.7))
    mix = sphrect.Material(kind="mix", layers=[
        sphrect.MaterialLayer(0.5, sphrect.Material(kind="diffuse", base_color=BASE, diffuse_roughness=0.8)),
        sphrect.MaterialLayer(0.5, sphrect.Material(kind="diffuse", base_color=BASE))])
    image = render(mix, wo, wi)
    expected = np.array(BASE) * 0.5 * (oren_nayar(0.8, wo, wi) + 1 / math.pi) * E * wi[2]
    np.testing.assert_allclose(image, np.broadcast_to(expected, image.shape), rtol=2e-5)


@pytest.mark.parametrize("mis", ["power", "none"])
def test_bsdf_samples_and_mis_under_an_area_light_agree(mis):
    """Sampling an Oren-Nayar floor by its BSDF (MIS, BSDF samples on the diffuse floor) and by the light alone
    converge to the same image: their means within 1% (a fixed seed; the noise at 256 samples is ~0.2%)."""
    light = sphrect.RectLight(corner=(-0.5, 0.5, 1.0), edge_x=(1, 0, 0), edge_y=(0, -1, 0), radiance=(4, 4, 4))
    wo = unit((0, 1, 1))
    scene = sphrect.Scene(camera=ortho_camera(wo), meshes=[plane()], lights=[light],
                          materials=[sphrect.Material(kind="diffuse", base_color=BASE, diffuse_roughness=0.9)])
    means = []
    for kw in ({"mis": mis, "bsdf_samples_on_diffuse": True}, {"mis": "none"}):
        r = sphrect.Renderer(scene, techniques=["rectangle"], seed=5, **kw)
        assert r.render(256)
        means.append(r.image("rectangle")[..., 0].mean())
    assert means[0] == pytest.approx(means[1], rel=0.01) and means[1] > 0


def test_diffuse_roughness_must_be_finite():
    with pytest.raises(ValueError, match="diffuse_roughness must be finite"):
        render(sphrect.Material(kind="diffuse", diffuse_roughness=float("nan")), (0, 0, 1), (0, 0, 1))
