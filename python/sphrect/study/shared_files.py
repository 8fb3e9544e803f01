"""The files a study's jobs read -- the scene, the reference image, the .blend -- on workers that may not see the
study's folder (another machine of a Dask cluster): the executor sends their content, and a worker reads its own
copy wherever the study's path is named (local_path). On the study's own machine nothing is copied."""
from __future__ import annotations

import hashlib
import os
from typing import Dict, Iterable

from .store import atomic_write_bytes

_copies: Dict[str, str] = {}  # the study's path -> this worker's copy


def local_path(path: str) -> str:
    """This worker's copy of the study's file `path`, or `path` itself when none was sent."""
    return _copies.get(os.path.abspath(path), path)


def read_files(paths: Iterable[str]) -> Dict[str, bytes]:
    """{absolute path: content} of the files (None and repeats skipped)."""
    out = {}
    for path in paths:
        if path and os.path.abspath(path) not in out:
            with open(path, "rb") as f:
                out[os.path.abspath(path)] = f.read()
    return out


def use_copies(files: Dict[str, bytes], directory: str) -> None:
    """On a worker: keep a copy of each file in `directory` (named by its content, written once) and read it in place
    of the study's path from now on."""
    os.makedirs(directory, exist_ok=True)
    for path, content in files.items():
        name = f"{hashlib.sha256(content).hexdigest()[:16]}-{os.path.basename(path)}"
        copy = os.path.join(directory, name)
        if not os.path.exists(copy):
            atomic_write_bytes(copy, content)
        _copies[path] = copy
