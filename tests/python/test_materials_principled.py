"""Material kind 'principled' (Cycles 3.4's Principled BSDF) through sphrect.Scene: every input reaches the
renderer where it belongs (a sun-lit plane seen by a tilted orthographic camera has one exact radiance, the
BRDF at one (wo, wi) pair times E cos, compared with a NumPy transcription of Cycles 3.4's formulas), and scene
files: version-2 files (no 'principled' fields) load with the fields' defaults and render as before."""
import dataclasses
import math

import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh, save_as_older_version

E_SUN = 0.9
TILT = math.radians(50)  # the camera's view direction, from the plane's normal


def tilted_camera():
    """Orthographic camera rotated about x by TILT, looking at the plane z = 0 (wo = (0, -sin, cos))."""
    c, s = math.cos(TILT), math.sin(TILT)
    to_world = [[1, 0, 0, 0], [0, c, -s, -5 * s], [0, s, c, 5 * c], [0, 0, 0, 1]]
    return sphrect.Camera(width=4, height=4, type="orthographic", ortho_scale=0.5, to_world=to_world)


def schlick(c):
    return np.clip(1 - c, 0, 1) ** 5


def fresnel_dielectric(c, eta):
    c = abs(c)
    g2 = eta * eta - 1 + c * c
    if g2 <= 0:
        return 1.0
    g = math.sqrt(g2)
    a, b = (g - c) / (g + c), (c * (g + c) - 1) / (c * (g - c) + 1)
    return 0.5 * a * a * (1 + b * b)


def smith_g1(c, alpha):
    return 2 / (1 + math.sqrt(1 + alpha * alpha * (1 - c * c) / (c * c)))


def cycles_principled_brdf(m, wo, wi):
    """f(wo, wi) per channel, from Cycles 3.4's svm_node_closure_bsdf and closures (Burley in its 2012 Fd90
    form, which Cycles' split into Lambert + retro-reflection sums to)."""
    base = np.asarray(m.base_color, float)
    h = (wo + wi) / np.linalg.norm(wo + wi)
    ci, co, cih, ch = wi[2], wo[2], float(wi @ h), h[2]
    glass = m.transmission * (1 - m.metallic)  # Transmission's glass part: the reflection, the view's Fresnel
    dw = (1 - m.metallic) * (1 - m.transmission)
    fd90 = 0.5 + 2 * m.roughness * cih * cih
    f = base * dw * (1 + (fd90 - 1) * schlick(ci)) * (1 + (fd90 - 1) * schlick(co)) / math.pi
    lum709 = base @ [0.2126, 0.7152, 0.0722]
    f = f + m.sheen * dw * ((1 - m.sheen_tint) + base / lum709 * m.sheen_tint) * schlick(cih)
    alpha = max(m.roughness, 0.03) ** 2
    ior = 2 / (1 - math.sqrt(0.08 * m.specular)) - 1
    f0 = ((ior - 1) / (ior + 1)) ** 2
    tint = (1 - m.specular_tint) + base / (base @ [0.3, 0.6, 0.1]) * m.specular_tint
    cspec0 = np.clip(0.08 * m.specular * tint * (1 - m.metallic) + base * m.metallic, 0, 1)
    rise = (fresnel_dielectric(cih, ior) - f0) / (1 - f0)
    d = alpha ** 2 / (math.pi * (ch * ch * (alpha ** 2 - 1) + 1) ** 2)
    f = f + (1 - glass) * (cspec0 * (1 - rise) + rise) * d * smith_g1(co, alpha) * smith_g1(ci, alpha) / (4 * co * ci)
    if glass > 0:
        ag = m.roughness ** 2
        dg = ag ** 2 / (math.pi * (ch * ch * (ag ** 2 - 1) + 1) ** 2)
        f = f + glass * fresnel_dielectric(co, m.ior) * dg * smith_g1(co, ag) * smith_g1(ci, ag) / (4 * co * ci)
    a2 = max(m.clearcoat_roughness, 0.03) ** 4
    d_gtr1 = (a2 - 1) / (math.pi * math.log(a2) * (1 + (a2 - 1) * ch * ch))
    coat = 0.25 * m.clearcoat * fresnel_dielectric(cih, 1.5) * d_gtr1 * smith_g1(co, 0.25) * smith_g1(ci, 0.25)
    return f + coat / (4 * co * ci)


MATERIALS = {
    "diffuse rough": dict(roughness=1.0, specular=0.5),
    "tinted specular": dict(roughness=0.35, specular=0.8, specular_tint=0.7),
    "half metal": dict(roughness=0.5, metallic=0.5),
    "sheen": dict(roughness=0.6, sheen=1.0, sheen_tint=0.3),
    "clearcoat": dict(roughness=0.7, clearcoat=1.0, clearcoat_roughness=0.4),
    "transmission": dict(roughness=0.45, transmission=0.6, metallic=0.3, ior=1.6),
}


# Light directions (x, y of wi before normalising, z = 1): one nearly opposite the camera (grazing, where the
# sheen and the retro-reflection show), one to its side.
SUNS = [(0.0, 3.0), (0.6, -0.4)]


@pytest.mark.parametrize("name", sorted(MATERIALS))
def test_sunlit_plane_has_cycles_principled_radiance(name):
    mat = sphrect.Material(kind="principled", base_color=(0.7, 0.45, 0.2), **MATERIALS[name])
    wo = np.array([0.0, -math.sin(TILT), math.cos(TILT)])
    largest_change = {field: 0.0 for field in MATERIALS[name]}
    for sun in SUNS:
        wi = np.array([sun[0], sun[1], 1.0])
        wi /= np.linalg.norm(wi)
        scene = sphrect.Scene(camera=tilted_camera(), meshes=[plane_mesh()], materials=[mat],
                              lights=[sphrect.SunLight(direction=tuple(-wi), irradiance=(E_SUN,) * 3)])
        image = sphrect.render(scene, samples=2)["rectangle"][..., :3]
        brdf = cycles_principled_brdf(mat, wo, wi)
        np.testing.assert_allclose(image, np.broadcast_to(brdf * E_SUN * wi[2], image.shape), rtol=2e-4)
        for field in largest_change:
            value = getattr(mat, field)
            moved = dataclasses.replace(mat, **{field: value - 0.15 if value > 0.5 else value + 0.15})
            change = np.max(np.abs(cycles_principled_brdf(moved, wo, wi) / brdf - 1))
            largest_change[field] = max(largest_change[field], change)
    # The comparison sees each input: moving any of the case's inputs by 0.15 changes the reference by more
    # than 5x the tolerance in some channel and light.
    assert min(largest_change.values()) > 1e-3, largest_change


def plain(material):
    return {k: list(v) if isinstance(v, tuple) else v for k, v in dataclasses.asdict(material).items()}


def test_principled_fields_round_trip(tmp_path):
    mat = sphrect.Material(name="coat", kind="principled", base_color=(0.1, 0.2, 0.3), roughness=0.4, metallic=0.2,
                           specular=0.7, specular_tint=0.3, sheen=0.5, sheen_tint=0.9, clearcoat=0.8,
                           clearcoat_roughness=0.1)
    path = str(tmp_path / "s.sphrect.npz")
    sphrect.save_scene(sphrect.Scene(materials=[mat]), path)
    assert [plain(m) for m in sphrect.load_scene(path).materials] == [plain(mat)]


def test_version_2_files_load_with_defaults_and_render_unchanged(tmp_path):
    """A file written before format 3 (no 'principled' fields, kinds diffuse / glossy) loads with the new
    fields at their defaults, and renders exactly as the same scene built in memory."""
    glossy = sphrect.Material(name="g", kind="glossy", base_color=(0.6, 0.5, 0.4), roughness=0.3, specular=0.6)
    scene = sphrect.Scene(camera=tilted_camera(), meshes=[plane_mesh()], materials=[glossy],
                          lights=[sphrect.SunLight(direction=(0.2, 0.3, -1.0), irradiance=(1.0,) * 3)])
    path = str(tmp_path / "v3.sphrect.npz")
    sphrect.save_scene(scene, path)

    def drop_principled_fields(meta):
        for m in meta["materials"]:
            for key in ("specular_tint", "sheen", "sheen_tint", "clearcoat", "clearcoat_roughness", "ior",
                        "distribution"):
                del m[key]

    old = str(tmp_path / "v2.sphrect.npz")
    save_as_older_version(path, old, 2, drop_principled_fields)
    loaded = sphrect.load_scene(old)
    assert [plain(m) for m in loaded.materials] == [plain(glossy)]
    a = sphrect.render(loaded, samples=2)["rectangle"]
    b = sphrect.render(scene, samples=2)["rectangle"]
    np.testing.assert_array_equal(a, b)


def test_principled_inputs_are_validated():
    mat = sphrect.Material(kind="principled", sheen=float("nan"))
    with pytest.raises(Exception, match="finite"):
        sphrect.render(sphrect.Scene(materials=[mat], meshes=[plane_mesh()]), samples=1)


def test_principled_distribution_is_validated_and_multiscatter_brightens_a_rough_metal():
    scene = lambda **kw: sphrect.Scene(
        camera=tilted_camera(), meshes=[plane_mesh()],
        materials=[sphrect.Material(kind="principled", base_color=(0.9, 0.9, 0.9), metallic=1.0, roughness=0.9, **kw)],
        world=sphrect.World(background=(1.0, 1.0, 1.0)))
    with pytest.raises(ValueError, match="distribution 'beckmann' for kind 'principled'"):
        sphrect.render(scene(distribution="beckmann"), samples=1)
    # Under a white sky a rough white metal reflects most of it with multiple scattering, far less without
    # (tests/native/test_bsdf_lobes.cpp checks the walk's energy; Cycles' images: test_multiscatter_parity).
    multi = sphrect.render(scene(distribution="multiscatter_ggx"), samples=64)["rectangle"][..., :3].mean()
    single = sphrect.render(scene(), samples=64)["rectangle"][..., :3].mean()
    assert multi > 0.8 * 0.9 and single < 0.7 * multi
