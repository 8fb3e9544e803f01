"""Running a whole study: scene -> reference -> sample ladder -> equal-time renders -> report.

    from sphrect.study import StudyConfig, run_study
    run_study("blend_scenes/01_paper.blend", "out/study", StudyConfig(cycles=True))

Every phase is a list of independent jobs handed to an executor; each finished job is recorded at once
(see store.py), so running the same command again resumes where an interrupted study stopped.
"""
from __future__ import annotations

import functools
import hashlib
import os
import sys
import time
from collections import Counter
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from . import metrics
from ..build import build_hash
from .executors import Executor, LocalProcessPool
from .jobs import (SPHRECT, CostKey, Job, SettingError, StudyConfig, build_plan, cost_key, equal_time_jobs,
                   fingerprint)
from .lock import WORKER_EXIT_WAIT, StudyLock
from .machines import judged_times
from .preflight import check_resolution, check_scene, check_workers, load_study_scene_file, one_line
from .progress import ProgressBar
from .reference import ReferenceSettings, combine_reference, load_reference_info, reference_jobs
from .runner import RunContext, job_files, record_result, run_job, scene_texture_files
from .store import ResultStore, atomic_write_json

SCENE_FILE = "scene.sphrect.npz"
CONFIG_FILE = "config.json"


def log(message: str) -> None:
    sys.stderr.write(message + "\n")
    sys.stderr.flush()


def scene_content_hash(path: str) -> str:
    """Hash of a scene file's content (its JSON and arrays), not of the zip bytes, which carry timestamps."""
    digest = hashlib.sha256()
    with np.load(path, allow_pickle=False) as data:
        for name in sorted(data.files):
            digest.update(name.encode())
            digest.update(np.ascontiguousarray(data[name]).tobytes())
    return digest.hexdigest()[:16]


def prepare_scene(input_path: str, out_dir: str, resolution: Optional[Tuple[int, int]] = None,
                  blender: Optional[str] = None, blender_script: Optional[str] = None
                  ) -> Tuple[str, Optional[str], str]:
    """(scene file, .blend or None, exporter warnings). A .blend is exported with Blender headless
    (at `resolution` if given; SettingError naming the scene when it cannot be); a .sphrect.npz is used as it is."""
    if not os.path.isfile(input_path):
        raise ValueError(f"{input_path}: no such file")
    if input_path.endswith(".blend"):
        from .cycles import BlenderFailed, export_blend
        scene_path = os.path.join(out_dir, SCENE_FILE)
        log(f"exporting {input_path} with Blender ...")
        try:
            warnings = export_blend(input_path, scene_path, resolution=resolution, blender=blender,
                                    blender_script=blender_script)
        except RuntimeError as e:  # a .blend Blender cannot open (truncated), no Blender, no add-on script
            reason = e.reason if isinstance(e, BlenderFailed) else one_line(e)
            raise SettingError("scene", f"{input_path}: Blender could not export it: {reason}") from None
        return scene_path, os.path.abspath(input_path), warnings
    if input_path.endswith(".npz"):
        return os.path.abspath(input_path), None, ""
    raise ValueError(f"{input_path}: expected a .blend or a .sphrect.npz scene file")


def _run_phase(executor: Executor, context: RunContext, store: ResultStore, phase_jobs: Sequence[Job], label: str,
               show_progress: bool) -> Tuple[List[Dict], List[Tuple[Job, str]]]:
    """Run the jobs of one phase that have no current record; returns (records of all jobs, failures)."""
    todo = [j for j in phase_jobs if not store.is_done(j.key, context.fingerprint)]
    done = len(phase_jobs) - len(todo)
    failures, warned = [], Counter()  # warning -> runs that gave it
    if todo:
        if done:
            log(f"{label}: {done} of {len(phase_jobs)} runs already measured, {len(todo)} to go")
        with ProgressBar(len(todo), label, enabled=show_progress) as bar:
            for job, result in executor.run(functools.partial(run_job, context), todo, job_files(context, todo)):
                if isinstance(result, BaseException):
                    message = f"{type(result).__name__}: {result}"
                    store.write_failure(job.key, message)
                    failures.append((job, message))
                    bar.update(1, note=f"FAILED {job.key}")
                else:
                    record_result(store, *result)
                    warned.update(result[0].get("warnings", ()))
                    rmse = result[0].get("rmse")
                    bar.update(1, note=f"{job.label} n={job.samples}" + (f" rmse={rmse:.3g}" if rmse else ""))
    store.remove_stale_temporaries()  # no worker is writing now; a killed one may have left its temporary
    for job, message in failures:
        log(f"  failed: {job.key}: {message.splitlines()[0] if message else ''}")
    for message, runs in warned.items():  # also in the report
        log(f"  warning ({label}, {runs} run{'s' if runs > 1 else ''}): {message}")
    records = [r for r in (store.read_run(j.key) for j in phase_jobs)
               if r is not None and r.get("fingerprint") == context.fingerprint]
    return records, failures


def seconds_per_sample(records: List[Dict], threads: int) -> Dict[CostKey, float]:
    """jobs.cost_key (engine, technique, mis, light selection, ellipse technique, medium sampling) -> seconds per
    sample per pixel: each configuration's metrics.cost_per_sample over its ladder (on the study's time basis),
    median over patterns."""
    judged_times(records, threads)
    ladders: Dict[Tuple[CostKey, str], List[Dict]] = {}
    for r in records:
        ladders.setdefault((cost_key(r["job"]), r["job"]["pattern"]), []).append(r)
    costs: Dict[CostKey, List[float]] = {}
    for (key, _), runs in ladders.items():
        runs.sort(key=lambda r: r["job"]["samples"])
        cost, _ = metrics.cost_per_sample([r["time"] for r in runs], [r["job"]["samples"] for r in runs])
        costs.setdefault(key, []).append(cost)
    return {k: float(np.median(v)) for k, v in costs.items()}


def equal_time_budget(records: List[Dict], config: StudyConfig) -> float:
    """Default equal-time budget: the time our `rectangle` technique (or the first technique) takes, with the
    last grid MIS mode, the first light selection, ellipse technique and medium sampling, for a quarter of the ladder's
    top sample count. When that configuration has no measured run (its runs failed), the first of ours that has
    one stands in; RuntimeError when the ladder measured none."""
    technique = "rectangle" if "rectangle" in config.techniques else config.techniques[0]
    costs = seconds_per_sample(records, config.threads)
    preferred = [(SPHRECT, technique, config.grid_mis[-1], config.light_selections[0],
                  config.ellipse_techniques[0], config.medium_samplings[0])]
    measured = [key for key in preferred + sorted(costs) if key[0] == SPHRECT and costs.get(key, 0) > 0
                and np.isfinite(costs[key])]
    if not measured:
        raise RuntimeError("no ladder run measured: cannot choose the equal-time budget")
    return costs[measured[0]] * max(config.ladder[-1] // 4, 1)


STATE_FILE = "state.json"


class ReferenceFailed(RuntimeError):
    """Reference chunks failed: the study cannot measure any error without its reference."""


def _write_state(out_dir: str, **values) -> None:
    """study state the report needs (the current runs' fingerprint, the equal-time budget)."""
    state = ResultStore(out_dir).read_json(STATE_FILE) or {}  # a damaged one is set aside and rewritten
    state.update(values)
    atomic_write_json(os.path.join(out_dir, STATE_FILE), state)


def run_study(input_path: str, out_dir: str, config: Optional[StudyConfig] = None,
              reference: Optional[ReferenceSettings] = None, workers: Optional[int] = None,
              resolution: Optional[Tuple[int, int]] = None, blender: Optional[str] = None,
              executor: Optional[Executor] = None, render_hook: Optional[str] = None, progress: bool = True,
              report: bool = True, sampler_table: bool = True, blender_script: Optional[str] = None,
              lock_wait: float = WORKER_EXIT_WAIT) -> Dict:
    """Run (or resume) the study of `input_path` (.blend or .sphrect.npz) into `out_dir`; returns a summary
    dict (paths, counts, failures). See the package docstring for the phases. Settings are checked before
    anything renders (SettingError); StudyBusy when another study holds `out_dir` or workers of an earlier one
    still run after `lock_wait` seconds (lock.py)."""
    config = config or StudyConfig()
    reference = reference or ReferenceSettings(samples=64 * max(config.ladder), light_samples=config.light_samples)
    if not os.path.isfile(input_path):
        raise ValueError(f"{input_path}: no such file")
    if resolution is not None:
        # before a .blend's export; again below with the executor's own count
        check_resolution(*resolution, workers=getattr(executor, "workers", None) or check_workers(workers)
                         or os.cpu_count() or 1, chunks=reference.chunks)
    executor = executor or LocalProcessPool(check_workers(workers))
    os.makedirs(out_dir, exist_ok=True)
    with StudyLock(out_dir, wait=lock_wait):
        return _run_locked(input_path, out_dir, config, reference, executor, resolution, blender, blender_script,
                           render_hook, progress, report, sampler_table)


def _run_locked(input_path, out_dir, config, reference, executor, resolution, blender, blender_script, render_hook,
                progress, report, sampler_table) -> Dict:
    """run_study's phases, in a folder this study holds (lock.py)."""
    started = time.time()

    if config.cycles:
        from .cycles import find_blender
        if not input_path.endswith(".blend"):
            log("Cycles needs the .blend scene: Cycles runs skipped")
            config.cycles = False
        elif find_blender(blender) is None:
            log("Blender not found: Cycles runs skipped")
            config.cycles = False

    scene_path, blend_path, warnings = prepare_scene(input_path, out_dir, resolution, blender, blender_script)
    if warnings:
        log(f"exporter warnings: {warnings}")
    # The scene checked once, before any job (every job would fail on a scene that cannot be built).
    scene = load_study_scene_file(scene_path)
    width, height = resolution or (scene.camera.width, scene.camera.height)
    check_resolution(width, height, workers=getattr(executor, "workers", None) or 1, chunks=reference.chunks,
                     setting="resolution")  # the scene's own, when not given
    scene.camera.width, scene.camera.height = width, height
    scene_warnings = [] if render_hook else check_scene(scene, input_path)  # a hook renders instead (tests' fakes)
    for message in scene_warnings:
        log(f"scene warning: {message}")
    store = ResultStore(out_dir)
    # Runs are redone when the scene, the resolution or the renderer's build changes.
    scene_fp = fingerprint(scene=scene_content_hash(scene_path), width=width, height=height,
                           renderer=build_hash())
    # The input as the report shows it: relative to the directory the study runs from, so that a report
    # names no path of the machine that wrote it.
    atomic_write_json(os.path.join(out_dir, CONFIG_FILE), {
        "input": os.path.relpath(input_path), "scene_file": scene_path, "blend": blend_path, "width": width,
        "height": height, "study": config.to_dict(), "reference": reference.__dict__, "exporter_warnings": warnings,
        "scene_warnings": scene_warnings, "workers": getattr(executor, "workers", None),
        "executor": type(executor).__name__})
    context = RunContext(store_root=store.root, scene_path=scene_path, width=width, height=height,
                         fingerprint=scene_fp, blend_path=blend_path, blender=blender,
                         blender_script=blender_script, render_hook=render_hook,
                         texture_files=scene_texture_files(scene))
    log(f"study of {input_path}: {width}x{height}, {len(config.techniques)} techniques x {len(config.mis)} MIS x "
        f"{len(config.patterns)} patterns x {len(config.light_selections)} light selections x "
        f"{len(config.ellipse_techniques)} ellipse techniques x {len(config.medium_samplings)} medium samplings x "
        f"ladder "
        f"{list(config.ladder)}" + (" + Cycles" if config.cycles else ""))

    dashboard = getattr(executor, "dashboard_link", None)
    if dashboard:
        log(f"Dask dashboard: {dashboard}")

    # 1. The reference (independent chunks, combined; see reference.py).
    chunk_jobs = reference_jobs(reference, threads=config.threads)
    _, failures = _run_phase(executor, context, store, chunk_jobs, "reference", progress)
    if failures:
        raise ReferenceFailed(f"{len(failures)} reference chunks failed (see {os.path.join(out_dir, 'failed')}); "
                              f"first: {one_line(failures[0][1])}")
    info = load_reference_info(store)
    expected_keys = [j.key for j in chunk_jobs]
    if info is None or info.get("chunk_keys") != expected_keys or info.get("scene_fingerprint") != scene_fp \
            or not store.image_is_whole(info["image"]):
        info = combine_reference(store, reference, chunk_jobs, scene_fp)
    log(f"reference: {reference.samples} spp ({reference.technique}, mis={reference.mis}, {reference.pattern}), "
        f"estimated RMSE {info['estimated_rmse']:.4g}")
    context = context.with_reference(info["image"], fingerprint(scene=scene_fp, reference=info["id"]))
    _write_state(out_dir, run_fingerprint=context.fingerprint, reference_id=info["id"])

    # 2. The sample ladder.
    ladder_records, ladder_failures = _run_phase(executor, context, store, build_plan(config), "ladder", progress)

    # 3. Equal time (none when every ladder run failed: the report then shows the failures).
    try:
        budget = config.equal_time or equal_time_budget(ladder_records, config)
    except RuntimeError as e:
        log(f"{e}: equal-time renders skipped")
        budget = None
    et_jobs = equal_time_jobs(config, budget, seconds_per_sample(ladder_records, config.threads)) if budget else []
    et_records, et_failures = _run_phase(executor, context, store, et_jobs,
                                         f"equal time ({budget or 0:.3g} s)", progress)

    _write_state(out_dir, equal_time_budget=budget)
    summary = {"out_dir": os.path.abspath(out_dir), "reference": info, "ladder_runs": len(ladder_records),
               "equal_time_runs": len(et_records), "equal_time_budget": budget,
               "failures": [(j.key, m) for j, m in ladder_failures + et_failures],
               "elapsed": time.time() - started}
    if report:
        from .report import write_report
        summary["report"] = write_report(out_dir, sampler_table=sampler_table)
    return summary
