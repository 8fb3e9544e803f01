"""Material kind 'glass' (Cycles 3.4's Glass BSDF at zero bounces) through sphrect.Scene: a sun-lit plane seen
by a tilted orthographic camera has one exact radiance, colour x F(wo.n, ior) x GGX reflection (separable Smith
G, no micro-Fresnel) x E cos, compared with a NumPy transcription of Cycles' closure; a sharp glass is black
under the sun (Cycles' GGX returns 0 for alpha^2 <= 1e-7), its mirror and refracted rays see the world with Cycles'
Fresnel weights; the field round-trips through scene files, and version-3 files
(no ior, distribution) load with their defaults; Beckmann as Cycles' D and rational G1."""
import dataclasses
import json
import math

import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh
from test_materials_principled import E_SUN, TILT, fresnel_dielectric, plain, smith_g1, tilted_camera

SUNS = [(0.0, 1.2), (0.6, -0.4)]  # (x, y) of wi before normalising, z = 1: near the mirror direction, aside


def beckmann_g1(c, alpha):
    """Cycles' bsdf_beckmann_G1 (Walter et al.'s rational approximation)."""
    inv_a = alpha * math.sqrt(max(0.0, 1 - c * c) / (c * c))
    a = 1 / inv_a if inv_a >= 0.0625 else math.inf
    return (3.535 * a + 2.181 * a * a) / (1 + 2.276 * a + 2.577 * a * a) if a < 1.6 else 1.0


def cycles_microfacet_reflection(m, wo, wi):
    """Cycles 3.4's GGX / Beckmann reflection closure, colour x D G1(wo) G1(wi) / (4 cos cos), no Fresnel (the
    Glossy BSDF; the Glass BSDF's reflection adds the Fresnel of the view)."""
    h = (wo + wi) / np.linalg.norm(wo + wi)
    alpha = m.roughness ** 2
    if m.distribution == "beckmann":
        c2 = h[2] ** 2
        d = math.exp(-(1 - c2) / c2 / alpha ** 2) / (math.pi * alpha ** 2 * c2 * c2)
        g = beckmann_g1(wo[2], alpha) * beckmann_g1(wi[2], alpha)
    else:
        d = alpha ** 2 / (math.pi * (h[2] ** 2 * (alpha ** 2 - 1) + 1) ** 2)
        g = smith_g1(wo[2], alpha) * smith_g1(wi[2], alpha)
    return np.asarray(m.base_color) * d * g / (4 * wo[2] * wi[2])


def cycles_glass_reflection(m, wo, wi):
    return fresnel_dielectric(wo[2], m.ior) * cycles_microfacet_reflection(m, wo, wi)


def sunlit_plane(mat, wi):
    return sphrect.Scene(camera=tilted_camera(), meshes=[plane_mesh()], materials=[mat],
                         lights=[sphrect.SunLight(direction=tuple(-wi), irradiance=(E_SUN,) * 3)])


@pytest.mark.parametrize("distribution", sphrect.scene.GLASS_DISTRIBUTIONS)
@pytest.mark.parametrize("roughness, ior", [(0.2, 1.45), (0.5, 1.45), (0.35, 1.8), (0.8, 1.2)])
def test_sunlit_plane_has_cycles_glass_radiance(roughness, ior, distribution):
    mat = sphrect.Material(kind="glass", base_color=(0.9, 0.7, 0.5), roughness=roughness, ior=ior,
                           distribution=distribution)
    wo = np.array([0.0, -math.sin(TILT), math.cos(TILT)])
    for sun in SUNS:
        wi = np.array([sun[0], sun[1], 1.0])
        wi /= np.linalg.norm(wi)
        image = sphrect.render(sunlit_plane(mat, wi), samples=2)["rectangle"][..., :3]
        expected = cycles_glass_reflection(mat, wo, wi) * E_SUN * wi[2]
        np.testing.assert_allclose(image, np.broadcast_to(expected, image.shape), rtol=2e-4, atol=1e-9)
        # The comparison sees the IOR: 0.1 more changes the reference by far more than the tolerance.
        moved = cycles_glass_reflection(dataclasses.replace(mat, ior=ior + 0.1), wo, wi)
        assert np.max(np.abs(moved / cycles_glass_reflection(mat, wo, wi) - 1)) > 1e-2


def test_sharp_glass_is_black_at_zero_bounces():
    """Under a sharp sun, which no ray finds: a sharp glass's light samples see nothing of it (its mirror ray finds
    only emitters that can be hit, tests/blender/test_singular_parity.py)."""
    wi = np.array([0.0, math.sin(TILT), math.cos(TILT)])  # the mirror direction
    mat = sphrect.Material(kind="glass", base_color=(1.0, 1.0, 1.0), roughness=0.0, ior=1.45)
    assert sphrect.render(sunlit_plane(mat, wi), samples=2)["rectangle"][..., :3].max() == 0


def test_glass_fields_round_trip_and_version_3_files_load(tmp_path):
    mat = sphrect.Material(name="g", kind="glass", base_color=(0.9, 0.8, 0.7), roughness=0.3, ior=1.7,
                           distribution="beckmann")
    path = str(tmp_path / "v4.sphrect.npz")
    sphrect.save_scene(sphrect.Scene(materials=[mat]), path)
    assert [plain(m) for m in sphrect.load_scene(path).materials] == [plain(mat)]
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    meta = json.loads(bytes(arrays["scene.json"]).decode("utf-8"))
    meta["version"] = 3
    principled = sphrect.Material(name="p", kind="principled")
    meta["materials"] = [{k: v for k, v in plain(principled).items() if k not in ("ior", "distribution")}]
    arrays["scene.json"] = np.frombuffer(json.dumps(meta).encode("utf-8"), dtype=np.uint8)
    old = str(tmp_path / "v3.sphrect.npz")
    np.savez_compressed(old, **arrays)
    assert [plain(m) for m in sphrect.load_scene(old).materials] == [plain(principled)]


@pytest.mark.parametrize("ior", [1.45, 1.8])
def test_glass_seen_from_its_back_face_uses_the_inverse_ior(ior):
    # Cycles' glass closures take 1 / ior on a back face (SD_BACKFACING): the plane with its winding reversed
    # renders as the front face with 1 / ior (past the critical angle that is total reflection).
    mat = sphrect.Material(kind="glass", base_color=(0.9, 0.7, 0.5), roughness=0.3, ior=ior)
    wi = np.array([0.2, 0.5, 1.0]) / np.linalg.norm([0.2, 0.5, 1.0])
    back = sunlit_plane(mat, wi)
    back.meshes[0].triangles = back.meshes[0].triangles[:, ::-1].copy()
    inverse = sunlit_plane(dataclasses.replace(mat, ior=1 / ior), wi)
    front = sphrect.render(sunlit_plane(mat, wi), samples=2)["rectangle"][..., :3]
    image = sphrect.render(back, samples=2)["rectangle"][..., :3]
    np.testing.assert_allclose(image, sphrect.render(inverse, samples=2)["rectangle"][..., :3], rtol=1e-5, atol=1e-9)
    assert image.mean() > 1.2 * front.mean()  # seen from inside, the dielectric reflects more


BACKGROUND = (0.3, 0.5, 0.7)


def world_lit_plane(mat, floor=False):
    """The tilted camera's plane of `mat` under a constant world; floor: a black plane 1 below that stops the
    refracted rays."""
    meshes = [plane_mesh()]
    materials = [mat]
    if floor:
        meshes.append(dataclasses.replace(plane_mesh(z=-1.0), name="floor"))
        materials.append(sphrect.Material(name="black", base_color=(0.0, 0.0, 0.0)))
        meshes[1].material_ids = np.ones(2, np.int32)
    return sphrect.Scene(camera=tilted_camera(), meshes=meshes, materials=materials,
                         world=sphrect.World(background=BACKGROUND))


@pytest.mark.parametrize("ior", [1.45, 2.4])
def test_sharp_glass_mirror_ray_sees_the_world_with_cycles_fresnel(ior):
    """A singular lobe's mirror ray (Cycles 3.4 traces it at zero bounces, MIS skipped): the world's radiance x the
    glass colour x F(wo.n, ior) where the refracted ray ends on a black floor, and x (F + 1 - F) where it escapes
    too; a sharp Glossy BSDF reflects its colour whatever the angle.  One ray per camera sample: exact."""
    color = np.array([0.9, 0.7, 0.5])
    mat = sphrect.Material(name="g", kind="glass", base_color=tuple(color), roughness=0.0, ior=ior)
    f = fresnel_dielectric(math.cos(TILT), ior)
    reflected = sphrect.render(world_lit_plane(mat, floor=True), samples=2)["rectangle"][..., :3]
    np.testing.assert_allclose(reflected, np.broadcast_to(color * f * BACKGROUND, reflected.shape), rtol=1e-5)
    both = sphrect.render(world_lit_plane(mat), samples=2)["rectangle"][..., :3]
    np.testing.assert_allclose(both, np.broadcast_to(color * BACKGROUND, both.shape), rtol=1e-5)
    mirror = sphrect.Material(name="m", kind="glossy_bsdf", base_color=tuple(color), roughness=0.0)
    seen = sphrect.render(world_lit_plane(mirror, floor=True), samples=2)["rectangle"][..., :3]
    np.testing.assert_allclose(seen, np.broadcast_to(color * BACKGROUND, seen.shape), rtol=1e-5)
