"""The study on a Dask cluster (Debian's python3-distributed): an existing one (``--scheduler tcp://HOST:8786``), or
a local one of worker processes on this machine (``--executor dask-local --workers N``) to try it out.

Jobs go to workers as they free up and come back as they finish; the study's own process writes each record
(runner.record_result), so an interrupted study resumes as with the local pool. The files jobs read (the scene, the
reference image, the .blend) are sent to each worker once per phase (StudyFiles, shared_files.py): workers need not
see the study's folder. A worker that dies (killed, out of memory, its machine lost) has its jobs run again on other
workers by the scheduler; a job that has been on ALLOWED_FAILURES + 1 workers that died, KILLED_WORKER_ROUNDS times
over, is reported as failed (WorkerCrashed), as the local pool reports one that kills its worker, and the study goes
on. A worker whose sphrect is another build than this process's refuses every job (build.BuildMismatch), so results
never mix builds. With no worker for NO_WORKERS_TIMEOUT seconds the jobs left fail.

Timing on a cluster: each job still renders with the study's --threads (1), but a worker of the cluster may share
its machine with others, and machines differ: records carry their machine and calibration (machines.py) and the
report compares times on one kind of machine or normalises them.
"""
from __future__ import annotations

import os
import time
from typing import Dict, Optional

from ..build import build_hash, check_same_build
from .executors import Executor, WorkerCrashed
from .shared_files import read_files, use_copies

# Worker deaths a job may be present at before the scheduler fails it (KilledWorker): the local cluster's setting; an
# existing cluster's scheduler has its own, distributed.scheduler.allowed-failures, whose default is also 3.
ALLOWED_FAILURES = 3
# A job failed so is submitted again until it has been this many times in all before it is reported (WorkerCrashed):
# the scheduler counts every job a dying worker holds, also one queued behind the job that killed it. The local
# cluster gives a worker one job per thread (worker-saturation 1), so there only the culprit is counted.
KILLED_WORKER_ROUNDS = 2
NO_WORKERS_TIMEOUT = 120.0  # seconds without a worker before the jobs left are failed
POLL_SECONDS = 1.0
CONNECT_TIMEOUT = 30.0
SHARED_FILES_DIR = "sphrect-study-files"
DASHBOARD_ADDRESS = "127.0.0.1:8787"  # the local cluster binds to this machine only


def _run_checked(fn, client_build: str, task):
    """On a worker: refuse a job when this worker runs another build; else run it."""
    check_same_build(client_build)
    return fn(task)


class StudyFiles:
    """A Dask worker plugin giving every worker of the cluster, those that join or restart later included, its copy
    of the study's files (shared_files.py) in its own directory. A plugin rather than scattered data: data held only
    by workers is lost when they die, the plugin is the scheduler's."""
    name = "sphrect-study-files"

    def __init__(self, files: Dict[str, bytes]):
        self.files = files

    def setup(self, worker) -> None:
        use_copies(self.files, os.path.join(worker.local_directory, SHARED_FILES_DIR))


def _import_distributed():
    try:
        import distributed
    except ImportError:
        raise RuntimeError("the Dask executor needs Dask distributed: install python3-distributed and python3-dask "
                           "(Debian) or the 'distributed' package") from None
    return distributed


def dashboard_available() -> bool:
    """Whether the Dask dashboard can be served: it needs bokeh, which Debian 12 does not package (docs/study.md)."""
    try:
        import bokeh  # noqa: F401
        return True
    except ImportError:
        return False


class DaskExecutor(Executor):
    """Runs the study's jobs on a Dask cluster: `scheduler` ("tcp://HOST:8786") names an existing one; without it,
    a local cluster of `workers` worker processes (default: one per core), one thread each, is started on
    127.0.0.1 and closed with the executor. Use as a context manager, or call close()."""

    def __init__(self, scheduler: Optional[str] = None, workers: Optional[int] = None):
        distributed = _import_distributed()
        self.cluster = None
        if scheduler:
            self.client = distributed.Client(scheduler, timeout=CONNECT_TIMEOUT)
        else:
            import dask
            with dask.config.set({"distributed.scheduler.allowed-failures": ALLOWED_FAILURES,
                                  "distributed.scheduler.worker-saturation": 1.0}):
                self.cluster = distributed.LocalCluster(
                    n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True, host="127.0.0.1",
                    dashboard_address=DASHBOARD_ADDRESS if dashboard_available() else "127.0.0.1:0",
                    worker_dashboard_address="127.0.0.1:0")
            self.client = distributed.Client(self.cluster)

    @property
    def workers(self) -> int:
        """The cluster's workers now (at least 1: jobs wait for workers that have not joined yet)."""
        return max(1, len(self.client.scheduler_info().get("workers", {})))

    @property
    def dashboard_link(self) -> Optional[str]:
        return self.client.dashboard_link if dashboard_available() else None

    def run(self, fn, tasks, files=()):
        distributed = _import_distributed()
        tasks = list(tasks)
        futures, rounds = {}, {}  # future -> task index; task index -> times submitted
        if files:  # to every worker once, not with every job
            self.client.register_worker_plugin(StudyFiles(read_files(files)), name=StudyFiles.name)

        def submit(index):
            rounds[index] = rounds.get(index, 0) + 1
            future = self.client.submit(_run_checked, fn, build_hash(), tasks[index], pure=False)
            futures[future] = index
            return future

        pending, no_workers_since = {submit(i) for i in range(len(tasks))}, None
        try:
            while pending:
                try:
                    done, pending = distributed.wait(pending, timeout=POLL_SECONDS, return_when="FIRST_COMPLETED")
                except TimeoutError:  # (distributed's, the builtin)
                    done = set()
                for future in done:
                    index = futures.pop(future)
                    try:
                        result = future.result()
                    except distributed.KilledWorker:
                        if rounds[index] < KILLED_WORKER_ROUNDS:  # perhaps only queued behind the culprit: again
                            pending.add(submit(index))
                            continue
                        result = WorkerCrashed("every worker that ran this job died while running it")
                    except Exception as e:  # the job's own error (or a build mismatch), reported for the job
                        result = e
                    yield tasks[index], result
                if done or self.client.scheduler_info().get("workers"):
                    no_workers_since = None
                elif no_workers_since is None:
                    no_workers_since = time.monotonic()
                elif time.monotonic() - no_workers_since > NO_WORKERS_TIMEOUT:
                    for future in pending:
                        yield tasks[futures[future]], WorkerCrashed(
                            f"no worker on the cluster for {NO_WORKERS_TIMEOUT:g} s")
                    pending = set()
        finally:  # interrupted, or the consumer stopped: the jobs left are not run
            if pending:
                self.client.cancel(list(pending))

    def close(self) -> None:
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()

    def __enter__(self) -> "DaskExecutor":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
