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

# Where each public name lives, imported on first use: `sphrect.study.metrics` (the add-on's RMSE) must not pull in
# the executors' concurrent.futures.process, after which Debian's Blender 3.4.1 segfaults at exit.
_HOMES = {"Executor": "executors", "LocalProcessPool": "executors", "SerialExecutor": "executors", "Job": "jobs",
          "StudyConfig": "jobs", "build_plan": "jobs", "sample_ladder": "jobs", "ReferenceSettings": "reference",
          "run_study": "study"}


def __getattr__(name):
    if name not in _HOMES:
        raise AttributeError(f"module 'sphrect.study' has no attribute {name!r}")
    import importlib
    value = getattr(importlib.import_module(f".{_HOMES[name]}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(list(globals()) + __all__)
