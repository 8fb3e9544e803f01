"""Append-only, crash-safe storage of study results.

Layout under the study's output directory:

* ``runs/<job key>.json`` -- one file per finished run (its job, measurements and errors);
* ``failed/<job key>.json`` -- the error of a run that raised (retried on the next start);
* ``images/<name>.npy`` -- images kept for the report (reference, equal-time renders).
* ``damaged/`` -- files found damaged, set aside (see below).

Every file is written to a temporary file in the same directory, flushed to disk and renamed over its
final name (``os.replace`` is atomic on POSIX), so an interrupted study never leaves a half-written file
under a final name: a run is either recorded whole or not at all, and the next start redoes only the
runs that have no record.

A file that is damaged all the same (a truncated copy, a full disk, a hand edit) is never trusted: reading it
says so on stderr and moves it to ``damaged/`` (so it is said once), and whatever needed it is recomputed --
a run record or a run's image redoes the run, reference.npy or reference.json recombines the reference,
state.json is rewritten.
"""
from __future__ import annotations

import json
import os
import sys
from typing import Dict, Iterator, Optional

import numpy as np

from ..fileio import atomic_write

RUNS = "runs"
FAILED = "failed"
IMAGES = "images"
DAMAGED = "damaged"


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

    def set_aside(self, path: str, reason) -> None:
        """Report a damaged file and move it to damaged/ (its next write recomputes it)."""
        target = os.path.join(self.root, DAMAGED, os.path.relpath(path, self.root).replace(os.sep, "__"))
        try:
            os.makedirs(os.path.dirname(target), exist_ok=True)
            os.replace(path, target)
            where = f"moved to {target}"
        except OSError as e:
            where = f"could not be moved aside ({e})"
        sys.stderr.write(f"damaged file {path} ({reason}): {where}; it will be recomputed\n")
        sys.stderr.flush()

    def read_json(self, name: str, required=()) -> Optional[Dict]:
        """The JSON object in `name` (relative to the root) with the `required` keys; None when there is no such
        file, or when it is damaged (then set aside)."""
        path = os.path.join(self.root, name)
        try:
            with open(path, "r", encoding="utf-8") as f:
                obj = json.load(f)
        except FileNotFoundError:
            return None
        except (OSError, ValueError) as e:
            self.set_aside(path, f"unreadable: {e}")
            return None
        missing = [k for k in required if k not in obj] if isinstance(obj, dict) else None
        if missing is None or missing:
            self.set_aside(path, "not a JSON object" if missing is None else f"no {', '.join(missing)}")
            return None
        return obj

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
        """The run's record; None when there is none, or a damaged one (set aside: the run is redone)."""
        record = self.read_json(os.path.join(RUNS, f"{key}.json"), required=("key", "fingerprint", "job"))
        if record is not None and not isinstance(record["job"], dict):
            self.set_aside(self.run_path(key), "its job is not a JSON object")
            return None
        return record

    def is_done(self, key: str, fingerprint: str) -> bool:
        """Whether the run has a record of this fingerprint, and its image (if it keeps one) is whole: a run whose
        image is damaged is redone."""
        record = self.read_run(key)
        if record is None or record.get("fingerprint") != fingerprint:
            return False
        return "image" not in record or self.image_is_whole(record["image"])

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
                failure = self.read_json(os.path.join(FAILED, name), required=("key", "error"))
                if failure is not None:
                    yield failure

    # -- images -------------------------------------------------------------------------------------
    def image_path(self, name: str) -> str:
        return os.path.join(self.root, IMAGES, f"{name}.npy")

    def save_image(self, name: str, image: np.ndarray) -> str:
        path = self.image_path(name)
        atomic_save_npy(path, image)
        return path

    def load_image(self, name: str) -> Optional[np.ndarray]:
        """The image; None when there is none, or a damaged one (set aside)."""
        return self._open_image(name, mmap_mode=None)

    def image_is_whole(self, name: str) -> bool:
        """Whether the image file is there and whole (its header and all its data), without reading the data."""
        return self._open_image(name, mmap_mode="r") is not None

    def _open_image(self, name: str, mmap_mode: Optional[str]) -> Optional[np.ndarray]:
        path = self.image_path(name)
        try:
            image = np.load(path, allow_pickle=False, mmap_mode=mmap_mode)
        except FileNotFoundError:
            return None
        except (OSError, ValueError, EOFError) as e:  # truncated, not an .npy, an object array
            self.set_aside(path, f"unreadable: {e}")
            return None
        if image.ndim != 3 or image.shape[2] not in (3, 4) or image.dtype != np.float32:
            del image
            self.set_aside(path, "not a float32 [H, W, 3|4] image")
            return None
        return image
