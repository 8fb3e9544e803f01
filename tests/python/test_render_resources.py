"""The renderer's resources (issue 15): images that would not fit the memory limit are refused before anything
is allocated, with the figures; absurd thread counts are refused; cancel() before render() is not lost."""
import threading
import time

import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh, top_camera


def lit_scene(width=16, height=12):
    light = sphrect.RectLight(corner=(-0.4, -0.3, 0.6), edge_x=(0, 0.8, 0), edge_y=(0.8, 0, 0), radiance=(3, 3, 3))
    return sphrect.Scene(camera=top_camera(width=width, height=height), meshes=[plane_mesh()], lights=[light])


def test_the_memory_estimate_is_the_images():
    # Per technique 3 doubles + 4 floats per pixel, and a sample count per pixel.
    assert sphrect.render_memory_bytes(4, 1000, 500) == 500_000 * (4 * 40 + 4 + 8)
    assert 0 < sphrect.default_memory_limit() < 2 ** 50


def test_images_beyond_the_limit_are_refused_before_allocating():
    scene = lit_scene(64, 64)
    need = sphrect.render_memory_bytes(2, 64, 64)
    with pytest.raises(ValueError, match=r"64x64 image with 2 technique\(s\) needs .* GiB, more than the memory "
                                         r"limit"):
        sphrect.Renderer(scene, techniques=["rectangle", "area"], memory_limit=need - 1)
    r = sphrect.Renderer(scene, techniques=["rectangle", "area"], memory_limit=need)  # exactly enough
    assert r.render(1)


def test_a_huge_image_is_refused_at_once_by_default():
    """32768 x 32768 with four techniques needs 172 GiB: more than half of any machine this runs on, refused
    before the scene is built (a million-triangle mesh would not be looked at)."""
    scene = lit_scene(32768, 32768)
    scene.meshes = [sphrect.Mesh(vertices=np.random.default_rng(0).random((300_000, 3), np.float32),
                                 triangles=np.arange(300_000, dtype=np.int32).reshape(-1, 3) % 300_000)]
    assert sphrect.render_memory_bytes(4, 32768, 32768) > sphrect.default_memory_limit()
    start = time.process_time()
    with pytest.raises(ValueError, match="half the physical memory"):
        sphrect.Renderer(scene, techniques=["area", "triangles", "rectangle", "rectangle_cosine"])
    assert time.process_time() - start < 5  # (not a timing test: building the scene would take far longer)


@pytest.mark.parametrize("bad", [-1, sphrect.MAX_THREADS + 1, 100_000])
def test_thread_counts_beyond_the_cap_are_refused(bad):
    with pytest.raises(ValueError, match="threads"):
        sphrect.Renderer(lit_scene(), threads=bad)


def test_cancel_before_render_cancels_that_render_only():
    r = sphrect.Renderer(lit_scene(), threads=2)
    r.cancel()
    assert r.render(4) is False
    assert r.stats()["samples"] == 0
    assert r.render(4) is True and r.stats()["samples"] == 4  # the cancel was consumed
    r.cancel()
    r.cancel()  # two cancels before a render still stop one render
    assert r.render(2) is False and r.render(2) is True


def test_cancel_from_another_thread_stops_the_running_render():
    r = sphrect.Renderer(lit_scene(256, 256), threads=1, tile_size=8)
    started = threading.Event()
    progress = lambda done, total: started.set()
    t = threading.Thread(target=lambda: (started.wait(30), r.cancel()))
    t.start()
    assert r.render(4096, progress=progress) is False
    t.join()
    assert r.render(1) is True  # consumed by the render it stopped


def test_an_error_in_the_progress_callback_leaves_no_pending_cancel():
    r = sphrect.Renderer(lit_scene(64, 64), threads=1, tile_size=8)

    def boom(done, total):
        raise RuntimeError("callback failed")
    with pytest.raises(RuntimeError, match="callback failed"):
        r.render(1, progress=boom)
    assert r.render(1) is True
