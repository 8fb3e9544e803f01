"""Where a run was measured, and how its time compares with runs measured elsewhere.

Each record carries its worker's machine (host name, CPU model, core count) and a *calibration*: the CPU seconds
a short fixed render takes on that worker (CALIBRATION_*, measured once per worker process and cached). Machines
differ in speed, so times measured on different kinds of machine are not comparable as they are; the report
(report/results.py) judges runs by their times as measured when every run comes from one kind of machine, and
otherwise by their times normalised by the calibration (see :func:`time_basis`), and says which.

SLOWDOWN_ENV (a factor, for tests and demonstrations): a worker whose environment sets it reports every time it
measures, the calibration included, multiplied by it -- a worker that many times slower, consistently.
"""
from __future__ import annotations

import functools
import os
import socket
import time
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence

import numpy as np

SLOWDOWN_ENV = "SPHRECT_STUDY_SLOWDOWN"
# The times a run's measurements carry (runner.py); all scale with the machine's speed.
TIME_FIELDS = ("build_time", "call_time", "wall_time", "cpu_time", "light_time", "shading_time", "camera_time")
# The calibration render: a ground lit by one rectangle, CALIBRATION_SIDE^2 pixels, one thread, the best of
# CALIBRATION_REPEATS (the least disturbed by other load).
CALIBRATION_SIDE = 64
CALIBRATION_SAMPLES = 16
CALIBRATION_REPEATS = 7
# What a record's "machine" says (machine_info), also runs.csv's columns.
MACHINE_FIELDS = ("host", "cpu_model", "cores", "calibration")
# Calibrations of one kind of machine agree within this factor (they vary a few % from run to run).
CALIBRATION_SPREAD = 1.3


def slowdown() -> float:
    """This worker's SLOWDOWN_ENV factor (1 when unset); ValueError when it is not a positive number."""
    text = os.environ.get(SLOWDOWN_ENV)
    if not text:
        return 1.0
    try:
        factor = float(text)
    except ValueError:
        factor = float("nan")
    if not (factor > 0 and np.isfinite(factor)):
        raise ValueError(f"{SLOWDOWN_ENV} must be a positive number, got {text!r}")
    return factor


def scale_times(measured: Dict, factor: float) -> Dict:
    """`measured` with its TIME_FIELDS multiplied by `factor` (those present and not None)."""
    return {k: (v * factor if k in TIME_FIELDS and v is not None else v) for k, v in measured.items()}


def calibration_scene():
    """The calibration's fixed scene."""
    import sphrect
    ground = sphrect.Mesh(vertices=np.array([[-4, -4, -4], [4, -4, -4], [4, 4, -4], [-4, 4, -4]], np.float32),
                          triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32))
    light = sphrect.RectLight(corner=(-1.0, -0.5, -2.0), edge_x=(2.0, 0.0, 0.0), edge_y=(0.0, 1.0, 0.0),
                              radiance=(5.0, 5.0, 5.0), two_sided=True, visible=False)
    return sphrect.Scene(camera=sphrect.Camera(width=CALIBRATION_SIDE, height=CALIBRATION_SIDE), meshes=[ground],
                         lights=[light])


@functools.lru_cache(maxsize=1)
def calibration_seconds() -> float:
    """CPU seconds of the calibration render on this worker (x its slowdown), measured once per process."""
    from ..render import Renderer
    scene, best = calibration_scene(), float("inf")
    for _ in range(CALIBRATION_REPEATS):
        renderer = Renderer(scene, techniques=["rectangle"], light_samples=1, pattern="stratified", threads=1)
        start = time.process_time()
        renderer.render(CALIBRATION_SAMPLES)
        best = min(best, time.process_time() - start)
    return best * slowdown()


def cpu_model() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    import platform
    return platform.processor() or platform.machine() or "unknown"


@functools.lru_cache(maxsize=1)
def machine_info() -> Dict:
    """Where this worker runs: host, cpu_model, cores, calibration (seconds; see the module docstring)."""
    values = (socket.gethostname(), cpu_model(), os.cpu_count() or 1, calibration_seconds())
    return dict(zip(MACHINE_FIELDS, values))


@dataclass(frozen=True)
class TimeBasis:
    """How runs' times are compared: as measured (`normalised` False), or each x reference_calibration / its own
    calibration, i.e. in seconds of a machine whose calibration is reference_calibration."""
    normalised: bool
    reference_calibration: Optional[float]
    description: str

    def time(self, record: Dict, measured: float) -> float:
        if not self.normalised:
            return measured
        return measured * self.reference_calibration / record["machine"]["calibration"]


def _kind(machine: Dict) -> tuple:
    return machine.get("cpu_model"), machine.get("cores")


def time_basis(records: Sequence[Dict]) -> TimeBasis:
    """Times as measured when every record was measured on one kind of machine (the same CPU model and core count,
    calibrations within CALIBRATION_SPREAD) or records carry no machine (measured before they did); otherwise times
    normalised by the calibration to the kind of machine that measured the most runs."""
    machines = [r["machine"] for r in records if r.get("machine") and r["machine"].get("calibration")]
    if not machines:
        return TimeBasis(False, None, "times as measured (the runs do not say on which machine)")
    calibrations = np.array([m["calibration"] for m in machines])
    kinds = {_kind(m) for m in machines}
    hosts = sorted({m.get("host", "?") for m in machines})
    if len(kinds) == 1 and calibrations.max() <= CALIBRATION_SPREAD * calibrations.min():
        (cpu, cores), = kinds
        return TimeBasis(False, None, f"times as measured, every run on one kind of machine ({cpu}, {cores} cores; "
                                      f"{len(hosts)} host{'s' if len(hosts) > 1 else ''})")
    # The reference: the calibration measuring the most runs (its median, should a kind's workers differ a little).
    groups: Dict[tuple, List[float]] = {}
    for m in machines:
        key = (_kind(m), round(float(np.log(m["calibration"]) / np.log(CALIBRATION_SPREAD))))
        groups.setdefault(key, []).append(m["calibration"])
    largest = max(groups.values(), key=len)
    reference = float(np.median(largest))
    return TimeBasis(True, reference,
                     f"times normalised by each worker's calibration (a fixed {CALIBRATION_SIDE}x{CALIBRATION_SIDE}, "
                     f"{CALIBRATION_SAMPLES}-spp render) to a machine calibrated at {reference:.4g} s: the runs "
                     f"come from {len(kinds)} kind(s) of machine, calibrations {calibrations.min():.4g} .. "
                     f"{calibrations.max():.4g} s")


def judged_times(records: Sequence[Dict], threads: int) -> TimeBasis:
    """Sets each record's "time" (metrics.time_of on the study's time basis); returns the basis."""
    from .metrics import time_of
    basis = time_basis(records)
    for r in records:
        r["time"] = basis.time(r, time_of(r, threads))
    return basis
