"""The comparative study: what accuracy costs in time.

For one scene, every light-sampling technique x MIS mode x sample pattern is rendered at a ladder of sample
counts (and, with Blender present, Cycles 3.4 at the same counts); each run's wall time, light-sampling time,
rays and RMSE / relative MSE against a converged reference are recorded, and a report with log-log plots,
fitted slopes, an equal-time image grid, a time-to-target-error table and the sampler's own accuracy/cost
table is written.

Command line: ``scripts/study.py scene.blend --out out/study`` (or ``python3 -m sphrect.study``).

Modules: jobs (the job list), executors (who runs it), runner (one job), store (crash-safe results),
reference (the reference and its error), metrics, cycles (Blender subprocesses), report, study (the phases),
preflight (checks of settings against each other and the machine), lock (one study per output folder), cli.
Behaviour under bad options, damaged files and a killed study: docs/study_reliability.md.
"""
__all__ = ["Executor", "LocalProcessPool", "SerialExecutor", "Job", "StudyConfig", "build_plan", "sample_ladder",
           "ReferenceSettings", "run_study"]

from .executors import Executor, LocalProcessPool, SerialExecutor  # noqa: F401
from .jobs import Job, StudyConfig, build_plan, sample_ladder  # noqa: F401
from .reference import ReferenceSettings  # noqa: F401
from .study import run_study  # noqa: F401
