"""Command line of the study: ``python3 -m sphrect.study SCENE --out DIR [options]``."""
from __future__ import annotations

import argparse
import os
import sys
from typing import List, Optional

from .._native import MAX_IMAGE_SIDE
from ..render import ELLIPSE_TECHNIQUES, LIGHT_SELECTIONS, MEDIUM_SAMPLING, MIS_MODES, PATTERNS, TECHNIQUES
from .jobs import SettingError, StudyConfig, check_positive, sample_ladder
from .lock import StudyBusy
from .preflight import check_resolution, check_workers
from .reference import ReferenceSettings

# The options' defaults are the settings' own.
_STUDY = StudyConfig()
_REFERENCE = ReferenceSettings()


def _names(text: str) -> List[str]:
    return [t.strip() for t in text.split(",") if t.strip()]


def _resolution(text: str):
    try:
        w, h = (int(x) for x in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"resolution must look like 320x240, got {text!r}") from None
    if not (1 <= w <= MAX_IMAGE_SIDE and 1 <= h <= MAX_IMAGE_SIDE):
        raise argparse.ArgumentTypeError(f"resolution {w}x{h} out of range (each side 1..{MAX_IMAGE_SIDE})")
    return w, h


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="sphrect.study",
        description="Measure every light-sampling technique's error against render time on a scene (and Cycles "
                    "3.4's, when the scene is a .blend and Blender is installed), then write a report. Running "
                    "the same command again resumes an interrupted study.")
    p.add_argument("scene", help="a .blend (exported with Blender headless) or a .sphrect.npz scene file")
    p.add_argument("--out", required=True, help="output directory (results, images, plots, report.md/html)")
    p.add_argument("--techniques", type=_names, default=list(_STUDY.techniques),
                   help=f"comma list of {','.join(TECHNIQUES)}")
    p.add_argument("--mis", type=_names, default=list(_STUDY.mis), help=f"comma list of {','.join(MIS_MODES)}")
    p.add_argument("--patterns", type=_names, default=list(_STUDY.patterns),
                   help=f"comma list of {','.join(PATTERNS)}")
    p.add_argument("--light-selections", type=_names, default=list(_STUDY.light_selections),
                   help=f"comma list of {','.join(LIGHT_SELECTIONS)}: how each light sample chooses its light "
                        f"(default {','.join(_STUDY.light_selections)}, the renderer's; give several to compare them)")
    p.add_argument("--ellipse-techniques", type=_names, default=list(_STUDY.ellipse_techniques),
                   help=f"comma list of {','.join(ELLIPSE_TECHNIQUES)}: how disk and ellipse lights are sampled "
                        f"(default {','.join(_STUDY.ellipse_techniques)}, the renderer's; give several to compare "
                        f"them)")
    p.add_argument("--medium-samplings", type=_names, default=list(_STUDY.medium_samplings),
                   help=f"comma list of {','.join(MEDIUM_SAMPLING)}: how camera rays through a volume choose their "
                        f"scattering point (default {','.join(_STUDY.medium_samplings)}, the renderer's; give several "
                        f"to compare them)")
    p.add_argument("--max-samples", type=int, default=256, help="top of the ladder 1, 2, 4, ... (default 256)")
    p.add_argument("--min-samples", type=int, default=1)
    p.add_argument("--light-samples", type=int, default=_STUDY.light_samples, help="light samples per camera sample")
    p.add_argument("--ris-candidates", type=int, default=_STUDY.ris_candidates,
                   help=f"under light selection ris: the light tree's candidates per light sample, one kept "
                        f"(default {_STUDY.ris_candidates}, the renderer's)")
    p.add_argument("--resolution", type=_resolution, default=None,
                   help="WxH render resolution (default: the scene's); small keeps the study quick")
    p.add_argument("--seed", type=int, default=_STUDY.seed)
    p.add_argument("--workers", type=int, default=None,
                   help="parallel jobs on this machine (default: number of cores); with --executor dask-local, the "
                        "local cluster's worker processes")
    p.add_argument("--executor", choices=EXECUTORS, default=None,
                   help="local: a pool of processes on this machine (the default); dask-local: a local Dask cluster "
                        "(scheduler and --workers worker processes); dask: an existing Dask cluster (--scheduler)")
    p.add_argument("--scheduler", default=None,
                   help="run every job on the Dask cluster of this scheduler, e.g. tcp://HOST:8786 (implies "
                        "--executor dask); every worker needs the same sphrect build (and Blender for Cycles); the "
                        "scene and the reference are sent to the workers")
    p.add_argument("--threads", type=int, default=_STUDY.threads,
                   help="render threads per job (default 1: one job per core, comparable single-core timings)")
    p.add_argument("--reference-samples", type=int, default=None,
                   help="reference samples per pixel (default 64 x --max-samples)")
    p.add_argument("--reference-chunks", type=int, default=_REFERENCE.chunks,
                   help="independent renders averaged into the reference")
    p.add_argument("--reference-technique", default=_REFERENCE.technique)
    p.add_argument("--reference-mis", default=_REFERENCE.mis)
    p.add_argument("--reference-pattern", default=_REFERENCE.pattern)
    p.add_argument("--cycles", choices=["auto", "on", "off"], default="auto",
                   help="Cycles 3.4 as a peer (auto: when the scene is a .blend and Blender is found)")
    p.add_argument("--blender", default=None, help="Blender executable (default: $BLENDER or blender on PATH)")
    p.add_argument("--blender-script", default=None,
                   help="the Blender add-on's headless entry script, through which Blender exports the .blend and "
                        "renders it with Cycles (default: $SPHRECT_BLENDER_SCRIPT; scripts/study.py sets it)")
    p.add_argument("--equal-time", type=float, default=None,
                   help="seconds per equal-time image (default: rectangle's time for a quarter of the ladder's top "
                        "sample count)")
    p.add_argument("--grid-pattern", default=_STUDY.grid_pattern, help="pattern of the equal-time grid")
    p.add_argument("--grid-mis", type=_names, default=list(_STUDY.grid_mis),
                   help="MIS modes in the equal-time grid (those among --mis; none of them: the last of --mis)")
    p.add_argument("--target-rmse", type=float, default=None,
                   help="target of the time-to-error table (default: Cycles' RMSE at the top of the ladder)")
    p.add_argument("--no-sampler-table", action="store_true", help="skip the sampler accuracy/cost table")
    p.add_argument("--report-only", action="store_true", help="only (re)write the report from stored results")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    return p


EXECUTORS = ("local", "dask-local", "dask")


def make_executor(name: Optional[str], scheduler: Optional[str], workers: Optional[int]):
    """The executor the options choose (None: run_study's default, the local pool); SettingError when they
    contradict each other."""
    name = name or ("dask" if scheduler else "local")
    if (name == "dask") != bool(scheduler):
        raise SettingError("scheduler", "--executor dask needs --scheduler tcp://HOST:PORT, and --scheduler goes "
                                        "with --executor dask only")
    if name == "local":
        return None
    from .dask_executor import DaskExecutor
    return DaskExecutor(scheduler=scheduler, workers=None if scheduler else workers)


def _option(setting: str) -> str:
    """The option of a setting (the scene is the positional argument)."""
    return setting if setting == "scene" else "--" + setting.replace("_", "-")


def main(argv: Optional[List[str]] = None) -> int:
    """Every option, and the scene, is checked (alone and with the others) before anything is rendered: a bad one
    ends the study at once with exit status 2 and a line naming it."""
    args = parser().parse_args(argv)
    from .report import write_report
    try:
        if args.target_rmse is not None:
            check_positive("target_rmse", args.target_rmse)
        if os.path.exists(args.out) and not os.path.isdir(args.out):
            raise SettingError("out", f"{args.out} is a file, not a directory")
        if args.report_only:
            path = write_report(args.out, sampler_table=not args.no_sampler_table, target_rmse=args.target_rmse)
            print(path)
            return 0
        check_workers(args.workers)
        config = StudyConfig(techniques=tuple(args.techniques), mis=tuple(args.mis), patterns=tuple(args.patterns),
                             light_selections=tuple(args.light_selections),
                             ellipse_techniques=tuple(args.ellipse_techniques),
                             medium_samplings=tuple(args.medium_samplings),
                             ladder=tuple(sample_ladder(args.max_samples, args.min_samples)),
                             light_samples=args.light_samples, ris_candidates=args.ris_candidates, seed=args.seed,
                             threads=args.threads,
                             cycles=args.cycles != "off" and args.scene.endswith(".blend"),
                             grid_mis=tuple(args.grid_mis), grid_pattern=args.grid_pattern,
                             equal_time=args.equal_time)
        reference = ReferenceSettings(samples=64 * args.max_samples if args.reference_samples is None
                                      else args.reference_samples,
                                      chunks=args.reference_chunks, technique=args.reference_technique,
                                      mis=args.reference_mis, pattern=args.reference_pattern,
                                      light_samples=args.light_samples)
        if args.resolution:
            check_resolution(*args.resolution, workers=args.workers or os.cpu_count() or 1, chunks=reference.chunks)
        if not os.path.isfile(args.scene):
            raise SettingError("scene", f"{args.scene}: no such file")
        if not args.scene.endswith((".blend", ".npz")):
            raise SettingError("scene", f"{args.scene}: expected a .blend or a .sphrect.npz scene file")
        if args.cycles == "on":
            from .cycles import find_blender
            if not args.scene.endswith(".blend") or find_blender(args.blender) is None:
                raise SettingError("cycles", "--cycles on needs a .blend scene and Blender")
        from .study import ReferenceFailed, run_study
        executor = make_executor(args.executor, args.scheduler, args.workers)
        try:
            summary = run_study(args.scene, args.out, config, reference, workers=args.workers,
                                resolution=args.resolution, blender=args.blender, blender_script=args.blender_script,
                                progress=not args.quiet, report=False, executor=executor)
        except ReferenceFailed as e:  # nothing to measure against: no report
            print(f"error: {e}", file=sys.stderr)
            return 1
        finally:
            if executor is not None:
                executor.close()
        path = write_report(args.out, sampler_table=not args.no_sampler_table, target_rmse=args.target_rmse)
    except SettingError as e:  # named by its option (the settings' fields are the options' names)
        print(f"error: {_option(e.setting)}: {e}", file=sys.stderr)
        return 2
    except (ValueError, StudyBusy, OSError) as e:  # an unreadable scene, an output folder in use, no scheduler...
        print(f"error: {e}", file=sys.stderr)
        return 2
    print(f"report: {os.path.abspath(path)} (and report.html)")
    if summary["failures"]:
        print(f"{len(summary['failures'])} runs failed (see {os.path.join(args.out, 'failed')}); run the same "
              f"command again to retry them", file=sys.stderr)
        return 1
    return 0
