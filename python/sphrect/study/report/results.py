"""The stored results of a study as the report reads them (records grouped into curves, the equal-time images)
and as it writes them out again (runs.csv, runs.json)."""
from __future__ import annotations

import csv
import io
import math
import os
from collections import defaultdict
from dataclasses import dataclass
from typing import Dict, List, NamedTuple, Optional, Tuple

import numpy as np

from ..jobs import CYCLES, EQUAL_TIME, LADDER, SPHRECT, CurveKey, StudyConfig, curve_key
from ..machines import MACHINE_FIELDS, judged_times
from ..reference import load_reference_info
from ..store import ResultStore, atomic_write_bytes, atomic_write_json

# jobs.CurveKey (technique, mis, pattern, light selection, ellipse technique, medium sampling); Cycles' CYCLES_CURVE
Curves = Dict[CurveKey, List[Dict]]

CSV_COLUMNS = ("key", "kind", "engine", "technique", "mis", "pattern", "light_selection", "ellipse_technique",
               "medium_sampling", "samples", "light_samples",
               "seed", "threads", "time_budget", "samples_done", "time", "cpu_time", "wall_time", "call_time",
               "build_time", "light_time", "shading_time", "camera_time", "tile_time", "trace_time",
               "camera_trace_time", "rays", "camera_rays", "surface_hits", "rmse", "relmse", "finite",
               "dropped_samples", *MACHINE_FIELDS)


@dataclass
class StudyResults:
    config: Dict            # config.json: scene, resolution, executor and the study's settings
    state: Dict             # state.json: the current runs' fingerprint, the equal-time budget
    store: ResultStore
    reference: Dict         # reference.json: the reference image and its own error
    settings: StudyConfig
    ladder: List[Dict]      # run records; each has "time", the time it is judged by (machines.judged_times)
    equal_time: List[Dict]
    failures: List[Dict]
    time_basis: str = ""    # how times are compared (machines.time_basis): as measured, or normalised

    @property
    def reference_rmse(self) -> float:
        return self.reference["estimated_rmse"]


def load_study(out_dir: str) -> StudyResults:
    """The study's stored results; ValueError when a file the report needs is missing or damaged (running the study
    again recomputes it)."""
    store = ResultStore(out_dir)
    needed = {"config.json": ("study",), "state.json": ("run_fingerprint",)}
    config, state = (store.read_json(name, required) for name, required in needed.items())
    reference = load_reference_info(store)
    for name, content in zip(list(needed) + ["reference.json"], (config, state, reference)):
        if content is None:
            raise ValueError(f"{os.path.join(out_dir, name)} is missing or damaged: run the study (not "
                             f"--report-only) to recompute it")
    records = list(store.runs(state["run_fingerprint"]))
    settings = StudyConfig.from_dict(config["study"])
    basis = judged_times(records, settings.threads)
    return StudyResults(config=config, state=state, store=store, reference=reference,
                        settings=settings, ladder=[r for r in records if r["job"]["kind"] == LADDER],
                        equal_time=[r for r in records if r["job"]["kind"] == EQUAL_TIME],
                        failures=list(store.failures()), time_basis=basis.description)


def study_warnings(results: StudyResults) -> List[Tuple[str, str]]:
    """Every warning the study gave, once each, with where: (message, "the exporter" | "the scene check" and/or "N
    runs"), the exporter's and the scene check's first, then the runs' (reference chunks included), most runs
    first."""
    sources: Dict[str, List[str]] = {}
    for message in (results.config.get("exporter_warnings") or "").splitlines():
        sources.setdefault(message, []).append("the exporter")
    for message in results.config.get("scene_warnings") or ():
        sources.setdefault(message, []).append("the scene check")
    chunks = [results.store.read_run(key) for key in results.reference.get("chunk_keys", ())]
    runs = defaultdict(int)
    for record in [r for r in chunks if r] + results.ladder + results.equal_time:
        for message in record.get("warnings") or ():
            runs[message] += 1
    for message, count in sorted(runs.items(), key=lambda item: -item[1]):
        sources.setdefault(message, []).append(f"{count} run{'s' if count > 1 else ''}")
    return [(message, " and ".join(where)) for message, where in sources.items()]


def curves(records: List[Dict]) -> Curves:
    """jobs.CurveKey -> records sorted by samples (Cycles: CYCLES_CURVE)."""
    out = defaultdict(list)
    for r in records:
        out[curve_key(r["job"])].append(r)
    for k in out:
        out[k].sort(key=lambda r: r["job"]["samples"])
    return dict(out)


def smallest_rmse(records: List[Dict]) -> float:
    """The smallest finite RMSE among the runs (NaN without one): what the reference's error is judged against."""
    rmse = [r["rmse"] for r in records if r.get("rmse") and math.isfinite(r["rmse"])]
    return min(rmse) if rmse else float("nan")


def write_runs(out_dir: str, results: StudyResults) -> None:
    """runs.csv (one row per run, CSV_COLUMNS) and runs.json (the reference and every record)."""
    records = results.ladder + results.equal_time
    buffer = io.StringIO()
    writer = csv.writer(buffer)
    writer.writerow(CSV_COLUMNS)
    for r in sorted(records, key=lambda r: r["key"]):
        key = curve_key(r["job"])  # the axes added later also of runs stored before they were kept
        row = {**r["job"], **{k: v for k, v in r.items() if k != "job"}, **(r.get("machine") or {}),
               "light_selection": key.light_selection, "ellipse_technique": key.ellipse_technique,
               "medium_sampling": key.medium_sampling}
        writer.writerow(["" if row.get(c) is None else row.get(c) for c in CSV_COLUMNS])
    atomic_write_bytes(os.path.join(out_dir, "runs.csv"), buffer.getvalue().encode("utf-8"))
    atomic_write_json(os.path.join(out_dir, "runs.json"), {"reference": results.reference, "runs": records})


REFERENCE_COLUMN = "reference"


class GridRow(NamedTuple):
    """A row of the equal-time grid."""
    mis: Optional[str]
    light_selection: Optional[str]
    ellipse_technique: Optional[str] = None
    medium_sampling: Optional[str] = None


def grid_row(record: Dict) -> GridRow:
    key = curve_key(record["job"])
    return GridRow(key.mis, key.light_selection, key.ellipse_technique, key.medium_sampling)


@dataclass
class EqualTimeGrid:
    """The equal-time renders laid out as the report shows them: a row per MIS mode, light selection, ellipse
    technique and medium sampling, a column per technique, then Cycles (one render, whatever the row) and the
    reference."""
    reference: np.ndarray
    rows: List[GridRow]                     # [GridRow(None, None)] when no render of ours was measured
    columns: List[str]                      # techniques, CYCLES, REFERENCE_COLUMN
    cells: Dict[Tuple[GridRow, str], Dict]  # (row, column) -> the record shown there
    images: Dict[str, np.ndarray]           # record key -> its image, for every equal-time render stored


def equal_time_grid(results: StudyResults) -> EqualTimeGrid:
    store, records, cfg = results.store, results.equal_time, results.settings
    ours = [r for r in records if r["job"]["engine"] == SPHRECT]
    rows = [GridRow(m, s, e, v) for m in cfg.grid_mis for s, e, v in cfg.variants
            if any(grid_row(r) == (m, s, e, v) for r in ours)] or [GridRow(None, None)]
    cycles = [r for r in records if r["job"]["engine"] == CYCLES]
    columns = list(cfg.techniques) + ([CYCLES] if cycles else []) + [REFERENCE_COLUMN]
    images = {}
    for r in records:
        image = store.load_image(r["image"])
        if image is not None:
            images[r["key"]] = image
    cells = {}
    for row in rows:
        for name in columns[:-1]:
            # The first record of the cell is shown; Cycles' render is the same in every row.
            match = cycles if name == CYCLES else [r for r in ours
                                                   if r["job"]["technique"] == name and grid_row(r) == row]
            if match and match[0]["key"] in images:
                cells[(row, name)] = match[0]
    return EqualTimeGrid(store.load_image(results.reference["image"]), rows, columns, cells, images)
