"""Anisotropic GGX (Material.anisotropic, anisotropic_rotation; kinds 'principled' and 'glossy_bsdf') along Cycles'
default tangent, radial about the object's Z axis from Mesh.generated.  The lobe itself is checked in
tests/native/test_bsdf_lobes.cpp (chi-square, normalisation, Cycles' roughness mapping) and against Cycles in
tests/blender/test_anisotropic_parity.py; here what the scene and the renderer make of it, with deterministic
identities (the same seeds: the same camera samples and light points)."""
import dataclasses

import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh, top_camera


def plane_with_generated():
    m = plane_mesh(1.0)
    # Blender's Generated coordinates of a plane: its bounding box mapped to [0, 1] (z constant).
    m.generated = np.concatenate([(m.vertices[:, :2] + 1.0) / 2.0, np.full((4, 1), 0.5)], axis=1).astype(np.float32)
    return m


def scene(material, mesh=None):
    light = sphrect.RectLight(corner=(-0.2, 0.6, 1.5), edge_x=(0.4, 0.0, 0.0), edge_y=(0.0, -1.2, 0.0),
                              radiance=(30.0,) * 3, visible=False)
    return sphrect.Scene(camera=top_camera(24, 24, half=1.0), materials=[material],
                         meshes=[mesh if mesh is not None else plane_with_generated()], lights=[light])


def render(s, samples=8):
    # Light samples alone (no MIS): the same light points evaluate the BSDF wherever its sampling would differ.
    r = sphrect.Renderer(s, techniques="rectangle", seed=5, mis="none")
    r.render(samples)
    return r.image("rectangle")[..., :3]


METAL = sphrect.Material(kind="principled", base_color=(0.9, 0.7, 0.4), metallic=1.0, roughness=0.3)
GLOSSY = sphrect.Material(kind="glossy_bsdf", base_color=(0.9, 0.9, 0.9), roughness=0.3)


@pytest.mark.parametrize("base", [METAL, GLOSSY], ids=["principled", "glossy_bsdf"])
def test_half_a_turn_changes_nothing_and_a_quarter_turn_does(base):
    aniso = dataclasses.replace(base, anisotropic=0.7)
    img = render(scene(aniso))
    half = render(scene(dataclasses.replace(aniso, anisotropic_rotation=0.5)))
    quarter = render(scene(dataclasses.replace(aniso, anisotropic_rotation=0.25)))
    isotropic = render(scene(base))
    np.testing.assert_allclose(half, img, rtol=1e-4, atol=1e-6)  # D is symmetric under a half turn
    assert np.abs(quarter - img).mean() > 0.05 * img.mean()
    assert np.abs(isotropic - img).mean() > 0.05 * img.mean()


def test_anisotropy_zero_is_the_isotropic_lobe_exactly():
    a = render(scene(dataclasses.replace(METAL, anisotropic=0.0, anisotropic_rotation=0.3)))
    b = render(scene(METAL))
    np.testing.assert_array_equal(a, b)


def test_a_mesh_without_generated_coordinates_is_warned():
    with pytest.warns(RuntimeWarning, match="anisotropic but the mesh has no generated coordinates"):
        sphrect.Renderer(scene(dataclasses.replace(METAL, anisotropic=0.5), mesh=plane_mesh(1.0)))


def test_anisotropy_round_trips_through_the_scene_file(tmp_path):
    s = scene(dataclasses.replace(GLOSSY, anisotropic=-0.4, anisotropic_rotation=0.2))
    path = tmp_path / "s.sphrect.npz"
    sphrect.save_scene(s, path)
    m = sphrect.load_scene(path).materials[0]
    assert (m.anisotropic, m.anisotropic_rotation) == pytest.approx((-0.4, 0.2))
    np.testing.assert_array_equal(render(sphrect.load_scene(path)), render(s))
