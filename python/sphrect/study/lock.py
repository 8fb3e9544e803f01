"""One study at a time in an output folder, and none while worker processes of an earlier one still run.

Two lock files in the output folder, held with flock(2), which the kernel releases when the holder dies
however it dies (kill -9 included), so a lock is never stale:

* ``.study.lock`` -- held exclusively by the study's main process for the whole study; a second study of the same
  folder is refused at once (StudyBusy, naming the holder: the pid and command line written in the file).
* ``.workers.lock`` -- held shared by each worker process while it lives (runner.hold_worker_lock). Workers end
  with their parent (executors.py), but one may still be finishing when a study killed with -9 is restarted:
  the new study waits (up to `wait` seconds, saying so) until it can take this lock exclusively, i.e. until no
  worker of an earlier study is left to write into the folder alongside its own.

The lock files are not results: their content (the holder, for the message) is written in place.
"""
from __future__ import annotations

import fcntl
import os
import sys
import time

STUDY_LOCK = ".study.lock"
WORKERS_LOCK = ".workers.lock"
WORKER_EXIT_WAIT = 30.0  # seconds: a worker of a killed study ends within about a second (executors.py)


class StudyBusy(RuntimeError):
    """The output folder is in use by another live study (or its workers)."""


def _try_lock(fd: int, mode: int) -> bool:
    try:
        fcntl.flock(fd, mode | fcntl.LOCK_NB)
        return True
    except BlockingIOError:
        return False


class StudyLock:
    """``with StudyLock(out_dir):`` -- this process's claim on the output folder (see the module docstring)."""

    def __init__(self, out_dir: str, wait: float = WORKER_EXIT_WAIT):
        self.out_dir = os.path.abspath(out_dir)
        self.wait = wait
        self.fd = None

    def __enter__(self) -> "StudyLock":
        path = os.path.join(self.out_dir, STUDY_LOCK)
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        if not _try_lock(fd, fcntl.LOCK_EX):
            holder = os.pread(fd, 4096, 0).decode("utf-8", "replace").strip() or "a process"
            os.close(fd)
            raise StudyBusy(f"{self.out_dir} is in use by another study ({holder}): wait for it to end or stop it, "
                            f"or give another --out")
        try:
            self._wait_for_earlier_workers()
        except BaseException:
            os.close(fd)
            raise
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"pid {os.getpid()}: {' '.join(sys.argv)}\n".encode("utf-8", "replace"), 0)
        self.fd = fd
        return self

    def _wait_for_earlier_workers(self) -> None:
        path = os.path.join(self.out_dir, WORKERS_LOCK)
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            deadline = time.monotonic() + self.wait
            told = False
            while not _try_lock(fd, fcntl.LOCK_EX):
                if time.monotonic() > deadline:
                    raise StudyBusy(f"worker processes of an earlier study of {self.out_dir} are still running "
                                    f"(they hold {path}; `fuser -v {path}` lists them): stop them and run again")
                if not told:
                    sys.stderr.write(f"waiting for the worker processes of an earlier study of {self.out_dir} "
                                     f"to end (up to {self.wait:g} s) ...\n")
                    sys.stderr.flush()
                    told = True
                time.sleep(0.1)
            fcntl.flock(fd, fcntl.LOCK_UN)  # our own workers take it shared
        finally:
            os.close(fd)

    def __exit__(self, *exc) -> None:
        if self.fd is not None:
            os.ftruncate(self.fd, 0)
            os.close(self.fd)  # releases the lock (the file stays: removing a lock file races with its next taker)
            self.fd = None


_worker_locks = {}


def hold_worker_lock(out_dir: str) -> None:
    """In a worker process: hold the folder's workers lock shared until the process ends (once per folder)."""
    out_dir = os.path.abspath(out_dir)
    if out_dir not in _worker_locks:
        fd = os.open(os.path.join(out_dir, WORKERS_LOCK), os.O_RDWR | os.O_CREAT, 0o644)
        fcntl.flock(fd, fcntl.LOCK_SH)
        _worker_locks[out_dir] = fd
