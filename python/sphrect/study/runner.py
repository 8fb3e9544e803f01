"""Running one job (in a worker process): render, measure, compare with the reference, record.

:func:`run_job` is what executors call. It renders through a *render function* ``fn(context, job) ->
(image [H, W, 4], measurements dict)``: by default :func:`render_job` (our renderer or Cycles, by
``job.engine``); ``RunContext.render_hook`` ("module:function") substitutes another one, which is how the
tests drive the whole machinery with a fake renderer.
"""
from __future__ import annotations

import importlib
import math
import os
import time
import warnings
from dataclasses import dataclass, replace
from typing import Dict, Optional, Tuple

import numpy as np

from . import metrics
from .jobs import CYCLES, EQUAL_TIME, SPHRECT, Job
from .executors import in_study_pool
from .lock import hold_worker_lock
from .machines import machine_info, scale_times, slowdown
from .shared_files import local_path
from .store import ResultStore

REFERENCE_KIND = "reference"


@dataclass(frozen=True)
class RunContext:
    """What every job of a study shares (picklable: it travels to the worker processes)."""
    store_root: str
    scene_path: str                       # .sphrect.npz
    width: int
    height: int
    fingerprint: str                      # of the scene (+ reference for ladder/equal-time runs)
    reference_name: Optional[str] = None  # image name in the store; None while making the reference
    blend_path: Optional[str] = None      # for Cycles
    blender: Optional[str] = None
    blender_script: Optional[str] = None  # the add-on's headless entry point (cycles.find_blender_script)
    render_hook: Optional[str] = None     # "module:function" replacing render_job (tests)
    texture_files: Tuple[str, ...] = ()   # the image files the scene reads by path (scene_texture_files)

    def with_reference(self, name: str, fingerprint: str) -> "RunContext":
        return replace(self, reference_name=name, fingerprint=fingerprint)


# Per worker process, which may serve several studies in turn (a Dask worker): keyed by what identifies the content.
_scene_cache: Dict[Tuple, object] = {}
_reference_cache: Dict[Tuple[str, str, str], np.ndarray] = {}


def load_study_scene(scene_path: str, width: int, height: int):
    """The study's scene file at the study's resolution, as this worker reads it (cached per worker process, while the
    file stays the same): its copy of the file and of each image the scene reads by path (shared_files.py), a relative
    texture path resolved against the study's scene file's folder, as on the study's own machine."""
    path = local_path(scene_path)
    info = os.stat(path)
    key = (os.path.abspath(path), info.st_mtime_ns, info.st_size, width, height)
    if key not in _scene_cache:
        import sphrect
        scene = sphrect.load_scene(path, relative_to=os.path.dirname(os.path.abspath(scene_path)))
        for texture in scene.textures:
            texture.path = local_path(texture.path) if texture.path else texture.path
        scene.camera.width, scene.camera.height = int(width), int(height)
        _scene_cache.clear()
        _scene_cache[key] = scene
    return _scene_cache[key]


def render_sphrect(context: RunContext, job: Job) -> Tuple[np.ndarray, Dict]:
    """One render with our renderer. build_time: constructing the renderer (scene upload, BVH);
    call_time: the render() call measured here; cpu_time: the process's CPU time during it (with one render
    thread, the render's own compute time, insensitive to other load on the machine);
    wall_time/light_time/shading_time/camera_time/tile_time/trace_time/camera_trace_time/rays/surface_hits: the
    renderer's own
    stats (the cost model's terms, cost_model.py)."""
    import sphrect
    scene = load_study_scene(context.scene_path, context.width, context.height)
    t0 = time.perf_counter()
    renderer = sphrect.Renderer(scene, techniques=[job.technique], light_samples=job.light_samples,
                                pattern=job.pattern, mis=job.mis, light_selection=job.light_selection,
                                ellipse_technique=job.ellipse_technique, medium_sampling=job.medium_sampling,
                                ris_candidates=job.ris_candidates, seed=job.seed, threads=job.threads)
    if job.first_sample is not None:  # a range of a longer render (a reference chunk)
        renderer.start_at(job.first_sample, job.pass_index or 0)
    t1 = time.perf_counter()
    c1 = time.process_time()
    renderer.render(job.samples)
    c2 = time.process_time()
    t2 = time.perf_counter()
    image = renderer.image(job.technique)  # a fresh float32 array
    stats = renderer.stats(job.technique)  # every key is always present
    measured = {
        "build_time": t1 - t0,
        "call_time": t2 - t1,
        "wall_time": float(stats["wall_time"]),
        "cpu_time": c2 - c1,
        "light_time": float(stats["light_time"]),
        "shading_time": float(stats["shading_time"]),
        "rays": int(stats["rays"]),
        "samples_done": int(stats["samples"]),
        "camera_rays": int(stats["camera_rays"]),
        "camera_time": float(stats["camera_time"]),
        "tile_time": float(stats["tile_time"]),
        "trace_time": float(stats["trace_time"]),
        "camera_trace_time": float(stats["camera_trace_time"]),
        "surface_hits": int(stats["surface_hits"]),
        "dropped_samples": int(stats["dropped_samples"]),
    }
    return image, measured


def render_cycles_job(context: RunContext, job: Job) -> Tuple[np.ndarray, Dict]:
    from .cycles import render_cycles, worker_blender
    if not context.blend_path:
        raise ValueError("Cycles runs need the .blend scene")
    image, timing = render_cycles(local_path(context.blend_path), job.samples, context.width, context.height,
                                  seed=job.seed, threads=job.threads, blender=worker_blender(context.blender),
                                  blender_script=context.blender_script)
    measured = {"build_time": timing.get("build_time"), "call_time": timing.get("operator_time"),
                "wall_time": timing["wall_time"], "cpu_time": timing.get("cpu_time"), "light_time": None,
                "shading_time": None, "rays": None,
                "samples_done": timing.get("samples_done"), "timing_source": timing.get("timing_source"),
                "blender_version": timing.get("blender_version"),
                "cycles_sampling_pattern": timing.get("sampling_pattern")}
    return image, measured


def render_job(context: RunContext, job: Job) -> Tuple[np.ndarray, Dict]:
    if job.engine == SPHRECT:
        return render_sphrect(context, job)
    if job.engine == CYCLES:
        return render_cycles_job(context, job)
    raise ValueError(f"unknown engine {job.engine!r}")


def _render_function(context: RunContext):
    if not context.render_hook:
        return render_job
    module, _, name = context.render_hook.partition(":")
    return getattr(importlib.import_module(module), name)


def _reference(context: RunContext) -> np.ndarray:
    """The study's reference image (its fingerprint names the reference's id)."""
    key = (os.path.abspath(context.store_root), context.reference_name, context.fingerprint)
    if key not in _reference_cache:
        store = ResultStore(context.store_root)
        path = local_path(store.image_path(context.reference_name))
        image = store.load_image(context.reference_name) if path == store.image_path(context.reference_name) \
            else np.load(path, allow_pickle=False)  # a copy sent to this worker (shared_files.py)
        if image is None:
            raise RuntimeError(f"reference image {context.reference_name!r} is missing")
        _reference_cache.clear()
        _reference_cache[key] = image
    return _reference_cache[key]


def run_job(context: RunContext, job: Job) -> Tuple[Dict, Optional[np.ndarray]]:
    """Render `job` and measure it (in a worker); returns its record and, for reference chunks and equal-time runs,
    its image, which the study's own process stores (record_result): workers write nothing, so a worker on another
    machine, or one that dies, leaves the store as it was. The measured times are scaled by the worker's
    machines.slowdown(), and the record says where it ran (machines.machine_info) and every warning the render gave
    (a missing image, samples left out as not finite...), for the report."""
    if in_study_pool():  # a local pool's worker: claim the folder while this process lives (lock.py)
        hold_worker_lock(context.store_root)
    # This job's warnings: catch_warnings is the process's, and a study's worker runs one job at a time (a Dask worker
    # of several threads may mix those of the jobs it runs together).
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        image, measured = _render_function(context)(context, job)
    image = np.asarray(image, dtype=np.float32)
    if image.ndim != 3 or image.shape[0] != context.height or image.shape[1] != context.width:
        raise RuntimeError(f"{job.key}: rendered an image of shape {image.shape}, expected "
                           f"({context.height}, {context.width}, 4)")
    finite = bool(np.all(np.isfinite(image[..., :3])))
    record = {"key": job.key, "fingerprint": context.fingerprint, "job": job.to_dict(), "label": job.label,
              "finite": finite, **scale_times(measured, slowdown()), "machine": machine_info(),
              "warnings": list(dict.fromkeys(str(w.message) for w in caught))}
    kept = None
    if job.kind in (REFERENCE_KIND, EQUAL_TIME):
        record["image"] = job.key
        kept = image
    if job.kind != REFERENCE_KIND:
        reference = _reference(context)
        record["rmse"] = metrics.rmse(image, reference) if finite else math.inf
        record["relmse"] = metrics.relmse(image, reference) if finite else math.inf
        record["reference"] = context.reference_name
    return record, kept


def scene_texture_files(scene) -> Tuple[str, ...]:
    """The image files `scene` (as load_scene gives it: absolute texture paths) reads by path, those that are
    there: a missing one is magenta and warned on every worker alike."""
    return tuple(dict.fromkeys(t.path for t in scene.textures
                               if t.pixels is None and t.path and os.path.isfile(t.path)))


def record_result(store: ResultStore, record: Dict, image: Optional[np.ndarray]) -> None:
    """Stores a run_job result: its image first, then its record (each written atomically), so that a record is
    never there without its image."""
    if image is not None:
        store.save_image(record["image"], image)
    store.write_run(record)


def job_files(context: RunContext, jobs) -> list:
    """The files `jobs` read (Executor.run's `files`): the scene and the images it reads by path, the reference image
    once there is one, the .blend for Cycles jobs."""
    files = [context.scene_path, *context.texture_files]
    if context.reference_name:
        files.append(ResultStore(context.store_root).image_path(context.reference_name))
    if context.blend_path and any(job.engine == CYCLES for job in jobs):
        files.append(context.blend_path)
    return files
