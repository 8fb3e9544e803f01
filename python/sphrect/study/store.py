"""Append-only, crash-safe storage of study results.

Layout under the study's output directory:

* ``runs/<job key>.json`` -- one file per finished run (its job, measurements and errors);
* ``failed/<job key>.json`` -- the error of a run that raised (retried on the next start);
* ``images/<name>.npy`` -- images kept for the report (reference, equal-time renders).

Every file is written to a temporary file in the same directory, flushed to disk and renamed over its
final name (``os.replace`` is atomic on POSIX), so an interrupted study never leaves a half-written file
under a final name: a run is either recorded whole or not at all, and the next start redoes only the
runs that have no record.
"""
from __future__ import annotations

import json
import os
import warnings
from typing import Dict, Iterator, Optional

import numpy as np

from ..fileio import atomic_write

RUNS = "runs"
FAILED = "failed"
IMAGES = "images"


def atomic_write_bytes(path: str, data: bytes) -> None:
    atomic_write(path, lambda f: f.write(data))


def atomic_write_json(path: str, obj) -> None:
    atomic_write_bytes(path, (json.dumps(obj, indent=1, sort_keys=True, allow_nan=True) + "\n").encode("utf-8"))


def atomic_save_npy(path: str, array: np.ndarray) -> None:
    atomic_write(path, lambda f: np.save(f, np.ascontiguousarray(array)))


class ResultStore:
    """Results of one study directory. A record is a JSON object with at least ``key`` and ``fingerprint``:
    a record counts as done only if its fingerprint matches the current study's (same scene, reference
    and settings), so changing the scene or the reference redoes the runs instead of mixing results."""

    def __init__(self, root: str):
        self.root = os.path.abspath(root)
        for sub in (RUNS, FAILED, IMAGES):
            os.makedirs(os.path.join(self.root, sub), exist_ok=True)

    def remove_stale_temporaries(self) -> None:
        """Delete the temporaries of writes that never finished (a worker killed mid-write). Call only
        while no job is running: a live write's temporary looks the same."""
        for directory, _, names in os.walk(self.root):
            for name in names:
                if name.startswith(".") and name.endswith(".tmp"):
                    os.unlink(os.path.join(directory, name))

    # -- runs ---------------------------------------------------------------------------------------
    def run_path(self, key: str) -> str:
        return os.path.join(self.root, RUNS, f"{key}.json")

    def write_run(self, record: Dict) -> None:
        atomic_write_json(self.run_path(record["key"]), record)
        failed = os.path.join(self.root, FAILED, f"{record['key']}.json")
        if os.path.exists(failed):
            os.unlink(failed)

    def write_failure(self, key: str, error: str) -> None:
        atomic_write_json(os.path.join(self.root, FAILED, f"{key}.json"), {"key": key, "error": error})

    def read_run(self, key: str) -> Optional[Dict]:
        try:
            with open(self.run_path(key), "r", encoding="utf-8") as f:
                return json.load(f)
        except FileNotFoundError:
            return None
        except (OSError, ValueError) as e:  # cannot happen with atomic writes, but never trust a disk
            warnings.warn(f"ignoring unreadable result {self.run_path(key)}: {e}")
            return None

    def is_done(self, key: str, fingerprint: str) -> bool:
        record = self.read_run(key)
        return record is not None and record.get("fingerprint") == fingerprint

    def runs(self, fingerprint: Optional[str] = None) -> Iterator[Dict]:
        """Every readable record (of the given fingerprint), in key order."""
        directory = os.path.join(self.root, RUNS)
        for name in sorted(os.listdir(directory)):
            if name.startswith(".") or not name.endswith(".json"):
                continue  # temporaries of writes in progress or interrupted
            record = self.read_run(name[:-5])
            if record is not None and (fingerprint is None or record.get("fingerprint") == fingerprint):
                yield record

    def failures(self) -> Iterator[Dict]:
        directory = os.path.join(self.root, FAILED)
        for name in sorted(os.listdir(directory)):
            if name.endswith(".json") and not name.startswith("."):
                try:
                    with open(os.path.join(directory, name), encoding="utf-8") as f:
                        yield json.load(f)
                except (OSError, ValueError):
                    continue

    # -- images -------------------------------------------------------------------------------------
    def image_path(self, name: str) -> str:
        return os.path.join(self.root, IMAGES, f"{name}.npy")

    def save_image(self, name: str, image: np.ndarray) -> str:
        path = self.image_path(name)
        atomic_save_npy(path, image)
        return path

    def load_image(self, name: str) -> Optional[np.ndarray]:
        try:
            return np.load(self.image_path(name), allow_pickle=False)
        except FileNotFoundError:
            return None
