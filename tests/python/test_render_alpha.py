"""The film's alpha: Holdout surfaces (kind 'holdout', alone or in a mix) and a transparent film
(Camera.film_transparent).  Deterministic renders compared with exact values: no false failures."""
import dataclasses

import numpy as np

import sphrect
from render_testing import plane_mesh, top_camera

SUN = sphrect.SunLight(direction=(0.0, 0.0, -1.0), irradiance=(np.pi, np.pi, np.pi))  # radiance = albedo


def square(half, z, name):
    v = np.array([[-half, -half, z], [half, -half, z], [half, half, z], [-half, half, z]], np.float32)
    return sphrect.Mesh(vertices=v, triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32),
                        material_ids=np.array([1, 1], np.int32), name=name)


def scene_with_cover(cover, camera=None):
    """A ground of albedo 0.5 seen from above, its centre covered by a square of material `cover` above it."""
    return sphrect.Scene(camera=camera or top_camera(8, 8, half=1.0),
                         materials=[sphrect.Material(base_color=(0.5, 0.5, 0.5)), cover],
                         meshes=[plane_mesh(5.0), square(0.5, 0.5, "cover")], lights=[SUN])


def image(scene, spp=4):
    r = sphrect.Renderer(scene, techniques="rectangle", seed=1)
    r.render(spp)
    return r.image("rectangle")


def test_holdout_is_black_and_of_alpha_zero():
    img = image(scene_with_cover(sphrect.Material(kind="holdout")))
    inside, outside = img[2:6, 2:6], np.concatenate([img[:2].reshape(-1, 4), img[6:].reshape(-1, 4)])
    assert np.all(inside == 0)
    np.testing.assert_allclose(outside[:, 3], 1.0)
    np.testing.assert_allclose(outside[:, :3], 0.5, rtol=1e-5)


def test_holdout_in_a_mix_leaves_alpha_one_minus_its_weight():
    diffuse = sphrect.Material(base_color=(0.8, 0.8, 0.8))
    mix = sphrect.Material(kind="mix", layers=[sphrect.MaterialLayer(0.3, sphrect.Material(kind="holdout")),
                                               sphrect.MaterialLayer(0.7, diffuse)])
    inside = image(scene_with_cover(mix))[2:6, 2:6]
    np.testing.assert_allclose(inside[..., 3], 0.7, rtol=1e-6)
    np.testing.assert_allclose(inside[..., :3], 0.7 * 0.8, rtol=1e-5)


def test_transparent_film_shows_no_background_and_keeps_its_light():
    # A perspective camera above the small square only: around it the rays escape.
    cam = sphrect.Camera(width=12, height=12, lens=20.0,
                         to_world=[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 3], [0, 0, 0, 1]])
    scene = sphrect.Scene(camera=cam, materials=[sphrect.Material(base_color=(0.5, 0.5, 0.5))],
                          meshes=[dataclasses.replace(square(0.5, 0.0, "square"), material_ids=None)])
    scene.world.background = (0.2, 0.3, 0.4)  # lights the square too
    opaque = image(scene, spp=16)
    scene.camera.film_transparent = True
    transparent = image(scene, spp=16)
    escaped = opaque[..., 3] == 1  # every pixel is opaque without a transparent film
    assert escaped.all()
    background = np.all(np.isclose(opaque[..., :3], (0.2, 0.3, 0.4)), axis=-1)
    assert 0 < background.sum() < background.size
    assert np.all(transparent[background] == 0)
    square_pixels = transparent[..., 3] == 1
    np.testing.assert_array_equal(transparent[square_pixels], opaque[square_pixels])


def test_film_transparent_survives_the_scene_file(tmp_path):
    scene = scene_with_cover(sphrect.Material(kind="holdout"))
    scene.camera.film_transparent = True
    path = str(tmp_path / "s.sphrect.npz")
    sphrect.save_scene(scene, path)
    loaded = sphrect.load_scene(path)
    assert loaded.camera.film_transparent and loaded.materials[1].kind == "holdout"
