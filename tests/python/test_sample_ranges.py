"""A render split into sample ranges (sphrect.sample_ranges), on this machine: ranges rendered by fresh renderers and
merged are bit-identical to one renderer rendering the same ranges, the film's alpha included; bad ranges and late
start_at calls are refused with clear errors; a worker without Blender fails its Cycles job, naming the worker."""
import os
import socket
import subprocess
import sys

import numpy as np
import pytest

import sphrect
from sphrect.distributed import render_range
from sphrect.sample_ranges import Accumulation, merge, sample_ranges
from sphrect.study.cycles import _check_worker_blender, worker_blender
from test_study_render import paper_like_scene


def test_sample_ranges_split_the_samples():
    assert [(r.first, r.samples, r.pass_index) for r in sample_ranges(10, 3)] == [(0, 4, 0), (4, 3, 1), (7, 3, 2)]
    assert sum(r.samples for r in sample_ranges(65536, 7)) == 65536
    for samples, parts in ((4, 5), (4, 0), (0, 1)):
        with pytest.raises(ValueError, match="parts"):
            sample_ranges(samples, parts)


@pytest.mark.parametrize("pattern", ["independent", "stratified", "latin", "sobol"])
def test_merged_ranges_are_the_render_of_the_same_ranges(pattern):
    scene = paper_like_scene(20, 12)
    scene.camera.film_transparent = True  # the ground does not fill the image: alpha varies
    options = dict(pattern=pattern, mis="power", light_samples=2, seed=11, threads=2)
    techniques = ["area", "rectangle"]
    parts = [render_range(scene, r, techniques, options)[0] for r in sample_ranges(9, 3)]
    merged = merge(parts)
    local = sphrect.render(scene, 9, techniques=techniques, parts=3, **options)
    assert np.array_equal(merged.counts, np.full((12, 20), 9))
    for t in techniques:
        assert np.array_equal(merged.image(t), local[t])
    alpha = local["rectangle"][..., 3]
    assert alpha.min() < 0.9 and alpha.max() == 1  # the film's alpha varies, and is merged too
    # One renderer's own buffers give its image.
    renderer = sphrect.Renderer(scene, techniques=techniques, **options)
    renderer.render(5)
    assert np.array_equal(renderer.accumulation().image("area"), renderer.image("area"))


def test_start_at_and_merge_refuse_what_cannot_be_a_range():
    scene = paper_like_scene(8, 6)
    renderer = sphrect.Renderer(scene, threads=1)
    with pytest.raises(ValueError, match="first_sample"):
        renderer.start_at(-1, 0)
    with pytest.raises(ValueError, match="pass_index"):
        renderer.start_at(0, 2 ** 32)
    with pytest.raises(ValueError, match="more than a render takes"):
        sphrect.Renderer(scene, light_samples=4, threads=1).start_at(2 ** 30, 0)
    renderer.render(1)
    with pytest.raises(RuntimeError, match="before it renders"):
        renderer.start_at(1, 1)
    small = renderer.accumulation()
    other = sphrect.Renderer(paper_like_scene(6, 6), threads=1)
    other.render(1)
    with pytest.raises(ValueError, match="cannot merge"):
        merge([small, other.accumulation()])
    with pytest.raises(ValueError, match="resolve_image needs"):
        sphrect._native.resolve_image(np.zeros((2, 2, 4)), np.zeros((2, 2), np.uint32), np.zeros((2, 2)), False)
    assert isinstance(small, Accumulation) and small.sums["rectangle"].dtype == np.float64


def test_a_worker_without_blender_fails_its_cycles_job_naming_it(monkeypatch):
    monkeypatch.delenv("BLENDER", raising=False)
    monkeypatch.setenv("PATH", "/nonexistent")
    _check_worker_blender.cache_clear()
    for _ in range(2):  # checked once, the same error for every Cycles job of the worker
        with pytest.raises(RuntimeError, match=f"Blender was not found on worker {socket.gethostname()}"):
            worker_blender(None)
    assert _check_worker_blender.cache_info().misses == 1
    _check_worker_blender.cache_clear()


def test_import_sphrect_does_not_load_dask():
    code = "import sys, sphrect; print(sorted({'dask', 'distributed'} & set(sys.modules)))"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60,
                            env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))
    assert result.returncode == 0 and result.stdout.strip() == "[]", result.stderr
