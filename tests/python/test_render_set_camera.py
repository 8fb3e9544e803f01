"""Renderer.set_camera: a new camera for the same scene (no new BVH or light tree) renders exactly what a new
Renderer of the scene with that camera renders, and refuses what it cannot take without changing anything."""
import dataclasses

import numpy as np
import pytest

import sphrect
from test_render_light_coverage import seen_lights_scene

TECHNIQUES = ["rectangle", "area"]


def moved_camera(camera, **changes):
    """The camera moved and turned a little, with `changes`."""
    c, s = np.cos(0.1), np.sin(0.1)
    to_world = [[c, 0, s, 0.3], [0, 1, 0, -0.2], [-s, 0, c, 0.5], [0, 0, 0, 1]]
    return dataclasses.replace(camera, to_world=to_world, **changes)


def images(r):
    return [r.image(t) for t in r.techniques]


@pytest.mark.parametrize("changes", [
    {},                                                            # the view only
    {"width": 40, "height": 30, "pixel_filter": "blackman_harris", "filter_width": 1.5},
    {"type": "orthographic", "width": 17, "height": 23},
    {"aperture_radius": 0.05, "focus_distance": 4.0},              # the depth-of-field kernel
])
def test_equals_a_new_renderer_of_the_scene_with_that_camera(changes):
    scene = seen_lights_scene()
    camera = moved_camera(scene.camera, **changes)
    r = sphrect.Renderer(scene, techniques=TECHNIQUES, seed=3, threads=2)
    assert r.render(4)
    r.set_camera(camera)
    assert r.resolution == (camera.width, camera.height)
    assert all(not np.any(image[..., :3]) for image in images(r))   # empty until rendered
    assert r.stats()["samples"] == 0
    for samples in (3, 2):
        assert r.render(samples)
    fresh = sphrect.Renderer(dataclasses.replace(scene, camera=camera), techniques=TECHNIQUES, seed=3, threads=2)
    for samples in (3, 2):
        assert fresh.render(samples)
    for a, b in zip(images(r), images(fresh)):
        assert np.array_equal(a, b)
    assert r.stats()["samples"] == fresh.stats()["samples"] == 5
    assert r.features == fresh.features
    assert ("dof" in r.features) == bool(camera.aperture_radius)


def test_back_to_the_first_camera_renders_the_first_image():
    scene = seen_lights_scene()
    r = sphrect.Renderer(scene, seed=1, threads=2)
    r.render(4)
    first = r.image()
    r.set_camera(moved_camera(scene.camera))
    r.render(4)
    assert not np.array_equal(r.image(), first)
    r.set_camera(scene.camera)
    r.render(4)
    assert np.array_equal(r.image(), first)


@pytest.mark.parametrize("bad, message", [
    ({"width": 0}, "width"),
    ({"to_world": np.zeros((4, 4)).tolist()}, "singular"),
    ({"pixel_filter": "mitchell"}, "pixel_filter"),
    ({"film_transparent": True}, "film_transparent"),
])
def test_refuses_a_camera_it_cannot_take_and_keeps_its_images(bad, message):
    scene = seen_lights_scene()
    r = sphrect.Renderer(scene, seed=1, threads=2)
    r.render(2)
    before = r.image()
    with pytest.raises(ValueError, match=message):
        r.set_camera(dataclasses.replace(scene.camera, **bad))
    assert np.array_equal(r.image(), before)
    r.render(2)   # still renders, from the camera it had
    fresh = sphrect.Renderer(scene, seed=1, threads=2)
    fresh.render(2)
    fresh.render(2)
    assert np.array_equal(r.image(), fresh.image())


def test_refuses_images_over_the_memory_limit():
    scene = seen_lights_scene()
    limit = sphrect.render_memory_bytes(1, 64, 64)
    r = sphrect.Renderer(scene, memory_limit=limit)
    with pytest.raises(ValueError, match="memory"):
        r.set_camera(dataclasses.replace(scene.camera, width=4096, height=4096))
    assert r.resolution == (scene.camera.width, scene.camera.height)


def test_not_while_rendering():
    scene = seen_lights_scene()
    r = sphrect.Renderer(scene, threads=1)
    errors = []

    def progress(done, total):
        if not errors:
            try:
                r.set_camera(moved_camera(scene.camera))
            except RuntimeError as e:
                errors.append(str(e))

    r.render(1, progress=progress)
    assert errors and "rendering" in errors[0]
    assert r.resolution == (scene.camera.width, scene.camera.height)
