"""A real Dask cluster for the tests: a `dask scheduler` and `dask worker` processes (Debian's python3-distributed)
on 127.0.0.1, each worker with its own environment, all ended (by their pids) when the test leaves the block."""
import contextlib
import json
import os
import signal
import subprocess
import sys
import time

import pytest

import sphrect

distributed = pytest.importorskip("distributed")

TESTS_DIR = os.path.dirname(os.path.abspath(__file__))
START_TIMEOUT = 60.0
# No dashboard, and the HTTP server each process still runs (health checks) on this machine only.
LOCAL_HTTP = ("--no-dashboard", "--dashboard-address", "127.0.0.1:0")


def _python_path() -> str:
    """The sphrect under test and these tests (the fake renderers), for the worker processes."""
    package_root = os.path.dirname(os.path.dirname(os.path.abspath(sphrect.__file__)))
    return os.pathsep.join([package_root, TESTS_DIR])


def _dask(*args) -> list:
    return [sys.executable, "-m", "distributed.cli.dask_" + args[0], *args[1:]]


def _end(process: subprocess.Popen) -> None:
    if process.poll() is None:
        os.killpg(process.pid, signal.SIGKILL)  # the worker's nanny and its worker process, nothing else
        process.wait(timeout=30)


def _scheduler_address(scheduler_file: str, scheduler: subprocess.Popen) -> str:
    """The address the scheduler writes into its file once it listens (read until it is whole)."""
    deadline = time.monotonic() + START_TIMEOUT
    while True:
        assert time.monotonic() < deadline and scheduler.poll() is None, "the scheduler did not start"
        try:
            with open(scheduler_file) as f:
                return json.load(f)["address"]
        except (OSError, ValueError, KeyError):
            time.sleep(0.1)


@contextlib.contextmanager
def dask_cluster(tmp_path, worker_envs=({}, {})):
    """Yields (scheduler address, client) of a scheduler and one worker per environment in `worker_envs` (each
    added to this process's), one thread each; waits until every worker has joined."""
    scheduler_file = str(tmp_path / "scheduler.json")
    env = dict(os.environ, PYTHONPATH=_python_path())
    processes = []
    client = None
    try:
        processes.append(subprocess.Popen(
            _dask("scheduler", "--host", "127.0.0.1", "--port", "0", *LOCAL_HTTP, "--scheduler-file", scheduler_file),
            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True))
        address = _scheduler_address(scheduler_file, processes[0])
        for i, extra in enumerate(worker_envs):
            processes.append(subprocess.Popen(
                _dask("worker", address, "--host", "127.0.0.1", "--nthreads", "1", "--nworkers", "1",
                      *LOCAL_HTTP, "--name", f"w{i}", "--local-directory", str(tmp_path / f"w{i}"),
                      "--death-timeout", "60"),
                env=dict(env, **extra), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                start_new_session=True))
        client = distributed.Client(address, timeout=START_TIMEOUT)
        client.wait_for_workers(len(worker_envs), timeout=START_TIMEOUT)
        yield address, client
    finally:
        if client is not None:
            client.close()
        for process in reversed(processes):
            _end(process)


def worker_pids(client) -> dict:
    """{worker address: pid of its worker process}."""
    return client.run(os.getpid)
