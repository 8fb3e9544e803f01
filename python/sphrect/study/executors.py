"""Executors run a list of independent tasks and report each one as it finishes.

The interface is one method, :meth:`Executor.run`: it takes a picklable module-level function and the tasks,
and yields ``(task, result)`` or ``(task, exception)`` pairs in completion order. The study's job list
knows nothing of the executor, so a cluster or batch-queue executor can be added by implementing ``run``.

Timing policy (why the default pool renders each job with one thread): on a small machine, timing runs
that share cores perturb each other. Each job renders single-threaded and the pool runs one job per core,
so every job has a core of its own and all techniques (and Cycles, also held to one thread) are timed
under the same conditions. The time a run is judged by is then its CPU time (runner.py, cycles.py), which
does not grow when other processes compete for the cores (wall time does: on a shared 2-core machine it
varied several-fold between identical runs); wall times are recorded too. ``--threads 0`` gives each job
all cores and judges runs by wall time instead (then use ``--workers 1``).
"""
from __future__ import annotations

import concurrent.futures as cf
import ctypes
import multiprocessing
import os
import signal
import sys
import tempfile
import threading
import time
from abc import ABC, abstractmethod
from concurrent.futures.process import BrokenProcessPool
from typing import Any, Callable, Iterable, Iterator, Sequence, Tuple


class Executor(ABC):
    @abstractmethod
    def run(self, fn: Callable[[Any], Any], tasks: Iterable[Any], files: Sequence[str] = ()
            ) -> Iterator[Tuple[Any, Any]]:
        """Run fn(task) for every task; yield (task, result) or (task, exception) as each finishes. `files` are the
        paths the tasks read: an executor whose workers may not see them sends them (shared_files.py); those on
        this machine ignore them."""


class SerialExecutor(Executor):
    """Runs the tasks one after the other in this process (debugging; tests with monkeypatched runners)."""

    def run(self, fn, tasks, files=()):
        for task in tasks:
            try:
                result = fn(task)
            except KeyboardInterrupt:
                raise
            except Exception as e:  # reported to the caller, which records the failure and goes on
                result = e
            yield task, result


class WorkerCrashed(RuntimeError):
    """A worker process died (killed, out of memory, crashed in native code) while running the task."""


def _tracked(fn, marker_dir: str, index: int, task):
    """Runs fn(task) in a worker, leaving a marker file while it runs: after a worker dies, the markers left
    behind name the tasks that were running (the suspects)."""
    marker = os.path.join(marker_dir, str(index))
    open(marker, "w").close()
    try:
        return fn(task)
    finally:
        os.unlink(marker)


PR_SET_PDEATHSIG = 1  # linux/prctl.h
PARENT_POLL_SECONDS = 0.5


_in_study_pool = False


def in_study_pool() -> bool:
    """Whether this process is a LocalProcessPool worker (of a study running on this machine)."""
    return _in_study_pool


def _end_with_parent(parent: int) -> None:
    """Worker initializer: end this worker when the study's process (`parent`) dies, even by kill -9, which no
    cleanup code of the parent survives. On Linux the kernel sends SIGKILL (prctl PR_SET_PDEATHSIG), which also
    stops a render inside native code; everywhere a watchdog thread ends the process once it is orphaned (its
    parent pid changes). Checked once at once too, in case the parent died while this worker started."""
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent:
        os._exit(1)

    def watch():
        while os.getppid() == parent:
            time.sleep(PARENT_POLL_SECONDS)
        os._exit(1)

    threading.Thread(target=watch, name="sphrect-parent-watchdog", daemon=True).start()
    global _in_study_pool
    _in_study_pool = True


class LocalProcessPool(Executor):
    """A pool of worker processes on this machine (started with 'spawn': the parent may hold render threads,
    which must not be forked). If a worker dies (killed, crashed in native code), the tasks that were running
    are each retried alone in a fresh process, so the one that kills its worker is found and reported as
    failed (WorkerCrashed) while the others, and the rest of the list, finish normally."""

    def __init__(self, workers: int | None = None):
        self.workers = max(1, workers or os.cpu_count() or 1)

    def run(self, fn, tasks, files=()):
        pending = dict(enumerate(tasks))
        context = multiprocessing.get_context("spawn")
        with tempfile.TemporaryDirectory(prefix="sphrect-pool-") as marker_dir:
            unexplained = 0
            while pending:
                suspects = yield from self._run_pool(fn, pending, self.workers, context, marker_dir)
                if suspects is None:  # workers died before starting any task (e.g. cannot import): give up
                    unexplained += 1
                    if unexplained >= 3:
                        for index in list(pending):
                            yield pending.pop(index), WorkerCrashed("worker processes die before running jobs")
                    continue
                for index in suspects:  # alone, each in its own process
                    if index not in pending:
                        continue
                    crashed = yield from self._run_pool(fn, {index: pending[index]}, 1, context, marker_dir,
                                                        pending)
                    if crashed:
                        task = pending.pop(index)
                        yield task, WorkerCrashed("the worker process died while running this job")

    @staticmethod
    def _run_pool(fn, tasks, workers, context, marker_dir, pending=None):
        """Runs `tasks` ({index: task}) in one pool, yielding finished ones and removing them from `pending`
        (default: `tasks` itself). Returns the indices that were running when a worker died (empty if none)."""
        pending = tasks if pending is None else pending
        for name in os.listdir(marker_dir):
            os.unlink(os.path.join(marker_dir, name))
        pool = cf.ProcessPoolExecutor(max_workers=min(workers, len(tasks)), mp_context=context,
                                      initializer=_end_with_parent, initargs=(os.getpid(),))
        futures = {pool.submit(_tracked, fn, marker_dir, i, t): i for i, t in list(tasks.items())}
        broken = False
        try:
            for future in cf.as_completed(futures):
                index = futures[future]
                try:
                    result = future.result()
                except BrokenProcessPool:
                    broken = True
                    continue
                except Exception as e:
                    result = e
                task = pending.pop(index)
                yield task, result
        except BaseException:
            # Interrupted (Ctrl-C, or the consumer stopped): stop our workers, then let it propagate.
            pool.shutdown(wait=False, cancel_futures=True)
            for process in list((getattr(pool, "_processes", None) or {}).values()):
                if process.is_alive():
                    process.terminate()
            raise
        pool.shutdown(wait=True, cancel_futures=True)
        if not broken:
            return []
        suspects = sorted(int(name) for name in os.listdir(marker_dir) if name.isdigit())
        return suspects or None
