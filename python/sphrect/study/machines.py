"""Where a run was measured, and how its time compares with runs measured elsewhere.

Each record carries its worker's machine (host name, CPU model, core count) and a *calibration*: the CPU seconds
a short fixed render takes on that worker (CALIBRATION_*, measured once per worker process and cached). Machines
differ in speed, so times measured on different kinds of machine (CPU model and core count) are not comparable as they
are; the report (report/results.py) judges runs by their times as measured when every run comes from one kind of
machine, and otherwise by their times normalised by the calibration (see :func:`time_basis`), and says which.

SLOWDOWN_ENV (a factor, for tests and demonstrations): a worker whose environment sets it reports every time it
measures, the calibration included, multiplied by it -- a worker that many times slower, consistently, and a kind of
machine of its own.
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
TIME_FIELDS = ("build_time", "call_time", "wall_time", "cpu_time", "light_time", "shading_time", "camera_time",
               "tile_time", "trace_time", "camera_trace_time")
# The calibration render: a ground lit by one rectangle, CALIBRATION_SIDE^2 pixels, one thread, the best of
# CALIBRATION_REPEATS (the least disturbed by other load).
CALIBRATION_SIDE = 64
CALIBRATION_SAMPLES = 16
CALIBRATION_REPEATS = 7
# What a record's "machine" says (machine_info), also runs.csv's columns.
MACHINE_FIELDS = ("host", "cpu_model", "cores", "calibration")


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
    info = dict(zip(MACHINE_FIELDS, values))
    if slowdown() != 1:
        info["slowdown"] = slowdown()  # a kind of machine of its own (machine_kind)
    return info


def machine_kind(machine: Dict) -> tuple:
    """What makes two workers one kind of machine: the CPU model, the core count and, for a worker made slower on
    purpose, its slowdown."""
    return machine.get("cpu_model"), machine.get("cores"), machine.get("slowdown", 1.0)


@dataclass(frozen=True)
class TimeBasis:
    """How runs' times are compared: as measured (`calibrations` None), or each x reference_calibration / its kind of
    machine's calibration (the median of its workers'), i.e. in seconds of the reference kind of machine."""
    description: str
    calibrations: Optional[Dict[tuple, float]] = None  # machine_kind -> calibration (s)
    reference_calibration: Optional[float] = None

    @property
    def normalised(self) -> bool:
        return self.calibrations is not None

    def time(self, record: Dict, measured: float) -> float:
        if not self.normalised:
            return measured
        return measured * self.reference_calibration / self.calibrations[machine_kind(record["machine"])]


def time_basis(records: Sequence[Dict]) -> TimeBasis:
    """Times as measured when every record was measured on one kind of machine (machine_kind), or the records do not
    say where (measured before they did); otherwise times normalised by the calibration to the kind of machine that
    measured the most runs. Within a kind the median calibration of its workers stands for all of them: one worker's
    calibration moves by +-30% with the load on its machine, which the kind's own times do not share."""
    machines = [r["machine"] for r in records if r.get("machine") and r["machine"].get("calibration")]
    if len(machines) < len(records) or not machines:
        return TimeBasis("times as measured (not every run says on which machine)" if machines else
                         "times as measured (the runs do not say on which machine)")
    by_kind: Dict[tuple, List[float]] = {}
    for m in machines:
        by_kind.setdefault(machine_kind(m), []).append(m["calibration"])
    hosts = len({m.get("host") for m in machines})
    if len(by_kind) == 1:
        (cpu, cores, _), = by_kind
        return TimeBasis(f"times as measured, every run on one kind of machine ({cpu}, {cores} cores; {hosts} "
                         f"host{'s' if hosts > 1 else ''})")
    calibrations = {kind: float(np.median(values)) for kind, values in by_kind.items()}
    reference_kind = max(by_kind, key=lambda kind: len(by_kind[kind]))
    kinds = "; ".join(f"{cpu}, {cores} cores" + (f", slowed down {slow:g}x" if slow != 1 else "") +
                      f": {len(by_kind[(cpu, cores, slow)])} runs, calibration {calibrations[(cpu, cores, slow)]:.4g} s"
                      for cpu, cores, slow in sorted(by_kind, key=str))
    return TimeBasis(f"times normalised by the calibration (a fixed {CALIBRATION_SIDE}x{CALIBRATION_SIDE}, "
                     f"{CALIBRATION_SAMPLES}-spp render) to the kind of machine that measured the most runs: the runs "
                     f"come from {len(by_kind)} kinds of machine ({kinds})",
                     calibrations, calibrations[reference_kind])


def judged_times(records: Sequence[Dict], threads: int) -> TimeBasis:
    """Sets each record's "time" (metrics.time_of on the study's time basis); returns the basis."""
    from .metrics import time_of
    basis = time_basis(records)
    for r in records:
        r["time"] = basis.time(r, time_of(r, threads))
    return basis
